//! Encapsulation and explicit messaging through the adapter's entry points: framing, every
//! encapsulation error, and the CIP status of each kind of bad request.

mod common;

use std::net::{Ipv4Addr, SocketAddrV4};

use common::*;

use enip_stack::originator;
use enip_stack::wire::encap::{EncapRepr, HEADER_LEN};
use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use enip_stack::wire::forward_open::{ForwardOpenReplyRepr, NetworkParams};
use enip_stack::wire::Writer;
use enip_stack::{Instant, SocketId};

fn path(class: u32, instance: u32, attribute: Option<u32>) -> Vec<SegmentRepr<'static>> {
    let mut p = vec![
        SegmentRepr::Logical(LogicalType::Class, class),
        SegmentRepr::Logical(LogicalType::Instance, instance),
    ];
    p.extend(attribute.map(|a| SegmentRepr::Logical(LogicalType::Attribute, a)));
    p
}

fn header(command: u16, length: u16, session: u32) -> [u8; 24] {
    let mut h = [0u8; 24];
    EncapRepr {
        command,
        length,
        session_handle: session,
        status: 0,
        sender_context: [7; 8],
        options: 0,
    }
    .emit(&mut Writer::new(&mut h))
    .unwrap();
    h
}

fn encap_status(reply: &[u8]) -> u32 {
    EncapRepr::parse_header(reply).unwrap().status
}

#[test]
fn identity_attributes_and_get_attributes_all() {
    let mut h = Harness::new();
    let (g, _, d) = status(&h.request(0x0E, &path(1, 1, Some(7)), &[]));
    assert_eq!((g, d.as_slice()), (0, &b"\x0btest device"[..]));
    let (g, _, d) = status(&h.request(0x01, &path(1, 1, None), &[]));
    assert_eq!(g, 0);
    assert_eq!(d.len(), 2 + 2 + 2 + 2 + 2 + 4 + 12);
    assert_eq!(&d[..6], &[1, 0, 12, 0, 0xE9, 0xFD]);
    let (g, _, d) = status(&h.request(0x0E, &path(1, 0, Some(1)), &[]));
    assert_eq!((g, d), (0, vec![1, 0]));
    // Class-level Get_Attributes_All: attributes 1-7 in order, lists with their counts
    // (optional attribute 8; optional services Get_Attribute_List and Set_Attribute_List).
    let (g, _, d) = status(&h.request(0x01, &path(1, 0, None), &[]));
    assert_eq!(
        (g, d),
        (
            0,
            vec![1, 0, 1, 0, 1, 0, 1, 0, 8, 0, 2, 0, 3, 0, 4, 0, 7, 0, 8, 0]
        )
    );
}

#[test]
fn cip_error_statuses() {
    let mut h = Harness::new();
    let cases: Vec<(u8, Vec<SegmentRepr<'static>>, Vec<u8>, u8)> = vec![
        (0x0E, path(0x77, 1, Some(1)), vec![], 0x05),
        (0x0E, path(1, 9, Some(1)), vec![], 0x16),
        (0x4B, path(1, 1, None), vec![], 0x08),
        (0x0E, path(1, 1, Some(99)), vec![], 0x14),
        (0x10, path(1, 1, Some(1)), vec![1, 0], 0x0E),
        (0x10, path(4, 100, Some(3)), vec![0; 32], 0x0E),
        (0x10, path(4, 110, Some(3)), vec![0; 31], 0x13),
        (0x10, path(4, 110, Some(3)), vec![0; 33], 0x15),
        (0x10, path(0xF5, 1, Some(8)), vec![0], 0x09),
        (0x10, path(0xF5, 1, Some(13)), vec![0x11, 0x0E], 0x09),
        (
            0x10,
            path(0xF5, 1, Some(9)),
            vec![1, 0, 1, 0, 1, 0, 0, 224],
            0x09,
        ),
        (0x05, path(1, 1, None), vec![7], 0x20),
        (
            0x0E,
            vec![SegmentRepr::Logical(LogicalType::Class, 1)],
            vec![],
            0x05,
        ),
    ];
    for (i, (service, p, data, want)) in cases.into_iter().enumerate() {
        let (g, _, _) = status(&h.request(service, &p, &data));
        assert_eq!(g, want, "case {i}");
    }
    // A path segment error: reserved logical format.
    let mut buf = vec![0u8; FRAME];
    let session = h.session;
    let n = originator::send_rr_data(&mut buf, session, None, |w| {
        w.bytes(&[0x0E, 2, 0x23, 1, 0x24, 1])
    })
    .unwrap();
    assert_eq!(status(&h.tcp(&buf[..n])).0, 0x04);
}

