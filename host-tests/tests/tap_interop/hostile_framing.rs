//! Hostile encapsulation framing and session misuse over raw TCP (and UDP): truncated and
//! lying headers, oversized lengths, non-zero options, unknown commands, bad session handles
//! and protocol versions. After each case a fresh client must be served within 1 s.

use std::net::{SocketAddrV4, UdpSocket};
use std::time::Duration;

use crate::common::{self, assert_serving, REPLY};
use host_tests::enip::{
    command, mr_request, path, register_data, rr_data, ucmm_cpf, Client, Header,
};
use host_tests::netns::Namespace;
use host_tests::rig::{board_addr, HOST_IP};

/// How long "no reply" is waited for.
const QUIET: Duration = Duration::from_millis(400);

fn connect(ns: &Namespace) -> Client {
    Client::connect(ns, REPLY).expect("connect")
}

fn registered(ns: &Namespace) -> Client {
    let mut c = connect(ns);
    c.register(REPLY).expect("register");
    c
}

/// Asserts nothing arrives on `c` for [`QUIET`] and the connection stays open.
#[track_caller]
fn assert_quiet(c: &mut Client, what: &str) {
    match c.recv(QUIET) {
        Err(e)
            if matches!(
                e.kind(),
                std::io::ErrorKind::TimedOut | std::io::ErrorKind::WouldBlock
            ) => {}
        other => panic!("{what}: expected no reply, got {other:?}"),
    }
}

/// A request on `c` still answered: its connection is usable.
#[track_caller]
fn assert_usable(c: &mut Client, what: &str) {
    let r = c
        .request(&mr_request(0x0E, &path(1, 1, Some(1)), &[]), REPLY)
        .unwrap_or_else(|e| panic!("{what}: connection no longer usable: {e}"));
    assert_eq!(r.general, 0, "{what}");
}

#[test]
#[ignore = "needs root and tshark"]
fn hostile_encapsulation_framing() {
    let rig = common::start("hostile_encapsulation_framing");
    let ns = rig.ns();

    // A truncated header, then close.
    let mut c = connect(ns);
    c.send(&Header::new(command::REGISTER_SESSION).bytes()[..10])
        .unwrap();
    drop(c);
    assert_serving(ns, "truncated header then close");

    // A length that claims more than was sent (within capacity): the adapter waits.
    let mut c = connect(ns);
    let lie = Header {
        length: 100,
        ..Header::new(command::REGISTER_SESSION)
    };
    c.send(&[lie.bytes(), register_data(1)].concat()).unwrap();
    assert_quiet(&mut c, "length claiming more than sent");
    assert_serving(ns, "a pending lying length");
    drop(c);
    assert_serving(ns, "lying length then close");

    // A length beyond the adapter's 1024-byte capacity: 0x0065, its data skipped as it
    // arrives, and the session goes on.
    for length in [1025u16, 0xFFFF] {
        let mut c = registered(ns);
        let big = Header {
            length,
            session: c.session,
            context: *b"too-long",
            ..Header::new(command::SEND_RR_DATA)
        };
        c.send(&[big.bytes(), vec![0; 64]].concat()).unwrap();
        let reply = c.recv(REPLY).expect("reply to an oversized length");
        assert_eq!(reply.header.status, 0x0065, "length {length}");
        assert_eq!(reply.header.context, *b"too-long");
        c.send(&vec![0x5A; usize::from(length) - 64]).unwrap();
        assert_usable(&mut c, "after an oversized length");
        drop(c);
        assert_serving(ns, "oversized length");
    }
    // A NOP beyond the capacity: never answered, at any length (Vol 2, 2-4.1).
    let mut c = registered(ns);
    c.send(&Header::new(command::NOP).frame(&[0x5A; 3000]))
        .unwrap();
    assert_quiet(&mut c, "NOP of 3000 bytes");
    assert_usable(&mut c, "after a NOP of 3000 bytes");
    drop(c);

    // Exactly the capacity (a NOP of 1024 data bytes) is accepted: no reply, still usable.
    let mut c = registered(ns);
    c.send(&Header::new(command::NOP).frame(&[0x5A; 1024]))
        .unwrap();
    assert_quiet(&mut c, "NOP of 1024 bytes");
    assert_usable(&mut c, "after a NOP of 1024 bytes");
    // A good frame and an oversized header in one segment: the first is answered, then 0x0065.
    let good = Header {
        session: c.session,
        ..Header::new(command::SEND_RR_DATA)
    }
    .frame(&rr_data(&ucmm_cpf(&mr_request(
        0x0E,
        &path(1, 1, Some(1)),
        &[],
    ))));
    let big = Header {
        length: 3000,
        ..Header::new(command::SEND_RR_DATA)
    }
    .bytes();
    c.send(&[good, big].concat()).unwrap();
    assert_eq!(c.recv(REPLY).expect("first of two").header.status, 0);
    assert_eq!(c.recv(REPLY).expect("second of two").header.status, 0x0065);
    c.send(&[0x5A; 3000]).unwrap();
    assert_usable(&mut c, "after the oversized one's data");
    drop(c);
    assert_serving(ns, "good frame then oversized header");

    // Non-zero options: the frame is discarded without reply; the connection stays usable.
    let mut c = connect(ns);
    let opts = Header {
        options: 1,
        ..Header::new(command::REGISTER_SESSION)
    };
    c.send(&opts.frame(&register_data(1))).unwrap();
    assert_quiet(&mut c, "non-zero options");
    c.register(REPLY).expect("register after a discarded frame");
    assert_usable(&mut c, "after non-zero options");
    drop(c);
    assert_serving(ns, "non-zero options");

    // An unknown command: 0x0001, connection kept.
    let mut c = registered(ns);
    let reply = c
        .exchange(
            Header {
                session: c.session,
                ..Header::new(0x00FF)
            },
            &[],
            REPLY,
        )
        .unwrap();
    assert_eq!(
        (reply.header.command, reply.header.status),
        (0x00FF, 0x0001)
    );
    assert_usable(&mut c, "after an unknown command");
    drop(c);
    assert_serving(ns, "unknown command");

    udp_framing(ns);
    common::finish_hostile(rig);
}

