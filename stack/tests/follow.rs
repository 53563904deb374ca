//! Cyclic T->O production that follows the originator's O->T data (`io/follow.rs`), in
//! virtual time: a scanner whose clock drifts and jitters against the adapter's, one whose
//! data stops, and one whose O->T RPI differs from its T->O RPI.

mod common;

use common::*;
use enip_stack::wire::forward_open::ForwardOpenReplyRepr;
use enip_stack::wire::io_datagram::Packet;
use enip_stack::Instant;

const RPI: u64 = 10_000;
/// The slack at 10 ms: RPI/8 (at most 2 ms).
const SLACK: u64 = 1_250;

/// Opens one exclusive owner at `o_t_rpi` / `t_o_rpi`; its O->T connection ID.
fn open(h: &mut Harness, o_t_rpi: u32, t_o_rpi: u32) -> u32 {
    let path = io_path(None, 110, 100, None);
    let mut f = fo(1, &path, t_o_rpi);
    f.o_t_rpi = o_t_rpi;
    let (g, _, data) = status(&h.forward_open(&f));
    assert_eq!(g, 0);
    ForwardOpenReplyRepr::parse(&data)
        .unwrap()
        .o_t_connection_id
}

/// Runs the adapter the way a runtime does: it wakes at its deadline or when an O->T datagram
/// arrives (at the instants `arrivals`, until `end`), and then sends whatever is due. Returns
/// each production as (instant, whether an O->T datagram woke that wake-up).
fn run(h: &mut Harness, o_t: u32, arrivals: &[u64], end: u64) -> Vec<(u64, bool)> {
    let mut produced = Vec::new();
    let mut out = [0u8; 128];
    let mut next = arrivals.iter().copied().peekable();
    let mut k = 0u32;
    for _ in 0..1_000_000 {
        let deadline = h
            .adapter
            .next_deadline()
            .map_or(u64::MAX, |d| d.as_micros());
        let arrival = next.peek().copied().unwrap_or(u64::MAX);
        let now = deadline.min(arrival);
        if now >= end {
            break;
        }
        let woken_by_data = now == arrival;
        if woken_by_data {
            next.next();
            k += 1;
            let mut buf = [0u8; 64];
            let n = enip_stack::originator::io_datagram(
                &mut buf,
                o_t,
                k,
                k as u16,
                Some(true),
                &[0; 32],
            )
            .unwrap();
            let from = std::net::SocketAddrV4::new(SCANNER_IP, 2222);
            let _ = h.adapter.io_receive(from, &buf[..n], Instant(now));
        }
        while let Some((_, len)) = h.adapter.poll_io(Instant(now), &mut out) {
            Packet::new_checked(&out[..len]).unwrap();
            produced.push((now, woken_by_data));
        }
    }
    produced
}

/// A scanner clock 100 ppm fast (or slow) with +-40 us of jitter (a fixed pseudo-random
/// sequence), starting `phase` after the Forward_Open: its O->T send instants up to `end`.
fn drifting_scanner(phase: u64, fast: bool, end: u64) -> Vec<u64> {
    let mut x = 0x2545_F491_4F6C_DD1Du64;
    (0..)
        .map(|k: u64| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let drift = k * RPI / 10_000;
            let ideal = phase + k * RPI;
            let ideal = if fast { ideal - drift } else { ideal + drift };
            ideal + 40 + x % 81 - 80
        })
        .take_while(|&t| t < end)
        .collect()
}

#[test]
fn production_follows_a_drifting_jittering_scanner_in_one_wake_up() {
    const END: u64 = 60_000_000;
    for (phase, fast) in [1_000, 3_700, 5_000, 6_300, 9_900]
        .into_iter()
        .flat_map(|p| [(p, true), (p, false)])
    {
        let mut h = Harness::new();
        let o_t = open(&mut h, RPI as u32, RPI as u32);
        let arrivals = drifting_scanner(phase, fast, END);
        let produced = run(&mut h, o_t, &arrivals, END);
        // One production per RPI of the scanner's clock, 100 ppm off the adapter's.
        let expected = arrivals.len() as i64;
        assert!(
            (produced.len() as i64 - expected).abs() <= 3,
            "phase {phase}: {} productions for {expected} arrivals",
            produced.len()
        );
        // Nominal instants 15/16 to 17/16 of the RPI apart, each datagram at most the slack
        // after its own.
        for w in produced[1..].windows(2) {
            let interval = w[1].0 - w[0].0;
            assert!(
                (RPI - RPI / 16 - SLACK..=RPI + RPI / 16 + SLACK).contains(&interval),
                "phase {phase}: interval {interval} at {}",
                w[1].0
            );
        }
        // Found within 20 RPIs (eight corrections at most, after the adapter's grid); from
        // then on the T->O datagram goes in the wake-up of the O->T datagram. A scanner
        // drifting early is followed at once; one drifting late leaves the slack now and
        // then: two late arrivals in a row (two wake-ups of their own, more where the jitter
        // straddles the slack's end) and the grid moves RPI/16 later. Under 1 % of them.
        let apart = produced[20..].iter().filter(|p| !p.1).count();
        let most = if fast { 0 } else { produced.len() / 100 };
        assert!(apart <= most, "phase {phase}, fast {fast}: {apart} apart");
    }
}

#[test]
fn when_the_data_stops_the_grid_holds_and_goes_out_within_the_slack() {
    let mut h = Harness::new();
    let o_t = open(&mut h, RPI as u32, RPI as u32);
    // Data for one second, then none (the watchdog, x4, closes the connection 40 ms on).
    let arrivals: Vec<u64> = (0..100).map(|k| 4_321 + k * RPI).collect();
    let produced = run(&mut h, o_t, &arrivals, 2_000_000);
    let last = *arrivals.last().unwrap();
    let after: Vec<u64> = produced
        .iter()
        .filter(|p| p.0 > last)
        .map(|p| p.0)
        .collect();
    assert!(!after.is_empty() && after.len() <= 4, "{after:?}");
    // Each one slack after a nominal instant of the grid the arrivals were in step with:
    // within the slack before them.
    for (i, at) in after.iter().enumerate() {
        let lag = (last + RPI - (at - SLACK) % RPI) % RPI;
        assert!(lag <= SLACK, "{i}: {at}, {lag}");
    }
    assert!(after.windows(2).all(|w| w[1] - w[0] == RPI), "{after:?}");
}

#[test]
fn another_o_t_rpi_is_not_followed() {
    let mut h = Harness::new();
    let o_t = open(&mut h, 2 * RPI as u32, RPI as u32);
    let arrivals: Vec<u64> = (0..100).map(|k| 4_321 + k * 2 * RPI).collect();
    let produced = run(&mut h, o_t, &arrivals, 2_000_000);
    // On the adapter's grid from the second production on, exactly; never with the data.
    let grid = u64::from(h.adapter.connections().grid_phase(RPI as u32));
    assert!(produced[1..].iter().all(|p| p.0 % RPI == grid && !p.1));
    assert!(produced[1..].windows(2).all(|w| w[1].0 - w[0].0 == RPI));
}