#[test]
fn settable_attributes_round_trip() {
    let mut h = Harness::new();
    assert_eq!(
        status(&h.request(0x10, &path(4, 110, Some(3)), &[3; 32])).0,
        0
    );
    assert_eq!(
        status(&h.request(0x0E, &path(4, 110, Some(3)), &[])).2,
        vec![3; 32]
    );
    assert_eq!(status(&h.request(0x10, &path(0xF5, 1, Some(8)), &[5])).0, 0);
    assert_eq!(
        status(&h.request(0x0E, &path(0xF5, 1, Some(8)), &[])).2,
        vec![5]
    );
    let mcast = [1, 0, 1, 0, 32, 15, 192, 239];
    assert_eq!(
        status(&h.request(0x10, &path(0xF5, 1, Some(9)), &mcast)).0,
        0
    );
    assert_eq!(
        status(&h.request(0x0E, &path(0xF5, 1, Some(9)), &[])).2,
        mcast.to_vec()
    );
    assert_eq!(
        status(&h.request(0x10, &path(0xF5, 1, Some(13)), &[30, 0])).0,
        0
    );
    assert_eq!(
        h.adapter.tcp_deadline(SocketId(0)),
        Some(Instant(30_000_000))
    );
}

#[test]
fn lists_and_multiple_service_packet() {
    let mut h = Harness::new();
    let (g, _, d) = status(&h.request(0x03, &path(1, 1, None), &[2, 0, 1, 0, 99, 0]));
    assert_eq!(g, 0x0A);
    assert_eq!(d, vec![2, 0, 1, 0, 0, 0, 1, 0, 99, 0, 0x14, 0]);
    // Two embedded requests: one good, one to an unknown class.
    let good = [0x0E, 3, 0x20, 1, 0x24, 1, 0x30, 1];
    let bad = [0x0E, 3, 0x20, 0x77, 0x24, 1, 0x30, 1];
    let mut data = vec![2, 0, 6, 0, 14, 0];
    data.extend(good);
    data.extend(bad);
    let (g, _, d) = status(&h.request(0x0A, &path(2, 1, None), &data));
    assert_eq!(g, 0x1E);
    assert_eq!(&d[..6], &[2, 0, 6, 0, 12, 0]);
    assert_eq!(&d[6..12], &[0x8E, 0, 0, 0, 1, 0]);
    assert_eq!(&d[12..], &[0x8E, 0, 0x05, 0]);
    // Offsets out of order (both inside the data).
    assert_eq!(
        status(&h.request(0x0A, &path(2, 1, None), &[2, 0, 8, 0, 6, 0, 0, 0, 0, 0])).0,
        0x20
    );
}

#[test]
fn unconnected_send_to_port_1_slot_0() {
    let mut h = Harness::new();
    let inner = [0x0E, 3, 0x20, 1, 0x24, 1, 0x30, 7];
    let mut data = vec![0x0A, 0x0E, inner.len() as u8, 0];
    data.extend(inner);
    data.extend([1, 0, 0x01, 0x00]);
    let (g, _, d) = status(&h.request(0x52, &path(6, 1, None), &data));
    assert_eq!((g, d.as_slice()), (0, &b"\x0btest device"[..]));
    let frame = h.request(
        0x52,
        &path(6, 1, None),
        &[&data[..12], &[1, 0, 0x02, 0x00][..]].concat(),
    );
    assert_eq!(status(&frame).1, vec![0x0311]);
    // A routing error's reply carries the Remaining Path Size: the route's words as this
    // device saw them (Vol 1 3-5.5.4), here the whole two-segment route, and a reserved
    // byte (tshark reads the reply malformed without it).
    let frame = h.request(
        0x52,
        &path(6, 1, None),
        &[&data[..12], &[2, 0, 0x01, 0x05, 0x01, 0x00][..]].concat(),
    );
    let (g, words, d) = status(&frame);
    assert_eq!((g, words, d), (0x01, vec![0x0315], vec![2, 0]));
    let frame = h.request(
        0x52,
        &path(6, 1, None),
        &[&data[..12], &[1, 0, 0x01, 0x05][..]].concat(),
    );
    assert_eq!(status(&frame), (0x01, vec![0x0312], vec![1, 0]));
}

