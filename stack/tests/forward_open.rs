//! Forward_Open / Forward_Close through the adapter's TCP entry point: every error with its
//! exact general and extended status, and the success paths.

mod common;

use common::*;
use enip_stack::device::{CloseReason, ConnectionEvent};
use enip_stack::wire::epath::{ElectronicKey, LogicalType, SegmentRepr};
use enip_stack::wire::forward_open::{ForwardOpenReplyRepr, NetworkParams};
use enip_stack::wire::Writer;
use enip_stack::{Instant, SocketId};

#[test]
fn exclusive_owner_opens_and_closes() {
    let mut h = Harness::new();
    let path = io_path(Some(151), 110, 100, Some(&[9; 10]));
    let (g, words, data) = open(&mut h, &fo(1, &path, 10_000));
    assert_eq!((g, words.len()), (0, 0));
    let reply = ForwardOpenReplyRepr::parse(&data).unwrap();
    assert_eq!(reply.t_o_connection_id, 0x7000_0001);
    assert_ne!(reply.o_t_connection_id, 0);
    assert_eq!((reply.o_t_api, reply.t_o_api), (10_000, 10_000));
    assert_eq!(reply.triad, fo(1, &[], 0).triad);
    assert_eq!(
        h.adapter.device().data[&151],
        vec![9; 10],
        "configuration data written"
    );
    assert_eq!(
        h.adapter.device().events,
        vec![ConnectionEvent::OwnershipGained]
    );
    assert_eq!(h.adapter.connections().len(), 1);
    // Identity status: owned, I/O connection established but idle.
    let (_, _, id) = status(&h.request(
        0x0E,
        &[
            SegmentRepr::Logical(LogicalType::Class, 1),
            SegmentRepr::Logical(LogicalType::Instance, 1),
            SegmentRepr::Logical(LogicalType::Attribute, 5),
        ],
        &[],
    ));
    assert_eq!(id, vec![0x71, 0x00]);
    // The owned output refuses explicit writes.
    let set = h.request(
        0x10,
        &[
            SegmentRepr::Logical(LogicalType::Class, 4),
            SegmentRepr::Logical(LogicalType::Instance, 110),
            SegmentRepr::Logical(LogicalType::Attribute, 3),
        ],
        &[0; 32],
    );
    assert_eq!(status(&set).0, 0x10);

    let (g, _, data) = close(&mut h, 1);
    assert_eq!(g, 0);
    assert_eq!(&data[..2], &1u16.to_le_bytes());
    assert!(h.adapter.connections().is_empty());
    assert_eq!(
        h.adapter.device().events.last(),
        Some(&ConnectionEvent::OwnershipLost(CloseReason::ForwardClose))
    );
}

#[test]
fn large_forward_open_uses_32_bit_parameters() {
    let mut h = Harness::new();
    let path = io_path(Some(151), 110, 100, None);
    let mut f = fo(2, &path, 2_000);
    f.large = true;
    f.o_t_params = NetworkParams::from_u32(0x4800_0000 | 38);
    f.t_o_params = NetworkParams::from_u32(0x4800_0000 | 34);
    assert_eq!(open(&mut h, &f).0, 0);
}

