//! Hostile SendRRData contents over a registered session: broken Common Packet Format
//! (item counts, item lengths, prefix), and odd or oversized EPATHs and route paths. Each
//! case checks the exact status, that the session is still usable, and that a fresh client
//! is served within 1 s.

use crate::common::{self, assert_serving, REPLY};
use host_tests::enip::{command, mr_request, path, rr_data, Client, Header, MrReply};
use host_tests::netns::Namespace;

/// Sends SendRRData with `data` on `c` and returns the encapsulation status.
fn rr_status(c: &mut Client, data: &[u8]) -> u32 {
    let h = Header {
        session: c.session,
        ..Header::new(command::SEND_RR_DATA)
    };
    let reply = c.exchange(h, data, REPLY).expect("SendRRData reply");
    reply.header.status
}

/// Sends the Message Router request `mr` on `c` and returns its reply.
fn mr(c: &mut Client, mr: &[u8]) -> MrReply {
    c.request(mr, REPLY)
        .unwrap_or_else(|e| panic!("request {mr:02x?}: {e}"))
}

/// The session still answers, and a fresh client is served.
#[track_caller]
fn after(ns: &Namespace, c: &mut Client, case: &str) {
    let r = mr(c, &mr_request(0x0E, &path(1, 1, Some(1)), &[]));
    assert_eq!(r.general, 0, "session unusable after {case}");
    assert_serving(ns, case);
}

/// An unconnected data item carrying `mr`, as raw CPF bytes with `count` items claimed.
fn cpf(count: u16, items: &[(u16, u16, &[u8])]) -> Vec<u8> {
    let mut c = count.to_le_bytes().to_vec();
    for (ty, len, data) in items {
        c.extend_from_slice(&ty.to_le_bytes());
        c.extend_from_slice(&len.to_le_bytes());
        c.extend_from_slice(data);
    }
    c
}

#[test]
#[ignore = "needs root and tshark"]
fn hostile_common_packet_format() {
    let rig = common::start("hostile_common_packet_format");
    let ns = rig.ns();
    let mut c = Client::connect(ns, REPLY).expect("connect");
    c.register(REPLY).expect("register");
    let get = mr_request(0x0E, &path(1, 1, Some(1)), &[]);
    let len = get.len() as u16;
    let cases: [(&str, Vec<u8>, u32); 8] = [
        (
            "count 3, two items",
            rr_data(&cpf(3, &[(0, 0, &[]), (0xB2, len, &get)])),
            0x0003,
        ),
        (
            "count 1, address only",
            rr_data(&cpf(1, &[(0, 0, &[])])),
            0x0003,
        ),
        ("count 0", rr_data(&cpf(0, &[])), 0x0003),
        (
            "count 200",
            rr_data(&cpf(200, &[(0, 0, &[]), (0xB2, len, &get)])),
            0x0003,
        ),
        (
            "item length beyond data",
            rr_data(&cpf(2, &[(0, 0, &[]), (0xB2, 50, &get)])),
            0x0003,
        ),
        (
            "empty unconnected item",
            rr_data(&cpf(2, &[(0, 0, &[]), (0xB2, 0, &[])])),
            0x0003,
        ),
        (
            "null address with data",
            rr_data(&cpf(2, &[(0, 2, &[0, 0]), (0xB2, len, &get)])),
            0x0003,
        ),
        ("prefix shorter than 6 bytes", vec![0, 0, 0], 0x0065),
    ];
    for (case, data, status) in cases {
        assert_eq!(rr_status(&mut c, &data), status, "{case}");
        after(ns, &mut c, case);
    }
    let mut handle = rr_data(&cpf(2, &[(0, 0, &[]), (0xB2, len, &get)]));
    handle[0] = 1;
    assert_eq!(
        rr_status(&mut c, &handle),
        0x0003,
        "non-zero interface handle"
    );
    after(ns, &mut c, "non-zero interface handle");
    common::finish_hostile(rig);
}

/// An Unconnected_Send to the Connection Manager of `inner` with `route`.
fn unconnected_send(inner: &[u8], route: &[u8]) -> Vec<u8> {
    let mut d = vec![0x0A, 0xF0];
    d.extend_from_slice(&(inner.len() as u16).to_le_bytes());
    d.extend_from_slice(inner);
    if inner.len() % 2 == 1 {
        d.push(0);
    }
    d.extend_from_slice(&[(route.len() / 2) as u8, 0]);
    d.extend_from_slice(route);
    mr_request(0x52, &path(6, 1, None), &d)
}

#[test]
#[ignore = "needs root and tshark"]
fn hostile_epaths() {
    let rig = common::start("hostile_epaths");
    let ns = rig.ns();
    let mut c = Client::connect(ns, REPLY).expect("connect");
    c.register(REPLY).expect("register");
    let forty: Vec<u8> = (0..40).flat_map(|_| [0x20, 0x01]).collect();
    let cases: [(&str, Vec<u8>, u8); 7] = [
        (
            "path size beyond the request",
            vec![0x0E, 10, 0x20, 0x01, 0x24, 0x01],
            0x26,
        ),
        (
            "reserved logical format",
            vec![0x0E, 3, 0x23, 0x01, 0x24, 0x01, 0x30, 0x01],
            0x04,
        ),
        ("40 segments", mr_request(0x0E, &forty, &[]), 0x04),
        ("empty path", vec![0x0E, 0], 0x04),
        ("16-bit class cut short", vec![0x0E, 1, 0x21, 0x00], 0x04),
        ("service byte only", vec![0x0E], 0x13),
        (
            "port segment in a request path",
            mr_request(0x0E, &[0x01, 0x00, 0x20, 0x01], &[]),
            0x04,
        ),
    ];
    for (case, request, general) in cases {
        let r = mr(&mut c, &request);
        assert_eq!(r.general, general, "{case}: {r:?}");
        assert_eq!(r.service, request[0] | 0x80, "{case}");
        after(ns, &mut c, case);
    }
    let inner = mr_request(0x0E, &path(1, 1, Some(7)), &[]);
    let routes: [(&str, &[u8], u8, &[u16]); 4] = [
        ("route port 1 link 0", &[0x01, 0x00], 0x00, &[]),
        ("route to port 2", &[0x02, 0x00], 0x01, &[0x0311]),
        ("route to link 5", &[0x01, 0x05], 0x01, &[0x0312]),
        ("route of a logical segment", &[0x20, 0x01], 0x01, &[0x0315]),
    ];
    for (case, route, general, additional) in routes {
        let r = mr(&mut c, &unconnected_send(&inner, route));
        assert_eq!(
            (r.general, r.additional.as_slice()),
            (general, additional),
            "{case}: {r:?}"
        );
        after(ns, &mut c, case);
    }
    common::finish_hostile(rig);
}