#[test]
fn tcp_framing_split_and_batched() {
    let mut h = Harness::new();
    let mut buf = vec![0u8; FRAME];
    let session = h.session;
    let n = originator::send_rr_data(&mut buf, session, None, |w| {
        originator::request(w, 0x0E, &path(1, 1, Some(1)), &[])
    })
    .unwrap();
    let frame = buf[..n].to_vec();
    // One byte at a time.
    let mut reply = vec![0u8; FRAME];
    for (i, b) in frame.iter().enumerate() {
        let out =
            h.adapter
                .tcp_receive(SocketId(0), std::slice::from_ref(b), Instant(0), &mut reply);
        assert_eq!(out.consumed, 1);
        assert_eq!(out.reply_len > 0, i == frame.len() - 1);
    }
    // Three frames in one segment.
    let three = [frame.clone(), frame.clone(), frame.clone()].concat();
    let mut at = 0;
    let mut replies = 0;
    while at < three.len() {
        let out = h
            .adapter
            .tcp_receive(SocketId(0), &three[at..], Instant(0), &mut reply);
        assert!(out.consumed > 0);
        at += out.consumed;
        replies += usize::from(out.reply_len > 0);
    }
    assert_eq!(replies, 3);
}

#[test]
fn tcp_framing_across_segments_keeps_order_and_replies_in_place() {
    let mut h = Harness::new();
    let mut buf = vec![0u8; FRAME];
    let n = originator::send_rr_data(&mut buf, h.session, None, |w| {
        originator::request(w, 0x0E, &path(1, 1, Some(7)), &[])
    })
    .unwrap();
    let frame = buf[..n].to_vec();
    let mut reply = vec![0u8; FRAME];
    // Half a frame, then its other half with a whole frame and the start of a third.
    let stream = [frame.clone(), frame.clone(), frame.clone()].concat();
    let cut = [n / 2, 2 * n + 5];
    let mut replies = Vec::new();
    for seg in [
        &stream[..cut[0]],
        &stream[cut[0]..cut[1]],
        &stream[cut[1]..],
    ] {
        let mut rest = seg;
        while !rest.is_empty() {
            let out = h
                .adapter
                .tcp_receive(SocketId(0), rest, Instant(0), &mut reply);
            assert!(out.consumed > 0 && !out.close && out.reset.is_none());
            rest = &rest[out.consumed..];
            if out.reply_len > 0 {
                replies.push(reply[..out.reply_len].to_vec());
            }
        }
    }
    assert_eq!(replies.len(), 3);
    assert!(replies.iter().all(|r| r == &replies[0]));
    assert_eq!(status(&replies[0]).2, b"\x0btest device");
}

#[test]
fn a_frame_over_capacity_is_answered_0x65_and_skipped_however_it_arrives() {
    for first in [24, 10, 1] {
        let mut h = Harness::new();
        let mut reply = vec![0u8; FRAME];
        let f = header(0x6F, (FRAME - HEADER_LEN + 1) as u16, h.session);
        let out = h
            .adapter
            .tcp_receive(SocketId(0), &f[..first], Instant(0), &mut reply);
        if first < HEADER_LEN {
            assert_eq!((out.consumed, out.reply_len, out.close), (first, 0, false));
            let rest = [&f[first..], &[0u8; 8][..]].concat();
            let out = h
                .adapter
                .tcp_receive(SocketId(0), &rest, Instant(0), &mut reply);
            assert_eq!((out.consumed, out.close), (rest.len(), false));
            assert_eq!(out.reply_len, HEADER_LEN);
        } else {
            assert_eq!(
                (out.consumed, out.reply_len, out.close),
                (24, HEADER_LEN, false)
            );
        }
        let r = reply[..HEADER_LEN].to_vec();
        assert_eq!(encap_status(&r), 0x65);
        assert_eq!(
            (&r[..2], &r[2..4], &r[12..20]),
            (&f[..2], &[0, 0][..], &[7; 8][..])
        );
        // The rest of its data is skipped; the frame behind it is answered.
        let skipped = FRAME - HEADER_LEN + 1 - if first < HEADER_LEN { 8 } else { 0 };
        let rest = [vec![0x5A; skipped], header(0x63, 0, 0).to_vec()].concat();
        let mut replies = Vec::new();
        let mut data = &rest[..];
        // Bounded: every call takes at least one byte.
        for _ in 0..rest.len() {
            if data.is_empty() {
                break;
            }
            let out = h
                .adapter
                .tcp_receive(SocketId(0), data, Instant(0), &mut reply);
            assert!(out.consumed > 0 && !out.close);
            data = &data[out.consumed..];
            if out.reply_len > 0 {
                replies.push(reply[..out.reply_len].to_vec());
            }
        }
        assert_eq!(replies.len(), 1, "first segment {first}");
        assert_eq!((replies[0][0], encap_status(&replies[0])), (0x63, 0));
    }
}