#[test]
fn multicast_reply_carries_group_and_listen_only_follows() {
    let mut h = Harness::new();
    let path = io_path(None, 110, 100, None);
    let mut owner = fo(1, &path, 5_000);
    owner.t_o_params = NetworkParams::from_u16(0x2800 | 34);
    let frame = h.forward_open(&owner);
    let reply = enip_stack::originator::parse_reply(&frame).unwrap();
    assert_eq!(reply.response.unwrap().general_status, 0);
    let group = reply
        .t_o_sockaddr
        .expect("T->O sockaddr item for multicast");
    assert_eq!(
        (group.addr, group.port),
        (std::net::Ipv4Addr::new(239, 192, 1, 32), 2222)
    );
    let owner_t_o = ForwardOpenReplyRepr::parse(reply.response.unwrap().data)
        .unwrap()
        .t_o_connection_id;
    assert_eq!(h.adapter.multicast_group(), Some(group.addr));

    let lo_path = io_path(None, 153, 100, None);
    let mut lo = fo(2, &lo_path, 5_000);
    lo.o_t_params = NetworkParams::from_u16(0x4800 | 2);
    lo.t_o_params = NetworkParams::from_u16(0x2800 | 34);
    let (g, _, data) = open(&mut h, &lo);
    assert_eq!(g, 0);
    assert_eq!(
        ForwardOpenReplyRepr::parse(&data)
            .unwrap()
            .t_o_connection_id,
        owner_t_o
    );
    assert_eq!(h.adapter.connections().len(), 2);
    // The owner goes: its listener goes with it.
    assert_eq!(close(&mut h, 1).0, 0);
    assert!(h.adapter.connections().is_empty());
}

#[test]
fn input_only_heartbeat() {
    let mut h = Harness::new();
    let path = io_path(None, 152, 101, None);
    let mut f = fo(3, &path, 1_000);
    f.o_t_params = NetworkParams::from_u16(0x4800 | 2);
    assert_eq!(open(&mut h, &f).0, 0);
    assert!(
        h.adapter.device().events.is_empty(),
        "input only does not own"
    );
}

#[test]
fn error_duplicate_and_ownership() {
    let mut h = Harness::new();
    let path = io_path(None, 110, 100, None);
    assert_eq!(open(&mut h, &fo(1, &path, 10_000)).0, 0);
    assert_eq!(ext_of(&mut h, &fo(1, &path, 10_000)), (0x01, Some(0x0100)));
    assert_eq!(ext_of(&mut h, &fo(2, &path, 10_000)), (0x01, Some(0x0106)));
    // The failure reply still carries the triad.
    let (_, _, data) = open(&mut h, &fo(2, &path, 10_000));
    assert_eq!(data, vec![2, 0, 0x37, 0x13, 0xEE, 0xFF, 0xC0, 0, 0, 0]);
}

#[test]
fn error_forward_close_unknown() {
    let mut h = Harness::new();
    let (g, words, data) = close(&mut h, 77);
    assert_eq!((g, words), (0x01, vec![0x0107]));
    assert_eq!(&data[..2], &77u16.to_le_bytes());
}

#[test]
fn error_transport_and_network_parameters() {
    let mut h = Harness::new();
    let path = io_path(None, 110, 100, None);
    for transport in [0x00, 0x02, 0x31, 0x41] {
        let mut f = fo(1, &path, 10_000);
        f.transport = transport;
        assert_eq!(
            ext_of(&mut h, &f),
            (0x01, Some(0x0103)),
            "transport {transport:#x}"
        );
    }
    let mut f = fo(1, &path, 10_000);
    f.o_t_params = NetworkParams::from_u16(0x2800 | 38);
    assert_eq!(ext_of(&mut h, &f), (0x01, Some(0x0108)));
    let mut f = fo(1, &path, 10_000);
    f.t_o_params = NetworkParams::from_u16(0x6800 | 34);
    assert_eq!(ext_of(&mut h, &f), (0x01, Some(0x0108)));
    let mut f = fo(1, &path, 10_000);
    f.o_t_params = NetworkParams::from_u16(0);
    f.t_o_params = NetworkParams::from_u16(0);
    assert_eq!(ext_of(&mut h, &f), (0x01, Some(0x0132)));
    let mut f = fo(1, &path, 10_000);
    f.timeout_multiplier = 8;
    assert_eq!(ext_of(&mut h, &f), (0x01, Some(0x0133)));
}

