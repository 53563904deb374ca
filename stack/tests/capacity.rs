//! Each capacity the adapter's type chooses, filled and then exceeded, at the default size and
//! (through `tests/large.rs`) at 16 sessions / 64 connections: every session slot serves and a
//! socket beyond them is closed; every delayed ListIdentity slot holds a reply, and a
//! broadcast request after them is not answered (no amplifier); a 1 448-byte assembly goes by
//! Large_Forward_Open at either size, and by an explicit read when the reply frame holds it
//! (0x11 when it does not); every connection slot produces on its own grid. The connection
//! after the last slot is `forward_open.rs`'s `error_out_of_connections`.

mod common;

use std::collections::BTreeMap;
use std::net::{Ipv4Addr, SocketAddrV4};

use common::*;
use enip_stack::originator;
use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use enip_stack::wire::forward_open::NetworkParams;
use enip_stack::wire::io_datagram::Packet;
use enip_stack::{AssemblyInfo, AssemblyRole, Instant, SocketId};

/// The large input assembly: the largest Class 1 data an Ethernet frame carries (1 500-byte
/// MTU less the IP, UDP and CPF headers and the sequence count).
const BIG: u16 = 160;
const BIG_SIZE: u16 = 1448;

/// A Get_Attribute_Single of `attribute` of `instance` of `class`.
fn get_path(class: u32, instance: u32, attribute: u32) -> [SegmentRepr<'static>; 3] {
    [
        SegmentRepr::Logical(LogicalType::Class, class),
        SegmentRepr::Logical(LogicalType::Instance, instance),
        SegmentRepr::Logical(LogicalType::Attribute, attribute),
    ]
}

#[test]
fn every_session_slot_serves_and_a_socket_beyond_them_is_closed() {
    let mut h = Harness::new();
    let mut handles = vec![h.session];
    for socket in 1..SESSIONS as u8 {
        handles.push(h.open_session(socket, 50_000 + u16::from(socket)));
    }
    for (socket, &handle) in handles.iter().enumerate() {
        let mut buf = vec![0u8; FRAME];
        let n = originator::send_rr_data(&mut buf, handle, None, |w| {
            originator::request(w, 0x0E, &get_path(1, 1, 1), &[])
        })
        .unwrap();
        let (g, _, data) = status(&h.tcp_on(socket as u8, &buf[..n]));
        assert_eq!((g, data), (0, IDENTITY.vendor_id.to_le_bytes().to_vec()));
    }
    let mut distinct = handles.clone();
    distinct.sort_unstable();
    distinct.dedup();
    assert_eq!(distinct.len(), SESSIONS, "one handle per session");

    let beyond = SocketId(SESSIONS as u8);
    h.adapter
        .tcp_accept(beyond, SocketAddrV4::new(SCANNER_IP, 60_000), h.now);
    let mut register = [0u8; 64];
    let n = originator::register_session(&mut register).unwrap();
    let mut reply = vec![0u8; FRAME];
    let out = h
        .adapter
        .tcp_receive(beyond, &register[..n], h.now, &mut reply);
    assert_eq!((out.reply_len, out.close), (0, true));
}

#[test]
fn every_list_identity_slot_holds_a_reply_and_the_next_broadcast_is_dropped() {
    let mut h = Harness::new();
    // A broadcast ListIdentity with a 500 ms bound (sender context 0xF4 0x01).
    let mut request = [0u8; 24];
    request[0] = 0x63;
    request[12..14].copy_from_slice(&500u16.to_le_bytes());
    let mut reply = vec![0u8; FRAME];
    for i in 0..=LIST_IDENTITY as u16 {
        let from = SocketAddrV4::new(SCANNER_IP, 50_000 + i);
        let broadcast = Ipv4Addr::new(198, 18, 0, 255);
        let n = h
            .adapter
            .udp_receive(from, broadcast, &request, Instant(0), &mut reply);
        if usize::from(i) < LIST_IDENTITY {
            assert_eq!(n, 0, "request {i} waits its delay");
        } else {
            assert_eq!(
                n, 0,
                "the queue is full: the broadcast is dropped, not answered"
            );
        }
    }
    let mut answered = Vec::new();
    while let Some((to, n)) = h.adapter.poll_udp(Instant(500_000), &mut reply) {
        assert!(n > 24);
        answered.push(to.port());
    }
    answered.sort_unstable();
    let expected: Vec<u16> = (0..LIST_IDENTITY as u16).map(|i| 50_000 + i).collect();
    assert_eq!(answered, expected, "the queued requests, each once");
}

