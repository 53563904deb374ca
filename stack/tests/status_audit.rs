//! The status audit: every malformed request is answered with the most specific general (and
//! extended) status CIP defines (Vol 1 appendix B, table 3-5.33), one case per rule and
//! object, sent as raw request bytes so nothing in the test's own encoder smooths them over.

mod common;

use common::*;
use enip_stack::config::MAX_MULTIPLE_SERVICES;
use enip_stack::originator;

/// Sends the raw Message Router request `req`; returns the general status and additional words.
fn raw(h: &mut Harness, req: &[u8]) -> (u8, Vec<u16>) {
    let mut buf = vec![0u8; FRAME];
    let n = originator::send_rr_data(&mut buf, h.session, None, |w| w.bytes(req)).unwrap();
    let (g, words, _) = status(&h.tcp(&buf[..n]));
    (g, words)
}

/// `service` to class/instance (one-byte logical segments), then `data`.
fn req(service: u8, class: u8, instance: u8, data: &[u8]) -> Vec<u8> {
    let mut r = vec![service, 2, 0x20, class, 0x24, instance];
    r.extend_from_slice(data);
    r
}

/// `service` to class/instance/attribute, then `data`.
fn req_attr(service: u8, class: u8, instance: u8, attribute: u8, data: &[u8]) -> Vec<u8> {
    let mut r = vec![service, 3, 0x20, class, 0x24, instance, 0x30, attribute];
    r.extend_from_slice(data);
    r
}

fn check(cases: &[(&str, Vec<u8>, u8, Option<u16>)]) {
    let mut h = Harness::new();
    for (what, request, general, ext) in cases {
        let (g, words) = raw(&mut h, request);
        assert_eq!(
            (g, words.first().copied()),
            (*general, *ext),
            "{what}: {request:02x?}"
        );
    }
}

#[test]
fn request_framing() {
    check(&[
        ("no path size byte", vec![0x0E], 0x13, None),
        (
            "path size beyond the request",
            vec![0x0E, 5, 0x20, 1],
            0x26,
            None,
        ),
        (
            "reserved logical format",
            vec![0x0E, 2, 0x23, 1, 0x24, 1],
            0x04,
            None,
        ),
        ("no class", vec![0x0E, 1, 0x24, 1], 0x04, None),
        ("unknown class", req(0x0E, 0x77, 1, &[]), 0x05, None),
    ]);
}

#[test]
fn attribute_services() {
    check(&[
        (
            "Get_Attribute_Single with data",
            req_attr(0x0E, 1, 1, 1, &[0]),
            0x15,
            None,
        ),
        (
            "Get_Attributes_All with data",
            req(0x01, 1, 1, &[0]),
            0x15,
            None,
        ),
        (
            "Set_Attribute_Single short",
            req_attr(0x10, 0xF5, 1, 13, &[1]),
            0x13,
            None,
        ),
        (
            "Set_Attribute_Single long",
            req_attr(0x10, 0xF5, 1, 13, &[1, 0, 0]),
            0x15,
            None,
        ),
        (
            "Set of a read-only attribute",
            req_attr(0x10, 1, 1, 1, &[1, 0]),
            0x0E,
            None,
        ),
        (
            "unknown attribute",
            req_attr(0x0E, 1, 1, 99, &[]),
            0x14,
            None,
        ),
        ("unknown instance", req_attr(0x0E, 1, 9, 1, &[]), 0x16, None),
        ("service the object lacks", req(0x4B, 1, 1, &[]), 0x08, None),
    ]);
}

#[test]
fn attribute_lists() {
    let mut too_many = (MAX_MULTIPLE_SERVICES as u16 + 1).to_le_bytes().to_vec();
    for _ in 0..=MAX_MULTIPLE_SERVICES {
        too_many.extend_from_slice(&[1, 0]);
    }
    check(&[
        (
            "Get_Attribute_List without a count",
            req(0x03, 1, 1, &[3]),
            0x13,
            None,
        ),
        (
            "Get_Attribute_List count beyond its IDs",
            req(0x03, 1, 1, &[3, 0, 1, 0]),
            0x13,
            None,
        ),
        (
            "Get_Attribute_List bytes after its IDs",
            req(0x03, 1, 1, &[1, 0, 1, 0, 0]),
            0x15,
            None,
        ),
        (
            "Get_Attribute_List more than a reply can carry",
            req(0x03, 1, 1, &too_many),
            0x02,
            None,
        ),
        (
            "Set_Attribute_List count beyond its IDs",
            req(0x04, 0xF5, 1, &[2, 0, 13, 0]),
            0x13,
            None,
        ),
    ]);
}