#[test]
fn an_identity_reset_is_in_the_outcome_of_its_frame() {
    let mut h = Harness::new();
    let mut buf = vec![0u8; FRAME];
    let n = originator::send_rr_data(&mut buf, h.session, None, |w| {
        originator::request(w, 0x05, &path(1, 1, None), &[0])
    })
    .unwrap();
    let mut reply = vec![0u8; FRAME];
    let out = h
        .adapter
        .tcp_receive(SocketId(0), &buf[..n], Instant(0), &mut reply);
    assert_eq!((out.consumed, out.close, out.reset), (n, false, Some(0)));
    assert_eq!(status(&reply[..out.reply_len]).0, 0);
    // Reported once.
    let out = h
        .adapter
        .tcp_receive(SocketId(0), &header(0, 0, 0), Instant(0), &mut reply);
    assert_eq!((out.reply_len, out.reset), (0, None));
    assert_eq!(h.adapter.take_reset(), None);
}

#[test]
fn encapsulation_errors() {
    let mut h = Harness::new();
    let mut reply = vec![0u8; FRAME];
    // Feeds `bytes` as a TCP connection would, until all are taken or the adapter closes:
    // the replies' length, whether it closed, and the replies.
    let mut run = |h: &mut Harness, bytes: &[u8]| {
        let (mut rest, mut replies, mut close) = (bytes, Vec::new(), false);
        // Bounded: each call takes at least one byte (checked), or closes.
        for _ in 0..bytes.len() {
            if rest.is_empty() || close {
                break;
            }
            let out = h
                .adapter
                .tcp_receive(SocketId(0), rest, Instant(0), &mut reply);
            assert!(out.consumed > 0 || out.close);
            replies.extend_from_slice(&reply[..out.reply_len]);
            rest = &rest[out.consumed.min(rest.len())..];
            close = out.close;
        }
        (replies.len(), close, replies)
    };
    // Wrong session handle, unknown command.
    let mut f = header(0x6F, 0, h.session ^ 0x100).to_vec();
    let (_, close, r) = run(&mut h, &f);
    assert_eq!((encap_status(&r), close), (0x64, false));
    f = header(0x0055, 0, h.session).to_vec();
    assert_eq!(encap_status(&run(&mut h, &f).2), 0x01);
    // Bad CPF: item count 5.
    f = header(0x6F, 8, h.session).to_vec();
    f.extend([0, 0, 0, 0, 0, 0, 5, 0]);
    assert_eq!(encap_status(&run(&mut h, &f).2), 0x03);
    // Non-zero options: discarded, nothing sent, the connection stays.
    f = header(0x0063, 0, 0).to_vec();
    f[20] = 1;
    assert_eq!(run(&mut h, &f).0, 0);
    // Second RegisterSession on the same connection.
    f = header(0x65, 4, 0).to_vec();
    f.extend([1, 0, 0, 0]);
    assert_eq!(encap_status(&run(&mut h, &f).2), 0x01);
    // Length over capacity: status 0x65; the data is skipped as it arrives, across
    // segments, and the session goes on: a ListIdentity right behind it is answered.
    f = header(0x6F, 2000, h.session).to_vec();
    f.extend([0xAB; 500]);
    let (n, close, r) = run(&mut h, &f);
    assert_eq!((n, close, encap_status(&r)), (HEADER_LEN, false, 0x65));
    let mut rest = vec![0xAB; 1500];
    rest.extend(header(0x63, 0, 0));
    let (n, close, r) = run(&mut h, &rest);
    assert!(n > HEADER_LEN && !close, "{n} {close}");
    assert_eq!((r[0], encap_status(&r)), (0x63, 0));
    // A NOP is never answered, at any length (Vol 2, 2-4.1); the session goes on.
    f = header(0x00, 3000, h.session).to_vec();
    f.extend([0; 3000]);
    assert_eq!(run(&mut h, &f).0, 0);
    f = header(0x63, 0, 0).to_vec();
    assert_eq!(encap_status(&run(&mut h, &f).2), 0);
    // Length over capacity, the most a header can say: status 0x65, the connection stays.
    f = header(0x6F, 0xFFFF, h.session).to_vec();
    let (n, close, r) = run(&mut h, &f);
    assert_eq!((n, close, encap_status(&r)), (HEADER_LEN, false, 0x65));

    // A fresh connection: unsupported protocol version, and SendRRData before registering.
    h.adapter.tcp_accept(
        SocketId(1),
        SocketAddrV4::new(SCANNER_IP, 50001),
        Instant(0),
    );
    let mut reply = vec![0u8; FRAME];
    let mut f = header(0x65, 4, 0).to_vec();
    f.extend([2, 0, 0, 0]);
    let out = h
        .adapter
        .tcp_receive(SocketId(1), &f, Instant(0), &mut reply);
    assert_eq!(encap_status(&reply[..out.reply_len]), 0x69);
    assert_eq!(
        &reply[24..28],
        &[1, 0, 0, 0],
        "the supported version is reported"
    );
    let f = header(0x6F, 0, 0);
    let out = h
        .adapter
        .tcp_receive(SocketId(1), &f, Instant(0), &mut reply);
    assert_eq!(encap_status(&reply[..out.reply_len]), 0x64);
}

