//! Electronic keys in explicit request paths, through the adapter's TCP entry point: a key
//! segment first in the path of a UCMM request, of the request inside an Unconnected_Send,
//! of a request over a Class 3 connection and of each Multiple_Service_Packet member is
//! checked against the Identity object like a Forward_Open's key; a mismatch is key failure
//! in path (0x25) with the part that failed (0x0114/0x0115/0x0116), and the request is not
//! executed. The device is vendor 1, device type 12, product 65001, revision 1.2.

mod common;

use common::*;
use enip_stack::wire::epath::{ElectronicKey, LogicalType, SegmentRepr};
use enip_stack::wire::forward_open::{ForwardOpenReplyRepr, NetworkParams};
use enip_stack::wire::Writer;

/// The device's own key, compatibility bit clear.
const EXACT: ElectronicKey = ElectronicKey {
    vendor_id: 1,
    device_type: 12,
    product_code: 65001,
    major_revision: 1,
    compatibility: false,
    minor_revision: 2,
};

/// Keys the device accepts, by name.
fn accepted() -> Vec<(&'static str, ElectronicKey)> {
    vec![
        ("exact", EXACT),
        (
            "all zero",
            ElectronicKey {
                vendor_id: 0,
                device_type: 0,
                product_code: 0,
                major_revision: 0,
                compatibility: false,
                minor_revision: 0,
            },
        ),
        (
            "compatible 1.1",
            ElectronicKey {
                compatibility: true,
                minor_revision: 1,
                ..EXACT
            },
        ),
    ]
}

/// Keys the device refuses, by name, with the extended status each must get.
fn refused() -> Vec<(&'static str, ElectronicKey, u16)> {
    vec![
        (
            "vendor",
            ElectronicKey {
                vendor_id: 2,
                ..EXACT
            },
            0x0114,
        ),
        (
            "product",
            ElectronicKey {
                product_code: 65000,
                ..EXACT
            },
            0x0114,
        ),
        (
            "device type",
            ElectronicKey {
                device_type: 7,
                ..EXACT
            },
            0x0115,
        ),
        (
            "major",
            ElectronicKey {
                major_revision: 2,
                ..EXACT
            },
            0x0116,
        ),
        (
            "compatible, newer minor",
            ElectronicKey {
                compatibility: true,
                minor_revision: 3,
                ..EXACT
            },
            0x0116,
        ),
        (
            "compatible, major 0",
            ElectronicKey {
                compatibility: true,
                major_revision: 0,
                ..EXACT
            },
            0x0116,
        ),
    ]
}

/// The path `key`, class, instance, attribute.
fn keyed(
    key: ElectronicKey,
    class: u32,
    instance: u32,
    attribute: u32,
) -> [SegmentRepr<'static>; 4] {
    [
        SegmentRepr::ElectronicKey(key),
        SegmentRepr::Logical(LogicalType::Class, class),
        SegmentRepr::Logical(LogicalType::Instance, instance),
        SegmentRepr::Logical(LogicalType::Attribute, attribute),
    ]
}

