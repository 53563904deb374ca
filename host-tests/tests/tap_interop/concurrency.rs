//! Clients that compete for the adapter's three TCP sockets: a slow client holding half a
//! header must not block anyone, and a 4th and 5th client while three are connected are
//! refused or closed cleanly while the three keep being served.

use std::io::ErrorKind;
use std::net::TcpStream;
use std::time::{Duration, Instant};

use crate::common::{self, assert_serving, REPLY};
use host_tests::enip::{
    command, mr_request, path, register_data, rr_data, ucmm_cpf, Client, Header,
};
use host_tests::netns::Namespace;
use host_tests::rig::board_addr;

/// Bound for a surplus client to be refused or closed.
const REFUSAL: Duration = Duration::from_secs(3);

#[test]
#[ignore = "needs root and tshark"]
fn slow_client_does_not_block_others() {
    let rig = common::start("slow_client_does_not_block_others");
    let ns = rig.ns();
    let mut slow = Client::connect(ns, REPLY).expect("connect");
    let frame = Header::new(command::REGISTER_SESSION).frame(&register_data(1));
    slow.send(&frame[..12]).unwrap();
    for round in 0..3 {
        assert_serving(ns, &format!("half a header held (round {round})"));
    }
    // The held frame completes normally once the rest arrives.
    slow.send(&frame[12..]).unwrap();
    let reply = slow.recv(REPLY).expect("reply to the completed frame");
    assert_eq!(
        reply.header.status, 0,
        "RegisterSession split over a long pause"
    );
    // One frame delivered a byte per segment.
    let identity = mr_request(0x0E, &path(1, 1, Some(1)), &[]);
    let session = Header {
        session: reply.header.session,
        ..Header::new(command::SEND_RR_DATA)
    };
    for b in session.frame(&rr_data(&ucmm_cpf(&identity))) {
        slow.send(&[b]).unwrap();
        std::thread::sleep(Duration::from_millis(2));
    }
    let reply = slow
        .recv(REPLY)
        .expect("reply to a frame sent byte by byte");
    assert_eq!(reply.header.status, 0, "frame sent byte by byte");
    drop(slow);
    assert_serving(ns, "slow client finished");
    common::finish(rig);
}

/// Connects a surplus client and asserts it is refused, or accepted and closed, in time.
fn assert_refused(ns: &Namespace, which: &str) -> Option<TcpStream> {
    let start = Instant::now();
    match ns
        .inside(|| TcpStream::connect_timeout(&board_addr(), REFUSAL))
        .expect("thread")
    {
        Err(e) if e.kind() == ErrorKind::ConnectionRefused => None,
        Err(e) => panic!("{which} client: neither accepted nor refused cleanly: {e}"),
        Ok(stream) => {
            let mut c = Client::from_stream(stream.try_clone().expect("clone"));
            let left = REFUSAL.saturating_sub(start.elapsed());
            let closed = c.closed_within(left).expect("read");
            assert!(closed, "{which} client accepted and left open");
            Some(stream)
        }
    }
}

#[test]
#[ignore = "needs root and tshark"]
fn fourth_and_fifth_clients_are_refused() {
    let rig = common::start("fourth_and_fifth_clients_are_refused");
    let ns = rig.ns();
    let mut three: Vec<Client> = (0..3)
        .map(|i| {
            let mut c = Client::connect(ns, REPLY).unwrap_or_else(|e| panic!("client {i}: {e}"));
            c.register(REPLY)
                .unwrap_or_else(|e| panic!("client {i}: {e}"));
            c
        })
        .collect();
    let fourth = assert_refused(ns, "4th");
    let fifth = assert_refused(ns, "5th");
    let identity = mr_request(0x0E, &path(1, 1, Some(7)), &[]);
    for (i, c) in three.iter_mut().enumerate() {
        let r = c
            .request(&identity, REPLY)
            .unwrap_or_else(|e| panic!("client {i} after refusals: {e}"));
        assert_eq!(r.general, 0, "client {i}");
    }
    drop((fourth, fifth));
    three.pop();
    // The freed socket listens again once the board has closed its side.
    std::thread::sleep(Duration::from_millis(200));
    assert_serving(ns, "one of three clients left");
    drop(three);
    common::finish_hostile(rig);
}
