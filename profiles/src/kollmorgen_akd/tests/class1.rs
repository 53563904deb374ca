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

/// Velocity (units/s) in a response.
fn velocity(r: &[u8]) -> i32 {
    dint(r, 12)
}

/// An enabled drive in velocity mode jogging at 2 rev/s (131072 units/s) behind an owner
/// at a 10 ms RPI, DRV.DECSTOP 10 rev/s² (a 200 ms controlled stop).
fn jogging_owner() -> (Scanner, Opened, [u8; 64]) {
    let mut s = Scanner::new();
    let o = s.open(10_000, 0x4800, 0x01);
    assert_eq!(o.general, 0);
    for (class, instance, attr, data) in [
        (0x25u8, 1u16, 3u8, vec![1u8]),
        (0x0F, id::DRV_DECSTOP, 1, 655_360i64.to_le_bytes().to_vec()),
    ] {
        let (status, ..) = s
            .scanner
            .unconnected(&request(0x10, class, instance, Some(attr), &data))
            .unwrap();
        assert_eq!(status, 0);
    }
    let jog = |c| respond(motion(c, 0x27, 0, 131_072, 6_553_600, 6_553_600), 0x23);
    let mut last = Vec::new();
    for c in [jog(EN | DIR), jog(EN | DIR | LOAD)] {
        for _ in 0..5 {
            s.scanner.send_io(o.o_t_id, Some(true), &c).unwrap();
            s.scanner.advance(10_000, |_, d| last = d.to_vec());
        }
    }
    assert_eq!(velocity(&last), 131_072, "jogging");
    (s, o, jog(EN | DIR | LOAD))
}

#[test]
fn program_mode_makes_a_controlled_stop_and_keeps_the_drive_enabled() {
    let (mut s, o, c) = jogging_owner();
    // Idle from now on: the responses of the next RPIs.
    let mut seen = Vec::new();
    for _ in 0..30 {
        s.scanner.send_io(o.o_t_id, Some(false), &c).unwrap();
        s.scanner.advance(10_000, |_, d| seen.push(d.to_vec()));
    }
    let begun = seen.iter().position(|r| velocity(r) < 131_072).unwrap();
    assert!(begun < 2, "the stop began after {} RPIs", begun + 1);
    // 2 rev/s at 10 rev/s²: 200 ms, 20 RPIs.
    let rest = seen.iter().position(|r| velocity(r) == 0).unwrap();
    assert!(rest <= 21, "at rest after {} RPIs", rest + 1);
    let r = seen.last().unwrap();
    assert_eq!(
        r[0] & (status1::ENABLED | status1::IN_MOTION),
        status1::ENABLED
    );
    // Back to Run with the same command: no edge, no motion; a new Load/Start edge jogs.
    let mut last = Vec::new();
    s.scanner.send_io(o.o_t_id, Some(true), &c).unwrap();
    s.scanner.advance(50_000, |_, d| last = d.to_vec());
    assert_eq!(velocity(&last), 0);
    for control in [EN | DIR, EN | DIR | LOAD] {
        let mut c = c;
        c[0] = control;
        s.scanner.send_io(o.o_t_id, Some(true), &c).unwrap();
        s.scanner.advance(10_000, |_, d| last = d.to_vec());
    }
    s.scanner.advance(40_000, |_, d| last = d.to_vec());
    assert!(velocity(&last) > 0, "jogging again");
}

#[test]
fn a_connection_timeout_makes_a_controlled_stop_then_disables() {
    let (mut s, _o, _c) = jogging_owner();
    // No more O->T data: the watchdog (x8, 80 ms) closes the connection.
    let mut closed = None;
    let mut begun = None;
    let mut rest = None;
    let mut enabled_while_stopping = true;
    for ms in 0..500u32 {
        s.scanner.advance(1_000, |_, _| {});
        let d = &s.scanner.adapter().device().state().drive;
        if closed.is_none() && s.scanner.adapter().connections().is_empty() {
            closed = Some(ms);
        }
        if begun.is_none() && d.velocity() < 131_072 * (COUNTS_PER_REV / 65_536) {
            begun = Some(ms);
        }
        if rest.is_none() && d.velocity() != 0 && !d.enabled() {
            enabled_while_stopping = false;
        }
        if rest.is_none() && d.velocity() == 0 {
            rest = Some(ms);
            assert!(!d.enabled() || !d.in_motion());
        }
    }
    let (closed, begun, rest) = (closed.unwrap(), begun.unwrap(), rest.unwrap());
    assert!((50..=100).contains(&closed), "closed after {closed} ms");
    assert!(
        begun >= closed && begun - closed <= 20,
        "stop began {begun}, closed {closed}"
    );
    // A ramp at DRV.DECSTOP (2 rev/s at 10 rev/s²: 200 ms), not a disable that lets the
    // motor coast: the drive stays enabled until it is at rest.
    assert!(
        (190..=202).contains(&(rest - begun)),
        "at rest {} ms after the stop began",
        rest - begun
    );
    assert!(enabled_while_stopping, "disabled before standstill");
    let d = &s.scanner.adapter().device().state().drive;
    assert!(!d.enabled(), "disabled at rest");
}
