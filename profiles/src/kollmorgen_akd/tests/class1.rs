//! The Class 1 path through the adapter: admission, sizes and the datagrams.

use super::*;
use enip_stack::virtual_scanner::{Opened, VirtualScanner};

/// The drive behind a virtual scanner.
struct Scanner {
    scanner: VirtualScanner<KollmorgenAkd>,
}

impl Scanner {
    fn new() -> Self {
        Scanner {
            scanner: VirtualScanner::new(KollmorgenAkd::new()),
        }
    }
    /// Forward_Open 101 -> 102 with config 100.
    fn open(&mut self, rpi: u32, t_o_type: u16, transport: u8) -> Opened {
        let segs = [
            SegmentRepr::Logical(LogicalType::Class, 4),
            SegmentRepr::Logical(LogicalType::Instance, 100),
            SegmentRepr::Logical(LogicalType::ConnectionPoint, 101),
            SegmentRepr::Logical(LogicalType::ConnectionPoint, 102),
        ];
        let mut path = [0u8; 32];
        let mut w = Writer::new(&mut path);
        for s in &segs {
            s.emit(&mut w).unwrap();
        }
        let n = w.len();
        let fo = ForwardOpenRepr {
            large: false,
            priority_tick: 0x0A,
            timeout_ticks: 0x0E,
            o_t_connection_id: 0,
            t_o_connection_id: 0x7000_0001,
            triad: Triad {
                connection_serial: 1,
                vendor_id: 0x1337,
                originator_serial: 7,
            },
            timeout_multiplier: 1,
            o_t_rpi: rpi,
            o_t_params: NetworkParams::from_u16(0x4800 | (2 + 4 + 64)),
            t_o_rpi: rpi,
            t_o_params: NetworkParams::from_u16(t_o_type | (2 + 64)),
            transport,
            path: &path[..n],
        };
        self.scanner.forward_open(&fo)
    }
}

#[test]
fn rpi_limits_and_triggers() {
    let mut s = Scanner::new();
    let o = s.open(5_000, 0x4800, 0x01);
    assert_eq!((o.general, o.extended), (0x01, Some(0x0112)));
    let o = s.open(10_000, 0x4800, 0x11);
    assert_eq!((o.general, o.extended), (0x01, Some(0x0103)));
    assert_eq!(
        s.open(10_000, 0x2800, 0x01).general,
        0,
        "multicast T->O at 10 ms"
    );
}

#[test]
fn exclusive_owner_at_ten_milliseconds() {
    let mut s = Scanner::new();
    let o = s.open(10_000, 0x4800, 0x01);
    assert_eq!(o.general, 0);
    let mut c = cmd(EN, 0x21, 0x20, 1000);
    let mut seen = Vec::new();
    for k in 1..=20u32 {
        if k == 10 {
            c[0] |= LOAD;
        }
        s.scanner.send_io(o.o_t_id, Some(true), &c).unwrap();
        s.scanner.advance(10_000, |_, data| {
            assert_eq!(data.len(), 64);
            seen.push(data.to_vec());
        });
    }
    assert!(seen.len() >= 19, "{} datagrams", seen.len());
    let first = &seen[1];
    assert_eq!(first[..8], [0x84, 0, 0, 0x20, 0, 0, 0, 0]);
    // The load in position mode before homing: General Fault and the error response.
    let last = seen.last().unwrap();
    assert_ne!(last[0] & status1::FAULT, 0);
    assert_eq!(last[3], 0x34);
}

#[test]
fn losing_the_owner_disables_the_drive() {
    let mut s = Scanner::new();
    let o = s.open(10_000, 0x4800, 0x01);
    assert_eq!(o.general, 0);
    s.scanner.advance(10_000, |_, _| {});
    let c = cmd(EN, 0x21, 0x20, 0);
    s.scanner.send_io(o.o_t_id, Some(true), &c).unwrap();
    assert!(s.scanner.adapter().device().state().drive.enabled());
    // Multiplier code 1: x8, so 80 ms without data closes the connection.
    s.scanner.advance(190_000, |_, _| {});
    assert!(s.scanner.adapter().connections().is_empty());
    assert!(!s.scanner.adapter().device().state().drive.enabled());
}
