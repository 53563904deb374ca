//! Class 1 I/O in virtual time: ten connections at a 1 ms RPI for 10 000 ms of simulated
//! time, exact production intervals and sequence numbers, and exact watchdog timeouts.

mod common;

use std::collections::BTreeMap;
use std::net::SocketAddrV4;

use common::*;
use enip_stack::device::{CloseReason, ConnectionEvent};
use enip_stack::io::{Accepted, Discard};
use enip_stack::wire::forward_open::{ForwardCloseRepr, ForwardOpenReplyRepr, NetworkParams};
use enip_stack::wire::io_datagram::Packet;
use enip_stack::wire::Writer;
use enip_stack::Instant;

const RPI: u64 = 1_000;
const END: u64 = 10_000_000;
const CONNECTIONS: u16 = 10;

/// Opens ten exclusive owners (outputs 110.., inputs 100..) and returns their (O->T, T->O) IDs.
fn open_ten(h: &mut Harness) -> Vec<(u32, u32)> {
    (0..CONNECTIONS)
        .map(|i| {
            let path = io_path(None, 110 + u32::from(i), 100 + u32::from(i), None);
            let (g, _, data) = status(&h.forward_open(&fo(i + 1, &path, RPI as u32)));
            assert_eq!(g, 0);
            let r = ForwardOpenReplyRepr::parse(&data).unwrap();
            (r.o_t_connection_id, r.t_o_connection_id)
        })
        .collect()
}

fn scanner() -> SocketAddrV4 {
    SocketAddrV4::new(SCANNER_IP, 2222)
}

fn send(h: &mut Harness, o_t: u32, k: u32, now: u64) -> Result<Accepted, Discard> {
    let mut buf = [0u8; 64];
    let n =
        enip_stack::originator::io_datagram(&mut buf, o_t, k, k as u16, Some(true), &[k as u8; 32])
            .unwrap();
    h.adapter.io_receive(scanner(), &buf[..n], Instant(now))
}

#[test]
fn ten_connections_at_one_millisecond_for_ten_seconds() {
    let mut h = Harness::new();
    let ids = open_ten(&mut h);
    let mut seen: BTreeMap<u32, Vec<(u64, u32, u16)>> = BTreeMap::new();
    let mut out = [0u8; 128];
    let mut next_send = RPI / 2;
    let mut k = 0u32;
    for _ in 0..1_000_000 {
        let deadline = h
            .adapter
            .next_deadline()
            .map_or(u64::MAX, |d| d.as_micros());
        let now = deadline.min(next_send);
        if now >= END {
            break;
        }
        if now == next_send {
            k += 1;
            for &(o_t, _) in &ids {
                assert_eq!(send(&mut h, o_t, k, now), Ok(Accepted::NewData));
            }
            next_send += RPI;
        }
        while let Some((to, len)) = h.adapter.poll_io(Instant(now), &mut out) {
            assert_eq!(to, scanner());
            let p = Packet::new_checked(&out[..len]).unwrap();
            let data = p.connected_data();
            assert_eq!(data.len(), 2 + 32);
            seen.entry(p.connection_id()).or_default().push((
                now,
                p.encap_sequence(),
                u16::from_le_bytes([data[0], data[1]]),
            ));
        }
    }
    assert_eq!(seen.len(), usize::from(CONNECTIONS));
    // At open, then on the adapter's grid of 1 ms from one RPI on, the same for all ten.
    let second = seen[&ids[0].1][1].0;
    assert!(
        (RPI..2 * RPI).contains(&second),
        "second production at {second}"
    );
    for &(_, t_o) in &ids {
        let packets = &seen[&t_o];
        assert_eq!(packets[0].0, 0, "first production at open");
        assert_eq!(packets[1].0, second, "{t_o:#x} on the shared grid");
        assert_eq!(packets.len(), 10_000, "{t_o:#x}");
        for (i, w) in packets.windows(2).enumerate() {
            if i > 0 {
                assert_eq!(w[1].0 - w[0].0, RPI, "interval {i} of {t_o:#x}");
            }
            assert_eq!(w[1].1, w[0].1 + 1, "encapsulation sequence {i}");
            assert_eq!(w[1].2, w[0].2.wrapping_add(1), "CIP sequence {i}");
        }
    }
    // O->T data reached the outputs, and every input went out as the device holds it.
    assert_eq!(h.adapter.device().data[&110], vec![k as u8; 32]);

    // Watchdog: the last O->T went at END - RPI/2; multiplier x4 at 1 ms -> 4 ms later exactly.
    let last = next_send - RPI;
    let expiry = last + 4 * RPI;
    let _ = h.adapter.poll_io(Instant(expiry - 1), &mut out);
    assert_eq!(h.adapter.connections().len(), usize::from(CONNECTIONS));
    while h.adapter.poll_io(Instant(expiry - 1), &mut out).is_some() {}
    assert_eq!(h.adapter.next_deadline(), Some(Instant(expiry)));
    let _ = h.adapter.poll_io(Instant(expiry), &mut out);
    assert!(h.adapter.connections().is_empty());
    assert_eq!(
        h.adapter.device().events.last(),
        Some(&ConnectionEvent::OwnershipLost(CloseReason::Timeout))
    );
    // Identity status: extended 0010 (a faulted I/O connection) until an owner opens again.
    assert_eq!(h.adapter.identity_status() & 0xF0, 0x20);
    assert!(h.adapter.connections().owner_timed_out());
    let path = io_path(None, 110, 100, None);
    assert_eq!(status(&h.forward_open(&fo(99, &path, RPI as u32))).0, 0);
    assert!(!h.adapter.connections().owner_timed_out());
    assert_eq!(h.adapter.identity_status() & 0xF0, 0x70);
}