#[test]
fn error_sizes_report_the_expected_size() {
    let mut h = Harness::new();
    let path = io_path(None, 110, 100, None);
    let mut f = fo(1, &path, 10_000);
    f.o_t_params = NetworkParams::from_u16(0x4800 | 36);
    assert_eq!(open(&mut h, &f).1, vec![0x0127, 38]);
    let mut f = fo(1, &path, 10_000);
    f.t_o_params = NetworkParams::from_u16(0x4800 | 32);
    assert_eq!(open(&mut h, &f).1, vec![0x0128, 34]);
    let cfg = io_path(Some(151), 110, 100, Some(&[1, 2, 3, 4]));
    // The configuration's size in words, as its data segment counts it (10 bytes: 5).
    assert_eq!(open(&mut h, &fo(1, &cfg, 10_000)).1, vec![0x0126, 5]);
    // Class 3 larger than the explicit buffer.
    let mr = [0x20, 0x02, 0x24, 0x01];
    let mut f = fo(1, &mr, 100_000);
    f.transport = 0xA3;
    f.o_t_params = NetworkParams::from_u16(0x4800 | 0x1FF);
    f.t_o_params = NetworkParams::from_u16(0x4800 | 0x1FF);
    assert_eq!(open(&mut h, &f).1, vec![0x0109, 506]);
}

#[test]
fn error_rpi_reports_acceptable_values() {
    let mut h = Harness::new();
    let path = io_path(None, 110, 100, None);
    let mut f = fo(1, &path, 500);
    f.t_o_rpi = 20_000_000;
    let (g, words, _) = open(&mut h, &f);
    assert_eq!(g, 0x01);
    // type O->T = 2 (minimum), T->O = 3 (maximum), then the values.
    assert_eq!(words, vec![0x0112, 0x0302, 1000, 0, 0x9680, 0x0098]);
}

#[test]
fn error_out_of_connections() {
    let mut h = Harness::new();
    open_every_slot(&mut h, 10_000);
    assert_eq!(h.adapter.connections().len(), CONNECTIONS);
    let path = io_path(None, 152, 100, None);
    let mut f = fo(1000, &path, 10_000);
    f.o_t_params = NetworkParams::from_u16(0x4800 | 2);
    assert_eq!(ext_of(&mut h, &f), (0x01, Some(0x0113)));
}

#[test]
fn error_electronic_key() {
    let mut h = Harness::new();
    let good = ElectronicKey {
        vendor_id: 1,
        device_type: 12,
        product_code: 65001,
        major_revision: 1,
        compatibility: false,
        minor_revision: 2,
    };
    let cases = [
        (
            ElectronicKey {
                vendor_id: 2,
                ..good
            },
            None,
        ),
        (
            ElectronicKey {
                product_code: 1,
                ..good
            },
            Some(0x0114),
        ),
        (
            ElectronicKey {
                device_type: 7,
                ..good
            },
            Some(0x0115),
        ),
        (
            ElectronicKey {
                major_revision: 2,
                ..good
            },
            Some(0x0116),
        ),
        (
            ElectronicKey {
                minor_revision: 3,
                ..good
            },
            Some(0x0116),
        ),
        (
            ElectronicKey {
                minor_revision: 3,
                compatibility: true,
                ..good
            },
            Some(0x0116),
        ),
        // With the compatibility bit a key names a device to emulate: zero is no value.
        (
            ElectronicKey {
                vendor_id: 0,
                compatibility: true,
                ..good
            },
            Some(0x0114),
        ),
        (
            ElectronicKey {
                device_type: 0,
                compatibility: true,
                ..good
            },
            Some(0x0115),
        ),
        (
            ElectronicKey {
                major_revision: 0,
                compatibility: true,
                ..good
            },
            Some(0x0116),
        ),
    ];
    for (i, (key, want)) in cases.iter().enumerate() {
        let mut buf = [0u8; 64];
        let mut w = Writer::new(&mut buf);
        SegmentRepr::ElectronicKey(*key).emit(&mut w).unwrap();
        let n = w.len();
        let path = [&buf[..n], &io_path(None, 110, 100, None)[..]].concat();
        let got = ext_of(&mut h, &fo(i as u16 + 1, &path, 10_000));
        assert_eq!(got, (0x01, Some(want.unwrap_or(0x0114))), "case {i}");
    }
    // Matching, wildcard and compatible keys open.
    for (i, key) in [
        good,
        ElectronicKey {
            vendor_id: 0,
            device_type: 0,
            product_code: 0,
            major_revision: 0,
            compatibility: false,
            minor_revision: 0,
        },
        ElectronicKey {
            minor_revision: 1,
            compatibility: true,
            ..good
        },
    ]
    .iter()
    .enumerate()
    {
        let mut buf = [0u8; 64];
        let mut w = Writer::new(&mut buf);
        SegmentRepr::ElectronicKey(*key).emit(&mut w).unwrap();
        let n = w.len();
        let path = [&buf[..n], &io_path(None, 110 + i as u32, 100, None)[..]].concat();
        assert_eq!(
            open(&mut h, &fo(20 + i as u16, &path, 10_000)).0,
            0,
            "key {i}"
        );
    }
}