/// Message Router request bytes.
fn mr(service: u8, path: &[SegmentRepr<'_>], data: &[u8]) -> Vec<u8> {
    let mut buf = [0u8; 600];
    let mut w = Writer::new(&mut buf);
    enip_stack::originator::request(&mut w, service, path, data).unwrap();
    w.written().to_vec()
}

/// How a request reaches the Message Router.
#[derive(Debug, Clone, Copy)]
enum Via {
    Ucmm,
    UnconnectedSend,
    Class3 { o_t_id: u32 },
}

/// Opens a Class 3 connection to the Message Router; returns its O->T connection ID.
fn open_class3(h: &mut Harness, serial: u16) -> u32 {
    let path = [0x20, 0x02, 0x24, 0x01];
    let mut f = fo(serial, &path, 100_000);
    f.transport = 0xA3;
    f.o_t_params = NetworkParams::from_u16(0x4800 | 500);
    f.t_o_params = NetworkParams::from_u16(0x4800 | 500);
    let (g, _, data) = status(&h.forward_open(&f));
    assert_eq!(g, 0, "Class 3 Forward_Open");
    ForwardOpenReplyRepr::parse(&data)
        .unwrap()
        .o_t_connection_id
}

/// Sends `service` `path` `data` the way `via` says; returns general status, additional
/// status words and reply data.
fn send(
    h: &mut Harness,
    via: Via,
    seq: &mut u16,
    service: u8,
    path: &[SegmentRepr<'_>],
    data: &[u8],
) -> (u8, Vec<u16>, Vec<u8>) {
    match via {
        Via::Ucmm => status(&h.request(service, path, data)),
        Via::UnconnectedSend => {
            let inner = mr(service, path, data);
            let mut ucs = vec![0x0A, 0x0E];
            ucs.extend((inner.len() as u16).to_le_bytes());
            ucs.extend(&inner);
            if inner.len() % 2 == 1 {
                ucs.push(0);
            }
            ucs.extend([1, 0, 0x01, 0x00]);
            status(&h.request(0x52, &cm_path(), &ucs))
        }
        Via::Class3 { o_t_id } => {
            *seq = seq.wrapping_add(1);
            let mut buf = vec![0u8; 600];
            let n =
                enip_stack::originator::send_unit_data(&mut buf, h.session, o_t_id, *seq, |w| {
                    enip_stack::originator::request(w, service, path, data)
                })
                .unwrap();
            let reply = h.tcp(&buf[..n]);
            let r = enip_stack::originator::parse_reply(&reply).unwrap();
            assert!(r.connected.is_some(), "a connected reply");
            status(&reply)
        }
    }
}

/// Every rule through `via`: accepted keys read Identity attribute 7, refused ones get 0x25
/// with their part, and a refused Set_Attribute_Single changes nothing.
fn every_rule(via: impl Fn(&mut Harness) -> Via) {
    let mut h = Harness::new();
    let via = via(&mut h);
    let mut seq = 0u16;
    for (name, key) in accepted() {
        let got = send(&mut h, via, &mut seq, 0x0E, &keyed(key, 1, 1, 7), &[]);
        assert_eq!(
            got,
            (0, vec![], b"\x0btest device".to_vec()),
            "{via:?}: {name}"
        );
    }
    for (name, key, ext) in refused() {
        let got = send(&mut h, via, &mut seq, 0x0E, &keyed(key, 1, 1, 7), &[]);
        assert_eq!(got, (0x25, vec![ext], vec![]), "{via:?}: {name}");
    }
    // Not executed: a refused write leaves the assembly as it was; an accepted one writes.
    let before = h.adapter.device().data[&154].clone();
    let writes = h.adapter.device().writes.len();
    for (name, key, ext) in refused() {
        let got = send(
            &mut h,
            via,
            &mut seq,
            0x10,
            &keyed(key, 4, 154, 3),
            &[0xA5; 32],
        );
        assert_eq!(got.0, 0x25, "{via:?}: write with {name}");
        assert_eq!(got.1, vec![ext], "{via:?}: write with {name}");
    }
    assert_eq!(h.adapter.device().data[&154], before, "{via:?}");
    assert_eq!(h.adapter.device().writes.len(), writes, "{via:?}");
    let got = send(
        &mut h,
        via,
        &mut seq,
        0x10,
        &keyed(EXACT, 4, 154, 3),
        &[0x5A; 32],
    );
    assert_eq!(got.0, 0, "{via:?}: write with the exact key");
    assert_eq!(h.adapter.device().data[&154], vec![0x5A; 32], "{via:?}");
}

#[test]
fn ucmm_requests_check_the_key() {
    every_rule(|_| Via::Ucmm);
}

#[test]
fn requests_inside_unconnected_send_check_the_key() {
    every_rule(|_| Via::UnconnectedSend);
}

#[test]
fn class3_requests_check_the_key() {
    every_rule(|h| Via::Class3 {
        o_t_id: open_class3(h, 7),
    });
}

#[test]
fn each_multiple_service_packet_member_checks_its_key() {
    let mut h = Harness::new();
    let mut members: Vec<(Vec<u8>, u8, Vec<u16>)> = Vec::new();
    for (_, key) in accepted() {
        members.push((mr(0x0E, &keyed(key, 1, 1, 1), &[]), 0, vec![]));
    }
    for (_, key, ext) in refused() {
        members.push((mr(0x0E, &keyed(key, 1, 1, 1), &[]), 0x25, vec![ext]));
    }
    // A refused write inside the packet is not executed either.
    let before = h.adapter.device().data[&154].clone();
    members.push((
        mr(0x10, &keyed(refused()[0].1, 4, 154, 3), &[0xA5; 32]),
        0x25,
        vec![0x0114],
    ));
    let count = members.len();
    let mut data = (count as u16).to_le_bytes().to_vec();
    let mut offset = 2 + 2 * count;
    for (m, _, _) in &members {
        data.extend((offset as u16).to_le_bytes());
        offset += m.len();
    }
    for (m, _, _) in &members {
        data.extend(m);
    }
    let path = [
        SegmentRepr::Logical(LogicalType::Class, 2),
        SegmentRepr::Logical(LogicalType::Instance, 1),
    ];
    let (g, _, reply) = status(&h.request(0x0A, &path, &data));
    assert_eq!(g, 0x1E, "an embedded service failed");
    assert_eq!(u16::from_le_bytes([reply[0], reply[1]]) as usize, count);
    for (i, (_, general, words)) in members.iter().enumerate() {
        let at = usize::from(u16::from_le_bytes([reply[2 + 2 * i], reply[3 + 2 * i]]));
        let r = &reply[at..];
        let size = usize::from(r[3]);
        let got: Vec<u16> = (0..size)
            .map(|k| u16::from_le_bytes([r[4 + 2 * k], r[5 + 2 * k]]))
            .collect();
        assert_eq!((r[2], &got), (*general, words), "member {i}");
        if *general == 0 {
            // Vendor ID 1 read back.
            assert_eq!(&r[4..6], &[1, 0], "member {i}");
        }
    }
    assert_eq!(h.adapter.device().data[&154], before);
}

#[test]
fn a_key_on_the_unconnected_send_itself_is_checked_too() {
    let mut h = Harness::new();
    let inner = mr(0x0E, &keyed(EXACT, 1, 1, 7)[1..], &[]);
    let mut ucs = vec![0x0A, 0x0E, inner.len() as u8, 0];
    ucs.extend(&inner);
    ucs.extend([1, 0, 0x01, 0x00]);
    let cm = |key| {
        [
            SegmentRepr::ElectronicKey(key),
            SegmentRepr::Logical(LogicalType::Class, 6),
            SegmentRepr::Logical(LogicalType::Instance, 1),
        ]
    };
    let (g, _, d) = status(&h.request(0x52, &cm(EXACT), &ucs));
    assert_eq!((g, d.as_slice()), (0, &b"\x0btest device"[..]));
    let wrong = ElectronicKey {
        device_type: 7,
        ..EXACT
    };
    let (g, words, _) = status(&h.request(0x52, &cm(wrong), &ucs));
    assert_eq!((g, words), (0x25, vec![0x0115]));
}

#[test]
fn a_forward_open_request_path_key_is_0x25_and_its_connection_path_key_0x01() {
    let mut h = Harness::new();
    let wrong = ElectronicKey {
        product_code: 1,
        ..EXACT
    };
    // The key on the request path (to the Connection Manager): a key failure in path.
    let conn = io_path(None, 110, 100, None);
    let mut body = [0u8; 128];
    let mut w = Writer::new(&mut body);
    fo(1, &conn, 10_000).emit(&mut w).unwrap();
    let n = w.len();
    let request_path = [
        SegmentRepr::ElectronicKey(wrong),
        SegmentRepr::Logical(LogicalType::Class, 6),
        SegmentRepr::Logical(LogicalType::Instance, 1),
    ];
    let (g, words, _) = status(&h.request(0x54, &request_path, &body[..n]));
    assert_eq!((g, words), (0x25, vec![0x0114]));
    assert_eq!(h.adapter.connections().len(), 0, "no connection opened");
    // The same key in the connection path: the Connection Manager's connection failure.
    let mut key = [0u8; 16];
    let mut w = Writer::new(&mut key);
    SegmentRepr::ElectronicKey(wrong).emit(&mut w).unwrap();
    let keyed_conn = [w.written(), &conn[..]].concat();
    let (g, words, _) = status(&h.forward_open(&fo(2, &keyed_conn, 10_000)));
    assert_eq!((g, words), (0x01, vec![0x0114]));
}