#[test]
fn first_packet_grace_is_ten_seconds() {
    let mut h = Harness::new();
    open_ten(&mut h);
    let mut out = [0u8; 128];
    while h.adapter.poll_io(Instant(END - 1), &mut out).is_some() {}
    assert_eq!(h.adapter.connections().len(), usize::from(CONNECTIONS));
    let _ = h.adapter.poll_io(Instant(END), &mut out);
    assert!(h.adapter.connections().is_empty());
}

#[test]
fn consumption_rules() {
    let mut h = Harness::new();
    let (o_t, _) = open_ten(&mut h)[0];
    assert_eq!(send(&mut h, o_t, 5, 10), Ok(Accepted::NewData));
    assert_eq!(
        h.adapter.device().events.last(),
        Some(&ConnectionEvent::RunIdle(true))
    );
    // Older or repeated encapsulation sequence: discarded.
    assert_eq!(send(&mut h, o_t, 5, 20), Err(Discard::Stale));
    assert_eq!(send(&mut h, o_t, 4, 20), Err(Discard::Stale));
    // Newer encapsulation sequence but repeated CIP sequence count: watchdog only.
    let mut buf = [0u8; 64];
    let n =
        enip_stack::originator::io_datagram(&mut buf, o_t, 6, 5, Some(true), &[0xEE; 32]).unwrap();
    assert_eq!(
        h.adapter.io_receive(scanner(), &buf[..n], Instant(30)),
        Ok(Accepted::NoNewData)
    );
    assert_eq!(h.adapter.device().data[&110], vec![5; 32]);
    // Idle: reported, data not applied.
    let n =
        enip_stack::originator::io_datagram(&mut buf, o_t, 7, 6, Some(false), &[0xEE; 32]).unwrap();
    assert_eq!(
        h.adapter.io_receive(scanner(), &buf[..n], Instant(40)),
        Ok(Accepted::NoNewData)
    );
    assert_eq!(
        h.adapter.device().events.last(),
        Some(&ConnectionEvent::RunIdle(false))
    );
    assert_eq!(h.adapter.device().data[&110], vec![5; 32]);
    // Wrong sender, wrong size, unknown connection, garbage.
    let n = enip_stack::originator::io_datagram(&mut buf, o_t, 8, 7, Some(true), &[1; 32]).unwrap();
    assert_eq!(
        h.adapter
            .io_receive("198.18.0.9:2222".parse().unwrap(), &buf[..n], Instant(50)),
        Err(Discard::UnknownConnection)
    );
    let n = enip_stack::originator::io_datagram(&mut buf, o_t, 8, 7, Some(true), &[1; 31]).unwrap();
    assert_eq!(
        h.adapter.io_receive(scanner(), &buf[..n], Instant(50)),
        Err(Discard::WrongSize)
    );
    let n =
        enip_stack::originator::io_datagram(&mut buf, o_t ^ 1, 8, 7, Some(true), &[1; 32]).unwrap();
    assert_eq!(
        h.adapter.io_receive(scanner(), &buf[..n], Instant(50)),
        Err(Discard::UnknownConnection)
    );
    assert_eq!(
        h.adapter.io_receive(scanner(), &[1, 2, 3], Instant(50)),
        Err(Discard::Malformed)
    );
}