#[test]
fn udp_commands_and_broadcast_delay() {
    let mut h = Harness::new();
    let from = SocketAddrV4::new(SCANNER_IP, 50000);
    let mut reply = vec![0u8; FRAME];
    let n = h.adapter.udp_receive(
        from,
        ADAPTER_IP,
        &header(0x65, 0, 0),
        Instant(0),
        &mut reply,
    );
    assert_eq!(encap_status(&reply[..n]), 0x01);
    let n = h.adapter.udp_receive(
        from,
        ADAPTER_IP,
        &header(0x04, 0, 0),
        Instant(0),
        &mut reply,
    );
    assert_eq!((encap_status(&reply[..n]), n), (0, 24 + 2 + 4 + 20));
    let n = h.adapter.udp_receive(
        from,
        ADAPTER_IP,
        &header(0x63, 0, 0),
        Instant(0),
        &mut reply,
    );
    assert!(n > 24 + 30, "unicast ListIdentity answered at once");
    // Broadcast with a 500 ms bound (sender context 0xF4 0x01 = 500).
    let mut f = header(0x63, 0, 0);
    f[12] = 0xF4;
    f[13] = 0x01;
    let n = h.adapter.udp_receive(
        from,
        Ipv4Addr::new(198, 18, 0, 255),
        &f,
        Instant(1_000),
        &mut reply,
    );
    assert_eq!(n, 0);
    let due = h.adapter.next_deadline().unwrap();
    assert!(due >= Instant(1_000) && due <= Instant(501_000));
    if due > Instant(1_000) {
        assert!(h
            .adapter
            .poll_udp(Instant(due.as_micros() - 1), &mut reply)
            .is_none());
    }
    let (to, n) = h.adapter.poll_udp(due, &mut reply).unwrap();
    assert_eq!(to, from);
    assert_eq!(&reply[12..14], &[0xF4, 0x01]);
    assert!(n > 24);
}

