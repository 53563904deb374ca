//! Encapsulation over UDP 44818 from a raw socket in the namespace: ListIdentity unicast
//! (immediate) and to the subnet broadcast (delayed within the requested bound), ListServices,
//! ListInterfaces, and TCP-only commands answered with status 0x0001.

use std::io;
use std::net::{SocketAddr, SocketAddrV4, UdpSocket};
use std::time::{Duration, Instant};

use crate::common::{self, DEVICE_TYPE, NAME, PRODUCT_CODE, REVISION, SERIAL, STATUS, VENDOR};
use host_tests::enip::{
    command, mr_request, path, register_data, rr_data, ucmm_cpf, Frame, Header,
};
use host_tests::netns::Namespace;
use host_tests::rig::{board_addr, Rig, BOARD_IP, BROADCAST_IP, ENCAP_PORT, HOST_IP, NEIGHBOUR_IP};

/// Maximum reply delay asked for in the broadcast requests (sender context bytes 0-1).
const ASKED_DELAY_MS: u16 = 500;
/// Scheduling and transmission slack on top of a requested delay.
const SLACK: Duration = Duration::from_millis(400);

/// A UDP socket on the kernel side of the TAP, allowed to broadcast.
fn socket(ns: &Namespace) -> UdpSocket {
    ns.inside(|| -> io::Result<UdpSocket> {
        let s = UdpSocket::bind(SocketAddrV4::new(HOST_IP, 0))?;
        s.set_broadcast(true)?;
        Ok(s)
    })
    .and_then(|r| r)
    .expect("udp socket in the namespace")
}

/// Sends `frame` to `to` and waits up to `bound` for one reply; returns it, its sender and
/// how long it took.
fn ask(
    s: &UdpSocket,
    frame: &[u8],
    to: SocketAddr,
    bound: Duration,
) -> (Frame, SocketAddr, Duration) {
    let start = Instant::now();
    s.send_to(frame, to).expect("send");
    let mut buf = [0u8; 1500];
    let (n, from) = receive(s, &mut buf, bound)
        .unwrap_or_else(|e| panic!("no reply to {:02x?} within {bound:?}: {e}", &frame[..2]));
    let frame = Frame::parse(&buf[..n]).unwrap_or_else(|| panic!("bad reply {:02x?}", &buf[..n]));
    (frame, from, start.elapsed())
}

/// The next datagram within `bound`, passing over those of the other device of a fleet
/// (`ENIP_HOST_LINK=fleet`: it answers broadcasts too, as any device on the subnet would).
fn receive(s: &UdpSocket, buf: &mut [u8], bound: Duration) -> io::Result<(usize, SocketAddr)> {
    let deadline = Instant::now() + bound;
    loop {
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return Err(io::ErrorKind::TimedOut.into());
        }
        s.set_read_timeout(Some(left))?;
        let (n, from) = s.recv_from(buf)?;
        if from.ip() != NEIGHBOUR_IP {
            return Ok((n, from));
        }
    }
}

/// Asserts that nothing arrives on `s` for `wait`.
fn assert_silent(s: &UdpSocket, wait: Duration, what: &str) {
    let mut buf = [0u8; 1500];
    if let Ok((n, _)) = receive(s, &mut buf, wait) {
        panic!("{what}: unexpected reply {:02x?}", &buf[..n]);
    }
}

fn list_identity(context: [u8; 8]) -> Vec<u8> {
    Header {
        context,
        ..Header::new(command::LIST_IDENTITY)
    }
    .frame(&[])
}

/// Checks a ListIdentity reply to a request with `context`.
fn check_identity(reply: &Frame, context: [u8; 8]) {
    let h = reply.header;
    assert_eq!(
        (h.command, h.status, h.context),
        (command::LIST_IDENTITY, 0, context)
    );
    let d = &reply.data;
    assert_eq!(d[..4], [1, 0, 0x0C, 0], "one CIP identity item");
    let item = &d[6..];
    assert_eq!(usize::from(u16::from_le_bytes([d[4], d[5]])), item.len());
    let u16_at = |i: usize| u16::from_le_bytes([item[i], item[i + 1]]);
    assert_eq!(u16_at(0), 1, "encapsulation protocol version");
    assert_eq!(item[2..4], [0, 2], "sin_family AF_INET, big-endian");
    assert_eq!(item[4..6], ENCAP_PORT.to_be_bytes());
    assert_eq!(item[6..10], BOARD_IP.octets());
    assert_eq!(item[10..18], [0; 8]);
    assert_eq!(
        [u16_at(18), u16_at(20), u16_at(22), u16_at(26)],
        [VENDOR, DEVICE_TYPE, PRODUCT_CODE, STATUS]
    );
    assert_eq!(item[24..26], REVISION);
    assert_eq!(item[28..32], SERIAL.to_le_bytes());
    assert_eq!(usize::from(item[32]), NAME.len());
    assert_eq!(&item[33..33 + NAME.len()], NAME.as_bytes());
    assert_eq!(item.len(), 33 + NAME.len() + 1, "state byte last");
}