#[test]
fn an_idle_datagram_may_carry_its_header_alone() {
    let mut h = Harness::new();
    let (o_t, _) = open_ten(&mut h)[0];
    assert_eq!(send(&mut h, o_t, 5, 10), Ok(Accepted::NewData));
    let mut buf = [0u8; 64];
    // Idle with no data: the watchdog fed, the device told, nothing applied.
    let n = enip_stack::originator::io_datagram(&mut buf, o_t, 6, 6, Some(false), &[]).unwrap();
    assert_eq!(
        h.adapter.io_receive(scanner(), &buf[..n], Instant(20)),
        Ok(Accepted::NoNewData)
    );
    assert_eq!(
        h.adapter.device().events.last(),
        Some(&ConnectionEvent::RunIdle(false))
    );
    assert_eq!(h.adapter.device().data[&110], vec![5; 32]);
    // Run with no data is short.
    let n = enip_stack::originator::io_datagram(&mut buf, o_t, 7, 7, Some(true), &[]).unwrap();
    assert_eq!(
        h.adapter.io_receive(scanner(), &buf[..n], Instant(30)),
        Err(Discard::WrongSize)
    );
}

#[test]
fn only_the_owner_runs_or_idles_the_device() {
    let mut h = Harness::new();
    let path = io_path(None, 110, 100, None);
    let (g, _, data) = status(&h.forward_open(&fo(1, &path, RPI as u32)));
    assert_eq!(g, 0);
    let owner = ForwardOpenReplyRepr::parse(&data)
        .unwrap()
        .o_t_connection_id;
    // An input-only connection whose heartbeat has a run/idle header.
    let path = io_path(None, 152, 101, None);
    let mut f = fo(20, &path, RPI as u32);
    f.o_t_params = NetworkParams::from_u16(0x4800 | 6);
    let (g, _, data) = status(&h.forward_open(&f));
    assert_eq!(g, 0);
    let heartbeat = ForwardOpenReplyRepr::parse(&data)
        .unwrap()
        .o_t_connection_id;
    assert_eq!(send(&mut h, owner, 5, 10), Ok(Accepted::NewData));
    let events = h.adapter.device().events.len();
    let mut buf = [0u8; 64];
    for (k, run) in [(1, true), (2, false), (3, true), (4, false)] {
        let n =
            enip_stack::originator::io_datagram(&mut buf, heartbeat, k, k as u16, Some(run), &[])
                .unwrap();
        assert!(h
            .adapter
            .io_receive(scanner(), &buf[..n], Instant(20 + u64::from(k)))
            .is_ok());
    }
    // The heartbeat's header told the device nothing; the owner's data still applies.
    assert_eq!(h.adapter.device().events.len(), events);
    assert_eq!(send(&mut h, owner, 6, 30), Ok(Accepted::NewData));
    assert_eq!(h.adapter.device().data[&110], vec![6; 32]);
}

#[test]
fn application_trigger_respects_inhibit_and_counts_new_data() {
    let mut h = Harness::new();
    // Connection path with a production inhibit time of 2 ms (network segment 0x43).
    let mut path = vec![0x43, 2];
    path.extend(io_path(None, 110, 100, None));
    let mut f = fo(1, &path, 10_000);
    f.transport = 0x21; // application triggered, class 1
    let (g, _, data) = status(&h.forward_open(&f));
    assert_eq!(g, 0);
    let t_o = ForwardOpenReplyRepr::parse(&data)
        .unwrap()
        .t_o_connection_id;
    let mut out = [0u8; 128];
    let seq = |out: &[u8]| u16::from_le_bytes([out[18], out[19]]);
    let (_, _) = h.adapter.poll_io(Instant(0), &mut out).unwrap();
    assert_eq!(
        seq(&out),
        0,
        "RPI production repeats the last sequence count"
    );
    assert!(h.adapter.poll_io(Instant(100), &mut out).is_none());
    h.adapter.trigger_input(100);
    let (_, len) = h.adapter.poll_io(Instant(100), &mut out).unwrap();
    assert_eq!(
        (
            Packet::new_checked(&out[..len]).unwrap().connection_id(),
            seq(&out)
        ),
        (t_o, 1)
    );
    h.adapter.trigger_input(100);
    assert!(
        h.adapter.poll_io(Instant(1_000), &mut out).is_none(),
        "inhibited for 2 ms"
    );
    assert_eq!(h.adapter.next_deadline(), Some(Instant(2_100)));
    assert!(h.adapter.poll_io(Instant(2_100), &mut out).is_some());
    assert_eq!(seq(&out), 2);
}