/// A storm of ListIdentity requests over UDP, unicast and broadcast: never more replies
/// than requests, and never more reply bytes than `LIST_IDENTITY_UDP_BYTES_PER_SECOND` a
/// second plus the second's worth that may be saved up; a broadcast request that finds the
/// delay queue full goes unanswered instead of being answered at once.
#[test]
fn a_list_identity_storm_is_answered_within_the_byte_budget() {
    use enip_stack::config::LIST_IDENTITY_UDP_BYTES_PER_SECOND;
    let mut h = Harness::new();
    let from = SocketAddrV4::new(SCANNER_IP, 50000);
    let mut reply = vec![0u8; FRAME];
    let mut broadcast = header(0x63, 0, 0);
    broadcast[12] = 0xF4;
    broadcast[13] = 0x01;
    let unicast = header(0x63, 0, 0);
    let (mut requests, mut replies, mut bytes) = (0u64, 0u64, 0u64);
    // 2 s of 10 000 requests a second, alternately broadcast and unicast.
    for i in 0..20_000u64 {
        let at = Instant(i * 100);
        let (to, f) = if i % 2 == 0 {
            (Ipv4Addr::new(198, 18, 0, 255), &broadcast)
        } else {
            (ADAPTER_IP, &unicast)
        };
        requests += 1;
        let n = h.adapter.udp_receive(from, to, f, at, &mut reply);
        if n > 0 {
            replies += 1;
            bytes += n as u64;
        }
        if i == 0 {
            // The first broadcasts fill the delay queue; the rest find it full.
            for _ in 1..LIST_IDENTITY {
                let n = h.adapter.udp_receive(from, to, f, at, &mut reply);
                assert_eq!(n, 0, "queued, not answered at once");
                requests += 1;
            }
        }
        while let Some((_, n)) = h.adapter.poll_udp(at, &mut reply) {
            replies += 1;
            bytes += n as u64;
        }
    }
    while let Some((_, n)) = h.adapter.poll_udp(Instant(3_000_000), &mut reply) {
        replies += 1;
        bytes += n as u64;
    }
    let budget = u64::from(LIST_IDENTITY_UDP_BYTES_PER_SECOND);
    assert!(replies <= requests);
    assert!(
        bytes <= budget * 3,
        "{bytes} reply bytes in 2 s (budget {budget}/s)"
    );
    assert!(bytes >= budget, "the budget is used: {bytes}");
}

/// The data of a Class 3 Forward_Open of serial `serial` to the Message Router.
fn class3_open(serial: u16) -> Vec<u8> {
    let mr = [0x20, 0x02, 0x24, 0x01];
    let mut f = fo(serial, &mr, 1_000_000);
    f.transport = 0xA3;
    f.o_t_params = NetworkParams::from_u16(0x4800 | 500);
    f.t_o_params = NetworkParams::from_u16(0x4800 | 500);
    let mut data = [0u8; 128];
    let mut w = Writer::new(&mut data);
    f.emit(&mut w).unwrap();
    w.written().to_vec()
}

/// Sends `request` on the Class 3 connection `id` with `seq`: the reply's service, general
/// status and data.
fn connected(h: &mut Harness, id: u32, seq: u16, request: &[u8]) -> (u8, u8, Vec<u8>) {
    let mut buf = vec![0u8; 600];
    let n = originator::send_unit_data(&mut buf, h.session, id, seq, |w| w.bytes(request)).unwrap();
    let reply = h.tcp(&buf[..n]);
    let r = originator::parse_reply(&reply).unwrap();
    assert_eq!(r.connected.map(|(_, s)| s), Some(seq));
    let resp = r.response.unwrap();
    (resp.service, resp.general_status, resp.data.to_vec())
}

#[test]
fn a_class3_connection_opened_in_the_slot_of_the_one_that_asked_starts_afresh() {
    let mut h = Harness::new();
    let (g, _, data) = status(&h.request(0x54, &cm_path(), &class3_open(1)));
    assert_eq!(g, 0);
    let old = ForwardOpenReplyRepr::parse(&data)
        .unwrap()
        .o_t_connection_id;
    // Over the connection itself, one Multiple_Service_Packet closes it and opens another,
    // which takes its slot.
    let mut close = vec![0x4E, 0x02, 0x20, 0x06, 0x24, 0x01, 0x0A, 0x0E];
    close.extend(1u16.to_le_bytes());
    close.extend(0x1337u16.to_le_bytes());
    close.extend(0xC0FFEEu32.to_le_bytes());
    close.extend([0, 0]);
    let mut open = vec![0x54, 0x02, 0x20, 0x06, 0x24, 0x01];
    open.extend(class3_open(2));
    let mut msp = vec![0x0A, 0x02, 0x20, 0x02, 0x24, 0x01, 2, 0, 6, 0];
    msp.extend(((6 + close.len()) as u16).to_le_bytes());
    msp.extend(&close);
    msp.extend(&open);
    assert_eq!(connected(&mut h, old, 7, &msp).1, 0);
    assert_eq!(h.adapter.connections().len(), 1);
    let new = h.adapter.connections().iter().next().unwrap().1.o_t_id;
    assert_ne!(new, old);
    // Its first request, whatever its sequence count, is executed: not answered with the
    // reply cached for the closed one.
    let get_name = [0x0E, 0x03, 0x20, 0x01, 0x24, 0x01, 0x30, 0x07];
    let (service, general, name) = connected(&mut h, new, 7, &get_name);
    assert_eq!((service, general), (0x8E, 0));
    assert_eq!(&name[1..], IDENTITY.product_name.as_bytes());
}