#[test]
#[ignore = "needs root and tshark"]
fn udp_list_identity_unicast_and_broadcast() {
    let rig = common::start("udp_list_identity_unicast_and_broadcast");
    let s = socket(rig.ns());
    let delay = ASKED_DELAY_MS.to_le_bytes();
    let unicast = [delay[0], delay[1], b'u', b'n', b'i', 0, 0, 1];
    let (reply, from, took) = ask(&s, &list_identity(unicast), board_addr(), SLACK);
    check_identity(&reply, unicast);
    assert_eq!(from, board_addr());
    assert!(took <= SLACK, "unicast reply is immediate: {took:?}");

    let bound = Duration::from_millis(u64::from(ASKED_DELAY_MS)) + SLACK;
    for round in 0..3u8 {
        let ctx = [delay[0], delay[1], b'b', b'c', b'a', b's', b't', round];
        let to = SocketAddr::from((BROADCAST_IP, ENCAP_PORT));
        let (reply, from, took) = ask(&s, &list_identity(ctx), to, bound);
        check_identity(&reply, ctx);
        assert_eq!(from, board_addr(), "reply from the board's own address");
        assert!(
            took <= bound,
            "broadcast reply within the asked delay: {took:?}"
        );
    }
    assert_silent(&s, Duration::from_millis(200), "after broadcasts");
    common::finish(rig);
}

#[test]
#[ignore = "needs root and tshark"]
fn udp_list_services_interfaces_and_tcp_only_commands() {
    let rig = common::start("udp_list_services_interfaces_and_tcp_only_commands");
    let s = socket(rig.ns());
    let ctx = *b"services";
    let req = Header {
        context: ctx,
        ..Header::new(command::LIST_SERVICES)
    };
    let (reply, _, _) = ask(&s, &req.frame(&[]), board_addr(), common::REPLY);
    assert_eq!((reply.header.status, reply.header.context), (0, ctx));
    let d = &reply.data;
    assert_eq!(
        d[..6],
        [1, 0, 0x00, 0x01, 20, 0],
        "one ListServices item of 20 bytes"
    );
    assert_eq!(u16::from_le_bytes([d[6], d[7]]), 1, "version");
    let flags = u16::from_le_bytes([d[8], d[9]]);
    assert_eq!(flags & 0x0020, 0x0020, "CIP over TCP");
    assert_eq!(&d[10..26], b"Communications\0\0");

    let (reply, _, _) = ask(
        &s,
        &Header::new(command::LIST_INTERFACES).frame(&[]),
        board_addr(),
        common::REPLY,
    );
    assert_eq!(
        (reply.header.status, reply.data.as_slice()),
        (0, &[0u8, 0][..]),
        "no interfaces"
    );

    for (cmd, data) in [
        (command::REGISTER_SESSION, register_data(1)),
        (command::SEND_RR_DATA, identity_rr_data()),
        (command::UNREGISTER_SESSION, vec![]),
    ] {
        let (reply, _, _) = ask(
            &s,
            &Header::new(cmd).frame(&data),
            board_addr(),
            common::REPLY,
        );
        assert_eq!(reply.header.command, cmd);
        assert_eq!(
            reply.header.status, 0x0001,
            "TCP-only command {cmd:#06x} over UDP"
        );
        assert!(reply.data.is_empty());
    }
    assert_silent_nop(&rig, &s);
    common::finish(rig);
}

/// SendRRData data of a well-formed Identity read.
fn identity_rr_data() -> Vec<u8> {
    rr_data(&ucmm_cpf(&mr_request(0x0E, &path(1, 1, Some(1)), &[])))
}

/// A NOP over UDP gets no reply.
fn assert_silent_nop(rig: &Rig, s: &UdpSocket) {
    s.send_to(&Header::new(command::NOP).frame(&[]), board_addr())
        .expect("send");
    assert_silent(s, Duration::from_millis(300), "NOP over UDP");
    common::assert_serving(rig.ns(), "UDP commands");
}