#[test]
fn io_traffic_keeps_its_session_alive_and_outlives_it() {
    let mut h = Harness::new();
    let (o_t, _) = open_ten(&mut h)[0];
    // Encapsulation inactivity timeout of 1 s.
    let tcpip = [
        enip_stack::wire::epath::SegmentRepr::Logical(
            enip_stack::wire::epath::LogicalType::Class,
            0xF5,
        ),
        enip_stack::wire::epath::SegmentRepr::Logical(
            enip_stack::wire::epath::LogicalType::Instance,
            1,
        ),
        enip_stack::wire::epath::SegmentRepr::Logical(
            enip_stack::wire::epath::LogicalType::Attribute,
            13,
        ),
    ];
    assert_eq!(status(&h.request(0x10, &tcpip, &[1, 0])).0, 0);
    assert_eq!(
        h.adapter.tcp_deadline(enip_stack::SocketId(0)),
        Some(Instant(1_000_000))
    );
    for k in 1..=30u32 {
        assert_eq!(
            send(&mut h, o_t, k, u64::from(k) * 100_000),
            Ok(Accepted::NewData)
        );
    }
    // The last O->T came at 3 s: the session may idle until 4 s.
    assert_eq!(
        h.adapter.tcp_deadline(enip_stack::SocketId(0)),
        Some(Instant(4_000_000))
    );
    // The session ends; the I/O goes on and keeps no new session on that socket alive.
    h.adapter
        .tcp_close(enip_stack::SocketId(0), Instant(3_000_000));
    assert_eq!(h.adapter.connections().len(), usize::from(CONNECTIONS));
    h.adapter.tcp_accept(
        enip_stack::SocketId(0),
        SocketAddrV4::new(SCANNER_IP, 50002),
        Instant(3_500_000),
    );
    assert_eq!(send(&mut h, o_t, 31, 3_600_000), Ok(Accepted::NewData));
    assert_eq!(
        h.adapter.tcp_deadline(enip_stack::SocketId(0)),
        Some(Instant(4_500_000))
    );
}

/// The two-step production the runtime uses to build a T->O datagram straight into a
/// transmit buffer: `io_due` names the datagram and its largest length, `write_io` builds it
/// and moves the connection on; a too-short buffer changes nothing, `None` drops the
/// datagram (the sequence still advances), and a closed connection's `due` writes nothing.
#[test]
fn io_due_then_write_io_builds_in_place_and_skips_on_request() {
    let mut h = Harness::new();
    let ids = open_ten(&mut h);
    let (_, t_o) = ids[0];
    let now = Instant(0);
    let due = h
        .adapter
        .io_due(now)
        .expect("every producer is due at once");
    assert_eq!(due.to, scanner());
    assert_eq!(due.max_len, 18 + 2 + 32);
    let mut short = [0u8; 51];
    assert_eq!(h.adapter.write_io(due, now, Some(&mut short)), 0);
    assert_eq!(
        h.adapter.io_due(now),
        Some(due),
        "a short buffer consumed nothing"
    );
    let mut buf = [0u8; 52];
    assert_eq!(h.adapter.write_io(due, now, Some(&mut buf)), 52);
    let p = Packet::new_checked(&buf[..]).unwrap();
    assert_eq!(p.connection_id(), t_o);
    let first = p.encap_sequence();
    // The same `due` again: the connection already moved on to its next deadline.
    let next = h.adapter.io_due(now).unwrap();
    assert_ne!(next, due);
    // Dropping the remaining nine leaves nothing due until the grid's next point.
    let mut handled = 1;
    while let Some(d) = h.adapter.io_due(now) {
        assert_eq!(h.adapter.write_io(d, now, None), 0);
        handled += 1;
        assert!(handled <= CONNECTIONS, "a dropped datagram stays due");
    }
    assert_eq!(handled, CONNECTIONS);
    // Next due on the adapter's grid, from one RPI on.
    let later = h.adapter.next_deadline().unwrap();
    assert!((RPI..2 * RPI).contains(&later.as_micros()));
    assert_eq!(h.adapter.io_due(Instant(later.as_micros() - 1)), None);
    let again = h.adapter.io_due(later).unwrap();
    assert_eq!(h.adapter.write_io(again, later, Some(&mut buf)), 52);
    assert_eq!(
        Packet::new_checked(&buf[..]).unwrap().encap_sequence(),
        first + 1
    );
    // A connection closed between `io_due` and `write_io`: nothing written.
    let stale = h.adapter.io_due(Instant(2 * RPI)).unwrap();
    h.adapter.close_all(CloseReason::Reset);
    assert_eq!(
        h.adapter.write_io(stale, Instant(2 * RPI), Some(&mut buf)),
        0
    );
}