/// Over UDP, frames with non-zero options or a lying length are dropped without reply.
fn udp_framing(ns: &Namespace) {
    let s = ns
        .inside(|| UdpSocket::bind(SocketAddrV4::new(HOST_IP, 0)))
        .and_then(|r| r)
        .expect("udp socket");
    s.set_read_timeout(Some(QUIET)).unwrap();
    let options = Header {
        options: 2,
        ..Header::new(command::LIST_IDENTITY)
    }
    .frame(&[]);
    let lie = Header {
        length: 8,
        ..Header::new(command::LIST_IDENTITY)
    }
    .bytes();
    let short = Header::new(command::LIST_IDENTITY).bytes()[..20].to_vec();
    for (what, frame) in [
        ("options", options),
        ("lying length", lie),
        ("short header", short),
    ] {
        s.send_to(&frame, board_addr()).unwrap();
        let mut buf = [0u8; 1500];
        if let Ok((n, _)) = s.recv_from(&mut buf) {
            panic!("UDP {what}: unexpected reply {:02x?}", &buf[..n]);
        }
    }
    assert_serving(ns, "hostile UDP frames");
}

#[test]
#[ignore = "needs root and tshark"]
fn hostile_session_misuse() {
    let rig = common::start("hostile_session_misuse");
    let ns = rig.ns();
    let identity = mr_request(0x0E, &path(1, 1, Some(1)), &[]);
    let rr = rr_data(&ucmm_cpf(&identity));

    // SendRRData before RegisterSession.
    let mut c = connect(ns);
    let reply = c
        .exchange(
            Header {
                session: 0x1234_5678,
                ..Header::new(command::SEND_RR_DATA)
            },
            &rr,
            REPLY,
        )
        .unwrap();
    assert_eq!(reply.header.status, 0x0064, "SendRRData without a session");
    c.register(REPLY).expect("register after the refusal");
    assert_usable(&mut c, "after SendRRData without a session");
    drop(c);
    assert_serving(ns, "SendRRData before RegisterSession");

    // A wrong session handle on a registered connection.
    let mut c = registered(ns);
    let wrong = c.session.wrapping_add(0x100);
    let reply = c
        .exchange(
            Header {
                session: wrong,
                ..Header::new(command::SEND_RR_DATA)
            },
            &rr,
            REPLY,
        )
        .unwrap();
    assert_eq!(reply.header.status, 0x0064, "wrong session handle");
    assert_usable(&mut c, "after a wrong session handle");
    drop(c);
    assert_serving(ns, "wrong session handle");

    // An unsupported protocol version, then the right one on the same connection.
    let mut c = connect(ns);
    let reply = c
        .exchange(
            Header::new(command::REGISTER_SESSION),
            &register_data(2),
            REPLY,
        )
        .unwrap();
    assert_eq!(reply.header.status, 0x0069, "protocol version 2");
    assert_eq!(reply.header.session, 0, "no session granted");
    c.register(REPLY).expect("version 1 after version 2");
    drop(c);
    assert_serving(ns, "unsupported protocol version");

    // RegisterSession data of the wrong length.
    let mut c = connect(ns);
    let reply = c
        .exchange(Header::new(command::REGISTER_SESSION), &[1, 0], REPLY)
        .unwrap();
    assert_eq!(
        reply.header.status, 0x0065,
        "RegisterSession with 2 data bytes"
    );
    drop(c);
    assert_serving(ns, "short RegisterSession data");

    // UnregisterSession ends the connection.
    let mut c = registered(ns);
    c.send(
        &Header {
            session: c.session,
            ..Header::new(command::UNREGISTER_SESSION)
        }
        .frame(&[]),
    )
    .unwrap();
    assert!(
        c.closed_within(Duration::from_secs(3)).unwrap(),
        "closed after UnregisterSession"
    );
    drop(c);
    assert_serving(ns, "UnregisterSession");
    common::finish_hostile(rig);
}