#[test]
fn error_application_paths() {
    let mut h = Harness::new();
    let lo = io_path(None, 153, 100, None);
    let mut f = fo(1, &lo, 10_000);
    f.o_t_params = NetworkParams::from_u16(0x4800 | 2);
    f.t_o_params = NetworkParams::from_u16(0x2800 | 34);
    assert_eq!(ext_of(&mut h, &f), (0x01, Some(0x0119)));
    assert_eq!(
        ext_of(&mut h, &fo(1, &io_path(Some(100), 110, 100, None), 10_000)),
        (0x01, Some(0x0129))
    );
    assert_eq!(
        ext_of(&mut h, &fo(1, &io_path(None, 100, 101, None), 10_000)),
        (0x01, Some(0x012A))
    );
    assert_eq!(
        ext_of(&mut h, &fo(1, &io_path(None, 999, 101, None), 10_000)),
        (0x01, Some(0x012A))
    );
    assert_eq!(
        ext_of(&mut h, &fo(1, &io_path(None, 110, 111, None), 10_000)),
        (0x01, Some(0x012B))
    );
    // A symbolic segment has no place in a connection path; nor has a class other than 4.
    let (g, words, data) = open(&mut h, &fo(1, &[0x91, 2, b'a', b'b', 0x20, 4], 10_000));
    assert_eq!((g, words[0]), (0x01, 0x0315));
    assert_eq!(data[8], 3, "remaining path size");
    assert_eq!(
        ext_of(&mut h, &fo(1, &[0x20, 0x99, 0x2C, 110, 0x2C, 100], 10_000)),
        (0x01, Some(0x0315))
    );
    assert_eq!(
        ext_of(&mut h, &fo(1, &[0x20, 4, 0x2D, 0], 10_000)),
        (0x01, Some(0x0315))
    );
}

#[test]
fn error_multicast_off_subnet_with_ttl_1() {
    let mut h = Harness::new();
    h.adapter
        .tcp_accept(SocketId(1), "198.19.0.9:50000".parse().unwrap(), Instant(0));
    let mut buf = [0u8; 64];
    let n = enip_stack::originator::register_session(&mut buf).unwrap();
    let mut reply = vec![0u8; 600];
    let out = h
        .adapter
        .tcp_receive(SocketId(1), &buf[..n], Instant(0), &mut reply);
    let session = u32::from_le_bytes(reply[4..8].try_into().unwrap());
    assert_eq!(out.reply_len, 28);
    let path = io_path(None, 110, 100, None);
    let mut f = fo(1, &path, 10_000);
    f.t_o_params = NetworkParams::from_u16(0x2800 | 34);
    let mut data = [0u8; 128];
    let mut w = Writer::new(&mut data);
    f.emit(&mut w).unwrap();
    let dn = w.len();
    let mut frame = vec![0u8; 600];
    let fn_ = enip_stack::originator::send_rr_data(&mut frame, session, None, |w| {
        enip_stack::originator::request(w, 0x54, &cm_path(), &data[..dn])
    })
    .unwrap();
    let out = h
        .adapter
        .tcp_receive(SocketId(1), &frame[..fn_], Instant(0), &mut reply);
    assert_eq!(status(&reply[..out.reply_len]).1[0], 0x0813);
}