/// Producers of different RPIs each keep their own grid, whichever comes first, and equal
/// deadlines go in slot order; a closed producer leaves the others' grids as they were and a
/// new one in its slot starts at once, then moves onto the adapter's grid of its RPI;
/// `poll_io` with a buffer too short for the datagram changes nothing.
#[test]
fn mixed_rpis_keep_their_grids_through_a_close_and_an_open() {
    let mut h = Harness::new();
    // (serial, RPI): serial n opens into slot n - 1.
    let open = |h: &mut Harness, serial: u16, rpi: u32| {
        let path = io_path(None, 110 + u32::from(serial), 100 + u32::from(serial), None);
        let (g, _, data) = status(&h.forward_open(&fo(serial, &path, rpi)));
        assert_eq!(g, 0);
        (
            ForwardOpenReplyRepr::parse(&data)
                .unwrap()
                .t_o_connection_id,
            rpi,
        )
    };
    let mut live: Vec<(u32, u32)> = [(1, 3_000), (2, 1_000), (3, 7_000), (4, 1_000)]
        .into_iter()
        .map(|(serial, rpi)| open(&mut h, serial, rpi))
        .collect();
    let mut out = [0u8; 128];
    assert_eq!(h.adapter.poll_io(Instant(0), &mut out[..51]), None);
    assert_eq!(h.adapter.next_deadline(), Some(Instant(0)), "still due");

    // Runs the adapter to `end` at its own deadlines; every production as (time, T->O ID).
    let mut run = |h: &mut Harness, end: u64| {
        let mut produced = Vec::new();
        while let Some(at) = h.adapter.next_deadline().filter(|d| d.as_micros() < end) {
            while let Some((_, len)) = h.adapter.poll_io(at, &mut out) {
                let id = Packet::new_checked(&out[..len]).unwrap().connection_id();
                produced.push((at.as_micros(), id));
            }
        }
        produced
    };
    // Each (ID, RPI) of `live` opened at `opened`: at once, then on the adapter's grid of its
    // RPI from one RPI on; in time order and slot order on a tie, between `from` and `to`.
    let expected = |h: &Harness, live: &[(u32, u32)], opened: &[u64], from: u64, to: u64| {
        let mut e = Vec::new();
        for (slot, (&(id, rpi), &open)) in live.iter().zip(opened).enumerate() {
            let phase = u64::from(h.adapter.connections().grid_phase(rpi));
            let rpi = u64::from(rpi);
            let on_grid = phase + (open + rpi - phase).div_ceil(rpi) * rpi;
            let points = core::iter::once(open).chain((on_grid..to).step_by(rpi as usize));
            e.extend(
                points
                    .filter(|t| (from..to).contains(t))
                    .map(|t| (t, slot, id)),
            );
        }
        e.sort_unstable();
        e.into_iter().map(|(t, _, id)| (t, id)).collect::<Vec<_>>()
    };
    let want = expected(&h, &live, &[0; 4], 0, 21_000);
    assert_eq!(run(&mut h, 21_000), want);

    // The 1 ms producer in slot 1 closes at 21 ms; a 2 ms one opens into its slot.
    let fc = ForwardCloseRepr {
        priority_tick: 0x0A,
        timeout_ticks: 0x0E,
        triad: fo(2, &[], 1_000).triad,
        path: &[],
    };
    let mut data = [0u8; 32];
    let mut w = Writer::new(&mut data);
    fc.emit(&mut w).unwrap();
    let n = w.len();
    h.now = Instant(21_000);
    assert_eq!(status(&h.request(0x4E, &cm_path(), &data[..n])).0, 0);
    live[1] = open(&mut h, 5, 2_000);
    let want = expected(&h, &live, &[0, 21_000, 0, 0], 21_000, 50_000);
    assert_eq!(run(&mut h, 50_000), want);
}