#[test]
fn a_1448_byte_assembly_goes_by_large_forward_open_and_by_read_if_the_frame_holds_it() {
    let mut device = TestDevice::new();
    device.assemblies.push(AssemblyInfo {
        instance: BIG,
        role: AssemblyRole::Input,
        size: BIG_SIZE,
        run_idle_header: false,
    });
    let pattern: Vec<u8> = (0..BIG_SIZE).map(|i| (i % 251) as u8).collect();
    device.data.insert(BIG, pattern.clone());
    let mut h = Harness::with_device(device);

    // Input only: heartbeat O->T, the sequence count and 1 448 bytes T->O.
    let path = io_path(None, 152, u32::from(BIG), None);
    let mut f = fo(1, &path, 10_000);
    f.large = true;
    f.o_t_params = NetworkParams::from_u32(0x4800_0000 | 2);
    f.t_o_params = NetworkParams::from_u32(0x4800_0000 | (2 + u32::from(BIG_SIZE)));
    let (g, words, _) = status(&h.forward_open(&f));
    assert_eq!((g, words), (0, vec![]));
    let mut out = vec![0u8; 1514];
    let (_, len) = h.adapter.poll_io(Instant(0), &mut out).unwrap();
    let p = Packet::new_checked(&out[..len]).unwrap();
    let data = p.connected_data();
    assert_eq!(data.len(), 2 + usize::from(BIG_SIZE));
    assert_eq!(&data[2..], &pattern[..]);

    // Explicitly: encapsulation header, SendRRData prefix, two CPF items and the Message
    // Router reply header before the data.
    let needed = 24 + 6 + 2 + 4 + 4 + 4 + usize::from(BIG_SIZE);
    let (g, _, data) = status(&h.request(0x0E, &get_path(4, u32::from(BIG), 3), &[]));
    if FRAME >= needed {
        assert_eq!((g, data), (0, pattern));
    } else {
        assert_eq!(g, 0x11, "reply data too large for a {FRAME}-byte frame");
    }
}

#[test]
fn every_connection_slot_produces_on_its_grid() {
    const RPI: u64 = 10_000;
    const END: u64 = 1_000_000;
    let mut h = Harness::new();
    let ids = open_every_slot(&mut h, RPI as u32);
    let mut seen: BTreeMap<u32, Vec<u64>> = BTreeMap::new();
    let mut out = [0u8; 128];
    while let Some(now) = h.adapter.next_deadline().map(Instant::as_micros) {
        if now >= END {
            break;
        }
        while let Some((_, len)) = h.adapter.poll_io(Instant(now), &mut out) {
            let p = Packet::new_checked(&out[..len]).unwrap();
            seen.entry(p.connection_id()).or_default().push(now);
        }
    }
    assert_eq!(seen.len(), CONNECTIONS, "every slot produced");
    // At once, then on the adapter's grid from one RPI on: one grid for all of them.
    let second = seen[&ids[0].1][1];
    for (_, t_o) in ids {
        let at = &seen[&t_o];
        assert!(
            (RPI..2 * RPI).contains(&(at[1] - at[0])),
            "{t_o:#x}: onto the grid, never sooner than one RPI"
        );
        assert_eq!(at[1], second, "{t_o:#x} on the same grid as the others");
        assert_eq!(
            at.len(),
            (2 + (END - 1 - second) / RPI) as usize,
            "{t_o:#x}"
        );
        assert!(
            at[1..].windows(2).all(|w| w[1] - w[0] == RPI),
            "{t_o:#x} on its grid"
        );
    }
}