#[test]
fn class3_repeated_sequence_gets_cached_reply() {
    let mut h = Harness::new();
    let mr = [0x20, 0x02, 0x24, 0x01];
    let mut f = fo(9, &mr, 100_000);
    f.transport = 0xA3;
    f.o_t_params = NetworkParams::from_u16(0x4800 | 500);
    f.t_o_params = NetworkParams::from_u16(0x4800 | 500);
    let (g, _, data) = open(&mut h, &f);
    assert_eq!(g, 0);
    let id = ForwardOpenReplyRepr::parse(&data)
        .unwrap()
        .o_t_connection_id;
    let set = |h: &mut Harness, seq: u16, value: u8| {
        let mut buf = vec![0u8; 600];
        let session = h.session;
        let n = enip_stack::originator::send_unit_data(&mut buf, session, id, seq, |w| {
            enip_stack::originator::request(
                w,
                0x10,
                &[
                    SegmentRepr::Logical(LogicalType::Class, 4),
                    SegmentRepr::Logical(LogicalType::Instance, 154),
                    SegmentRepr::Logical(LogicalType::Attribute, 3),
                ],
                &[value; 32],
            )
        })
        .unwrap();
        let reply = h.tcp(&buf[..n]);
        let r = enip_stack::originator::parse_reply(&reply).unwrap();
        assert_eq!(r.connected, Some((0x7000_0009, seq)));
        assert_eq!(r.response.unwrap().general_status, 0);
    };
    set(&mut h, 1, 5);
    set(&mut h, 1, 6); // repeated: not executed again
    assert_eq!(h.adapter.device().data[&154], vec![5; 32]);
    assert_eq!(
        h.adapter
            .device()
            .writes
            .iter()
            .filter(|(i, _)| *i == 154)
            .count(),
        1
    );
    set(&mut h, 2, 6);
    assert_eq!(h.adapter.device().data[&154], vec![6; 32]);
    // The session ends: its Class 3 connection goes.
    h.adapter.tcp_close(SocketId(0), Instant(0));
    assert!(h.adapter.connections().is_empty());
}

#[test]
fn connection_manager_counts_requests_and_rejects() {
    let mut h = Harness::new();
    let path = io_path(None, 110, 100, None);
    assert_eq!(open(&mut h, &fo(1, &path, 10_000)).0, 0);
    assert_eq!(ext_of(&mut h, &fo(1, &path, 10_000)), (0x01, Some(0x0100)));
    assert_eq!(status(&h.request(0x54, &cm_path(), &[1, 2, 3])).0, 0x13);
    assert_eq!(close(&mut h, 9).0, 0x01);
    assert_eq!(close(&mut h, 1).0, 0);
    let all = [
        SegmentRepr::Logical(LogicalType::Class, 6),
        SegmentRepr::Logical(LogicalType::Instance, 1),
    ];
    let (g, _, d) = status(&h.request(0x01, &all, &[]));
    assert_eq!(g, 0);
    // open requests 3, format rejects 1, resource 0, other 1, close requests 2, 0, 1, timeouts 0
    assert_eq!(d, vec![3, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 0, 1, 0, 0, 0]);
}

#[test]
fn error_rpi_below_production_inhibit() {
    let mut h = Harness::new();
    // Change-of-state with a 20 ms inhibit time and a 10 ms RPI.
    let path = [&[0x43u8, 20][..], &io_path(None, 110, 100, None)].concat();
    let mut f = fo(1, &path, 10_000);
    f.transport = 0x11;
    assert_eq!(ext_of(&mut h, &f), (0x01, Some(0x011B)));
    f.t_o_rpi = 20_000;
    assert_eq!(open(&mut h, &f).0, 0);
}