#[test]
fn multiple_service_packet() {
    let get = [0x0E, 3, 0x20, 1, 0x24, 1, 0x30, 1];
    let with = |head: &[u8]| {
        let mut d = head.to_vec();
        d.extend_from_slice(&get);
        req(0x0A, 2, 1, &d)
    };
    let mut too_many = (MAX_MULTIPLE_SERVICES as u16 + 1).to_le_bytes().to_vec();
    for i in 0..=MAX_MULTIPLE_SERVICES {
        too_many.extend_from_slice(&(2 + 2 * (MAX_MULTIPLE_SERVICES + 1) + i).to_le_bytes()[..2]);
    }
    check(&[
        ("no count", req(0x0A, 2, 1, &[]), 0x13, None),
        ("count 0", req(0x0A, 2, 1, &[0, 0]), 0x20, None),
        (
            "count beyond the offset table",
            with(&[3, 0, 4, 0]),
            0x13,
            None,
        ),
        (
            "more services than one request may carry",
            req(0x0A, 2, 1, &too_many),
            0x02,
            None,
        ),
        ("offset beyond the data", with(&[1, 0, 40, 0]), 0x13, None),
        (
            "offset into the offset table",
            with(&[1, 0, 2, 0]),
            0x20,
            None,
        ),
        (
            "offsets not increasing",
            with(&[2, 0, 6, 0, 6, 0]),
            0x20,
            None,
        ),
    ]);
}

#[test]
fn unconnected_send() {
    let inner = [0x0E, 3, 0x20, 1, 0x24, 1, 0x30, 1];
    let send = |head: &[u8], tail: &[u8]| {
        let mut d = vec![0x52, 2, 0x20, 6, 0x24, 1, 0x0A, 0x0E];
        d.extend_from_slice(head);
        d.extend_from_slice(&inner);
        d.extend_from_slice(tail);
        d
    };
    let len = [inner.len() as u8, 0];
    check(&[
        (
            "no instance",
            vec![0x52, 1, 0x20, 6, 0x0A, 0x0E],
            0x05,
            None,
        ),
        ("instance 2", req(0x52, 6, 2, &[0x0A, 0x0E]), 0x16, None),
        // Like Forward_Open and Forward_Close, an instance service: not the class's.
        ("the class", req(0x52, 6, 0, &[0x0A, 0x0E]), 0x08, None),
        (
            "embedded length beyond the data",
            send(&[40, 0], &[]),
            0x13,
            None,
        ),
        ("no route path", send(&len, &[]), 0x13, None),
        (
            "bytes after the route path",
            send(&len, &[1, 0, 1, 0, 0]),
            0x15,
            None,
        ),
        (
            "route to another port",
            send(&len, &[1, 0, 2, 0]),
            0x01,
            Some(0x0311),
        ),
        (
            "route to another link",
            send(&len, &[1, 0, 1, 5]),
            0x01,
            Some(0x0312),
        ),
    ]);
}

#[test]
fn identity_reset() {
    check(&[
        ("Reset type 5", req(0x05, 1, 1, &[5]), 0x20, None),
        ("Reset with two bytes", req(0x05, 1, 1, &[0, 0]), 0x15, None),
    ]);
}

#[test]
fn ethernet_link_get_and_clear() {
    check(&[
        (
            "Get_and_Clear of a non-counter attribute",
            req_attr(0x4C, 0xF6, 1, 1, &[]),
            0x2E,
            None,
        ),
        (
            "Get_and_Clear without an attribute",
            req(0x4C, 0xF6, 1, &[]),
            0x05,
            None,
        ),
    ]);
}

#[test]
fn forward_open_and_close() {
    let mut h = Harness::new();
    let mut data = [0u8; 128];
    let mut w = enip_stack::wire::Writer::new(&mut data);
    let path = io_path(None, 110, 100, None);
    fo(1, &path, 10_000).emit(&mut w).unwrap();
    let n = w.len();
    let cut = req(0x54, 6, 1, &data[..n - 3]);
    assert_eq!(raw(&mut h, &cut), (0x13, vec![]), "Forward_Open cut short");
    let long = req(0x54, 6, 1, &[&data[..n], &[0, 0]].concat());
    assert_eq!(
        raw(&mut h, &long),
        (0x15, vec![]),
        "Forward_Open with extra bytes"
    );
    assert_eq!(
        raw(&mut h, &req(0x4E, 6, 1, &[0x0A, 0x0E, 1, 0])),
        (0x13, vec![]),
        "Forward_Close cut short"
    );
    // Application paths naming assemblies the device does not have at all.
    let ext = |h: &mut Harness, path: &[u8]| {
        let (g, words, _) = status(&h.forward_open(&fo(2, path, 10_000)));
        (g, words.first().copied())
    };
    assert_eq!(
        ext(&mut h, &io_path(Some(199), 110, 100, None)),
        (0x01, Some(0x0129)),
        "configuration assembly that does not exist"
    );
    assert_eq!(
        ext(&mut h, &io_path(None, 199, 100, None)),
        (0x01, Some(0x012A)),
        "consuming assembly that does not exist"
    );
    assert_eq!(
        ext(&mut h, &io_path(None, 110, 199, None)),
        (0x01, Some(0x012B)),
        "producing assembly that does not exist"
    );
}
