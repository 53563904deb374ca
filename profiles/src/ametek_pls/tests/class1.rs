//! Class 1 through the stack's `Adapter` entry points in virtual time: a scanner's session,
//! the Forward_Open of §3.1 (150/100/1 at 10 ms), O->T data with the run/idle header, T->O
//! data read back; Acknowledge edges, Idle and the watchdog timeout as the device sees them.

extern crate std;

use std::vec::Vec;

use enip_stack::virtual_scanner::VirtualScanner;
use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use enip_stack::wire::forward_open::{ForwardOpenRepr, NetworkParams, Triad};
use enip_stack::wire::Writer;
use enip_stack::Instant;

use super::super::leds::NetworkStatus;
use super::super::AmetekPls;
use super::{execute, le, pls_object, programmed, request, words};

const RPI_US: u32 = 10_000;

/// The programmed PLS behind a virtual scanner, with an exclusive owner.
struct Scanner {
    scanner: VirtualScanner<AmetekPls>,
    o_t: u32,
    /// The O->T data repeated every RPI, as a scanner does (`None`: the scanner is gone).
    cyclic: Option<(bool, [u16; 7])>,
}

impl Scanner {
    /// Opens 150/100 with configuration 1; the Forward_Open's general status.
    fn open(pls: AmetekPls) -> (Self, u8) {
        let mut path = [0u8; 32];
        let mut w = Writer::new(&mut path);
        for seg in [
            SegmentRepr::Logical(LogicalType::Class, 4),
            SegmentRepr::Logical(LogicalType::Instance, 1),
            SegmentRepr::Logical(LogicalType::ConnectionPoint, 150),
            SegmentRepr::Logical(LogicalType::ConnectionPoint, 100),
        ] {
            seg.emit(&mut w).unwrap();
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
                originator_serial: 0xC0FFEE,
            },
            timeout_multiplier: 0,
            o_t_rpi: RPI_US,
            o_t_params: NetworkParams::from_u16(0x4800 | (2 + 4 + 14)),
            t_o_rpi: RPI_US,
            t_o_params: NetworkParams::from_u16(0x4800 | (2 + 34)),
            transport: 0x01,
            path: &path[..n],
        };
        let mut scanner = VirtualScanner::new(pls);
        let opened = scanner.forward_open(&fo);
        let s = Scanner {
            scanner,
            o_t: opened.o_t_id,
            cyclic: None,
        };
        (s, opened.general)
    }

    /// Sends O->T data `w` (Run or Idle) now, and then every RPI.
    fn send(&mut self, run: bool, w: [u16; 7]) {
        self.cyclic = Some((run, w));
        self.scanner.send_io(self.o_t, Some(run), &le(&w)).unwrap();
    }

    /// The current virtual time.
    fn now(&self) -> Instant {
        self.scanner.now()
    }

    /// The general status of an explicit request sent unconnected.
    fn status(&mut self, request: &[u8]) -> u8 {
        self.scanner.unconnected(request).unwrap().0
    }

    /// Advances `ms` milliseconds, running the device and producing; the last T->O data.
    fn advance(&mut self, ms: u64) -> Option<Vec<u16>> {
        let mut last = None;
        for _ in 0..ms {
            // T->O data: 34 bytes after the sequence count.
            self.scanner
                .advance(1_000, |_, data| last = Some(words(data)));
            if let Some((run, w)) = self
                .cyclic
                .filter(|_| self.now().as_micros().is_multiple_of(u64::from(RPI_US)))
            {
                self.scanner.send_io(self.o_t, Some(run), &le(&w)).unwrap();
            }
        }
        last
    }
}

#[test]
fn class1_exclusive_owner_at_10_ms() {
    let (mut s, status) = Scanner::open(programmed());
    assert_eq!(status, 0);
    s.send(true, [1, 0, 0, 0, 0, 0, 0]);
    let t_o = s.advance(25).expect("T->O data every 10 ms");
    let ns = || s.scanner.adapter().device().leds().network_status();
    assert_eq!(ns(), NetworkStatus::Connected);
    assert_eq!(t_o.len(), 17);
    assert_eq!(t_o[14..17], [0, 0, 0]);
    // An invalid Set while connected: the error is in the next T->O datagram.
    let mut bad = pls_object();
    bad[0] = 1;
    let mut pls_set = request(0x10, 0xC1, 1, Some(1), &le(&bad));
    assert_eq!(s.status(&pls_set), 0x09);
    assert_eq!(s.advance(15).unwrap()[14..17], [1, 1, 1]);
    // Acknowledge 0 -> 1 over O->T clears it.
    s.send(true, [1 | 4, 0, 0, 0, 0, 0, 0]);
    assert_eq!(s.advance(15).unwrap()[14..17], [0, 0, 0]);
    // Home 150: output 1 on.
    pls_set = request(0x10, 0xC1, 1, Some(36), &le(&[1, 150, 0, 0, 0, 0, 0, 0, 0]));
    assert_eq!(s.status(&pls_set), 0);
    let t_o = s.advance(15).unwrap();
    assert_eq!((t_o[0], t_o[10]), (150, 1));
    // While owned, an explicit Set of the output assembly is refused (0x10).
    let owned = request(0x10, 0x04, 150, Some(3), &[0; 14]);
    assert_eq!(s.status(&owned), 0x10);
    // Idle: outputs disabled.
    s.send(false, [1, 0, 0, 0, 0, 0, 0]);
    assert_eq!(s.advance(15).unwrap()[10], 0);
    s.send(true, [1, 0, 0, 0, 0, 0, 0]);
    assert_eq!(s.advance(15).unwrap()[10], 1);
    // No O->T for longer than the watchdog (4 x 10 ms): the owner is gone, outputs off.
    s.cyclic = None;
    s.advance(100);
    assert!(s.scanner.adapter_mut().connections().is_empty());
    assert_eq!(
        s.scanner.adapter_mut().device().leds().network_status(),
        NetworkStatus::TimedOut
    );
    let mut pls = s.scanner.into_device();
    let w = words(&execute(&mut pls, &request(0x0E, 0x04, 100, Some(3), &[])).1);
    assert_eq!(w[10], 0);
}
