//! The server against the peers RFC 9293 and RFC 1122 name that a probe of the TAP board
//! found mishandled: handshakes completing late (from their SYN cookies), peers silent or
//! stalled while replies wait, windows too small for the replies, and pipelined requests
//! whose replies outgrow the room (they wait, acknowledged, in the window offered).

extern crate std;

use std::vec::Vec;

use super::tests::{
    connect, drain, ms, peer, probed, seg, with_window, Echo, Event, Server, ACK, FIN_ACK, FRAME,
    RST, SYN,
};
use super::*;

/// The SYN-ACK answering a SYN from port 5000 (sequence 100) at 0 ms, whose half-open
/// connection then lapses.
fn lapsed_syn_ack(s: &mut Server, app: &mut Echo) -> Outgoing {
    s.process(&seg(peer(5000), 100, 0, SYN, &[]), ms(0), app);
    let syn_ack = drain(s, ms(0))[0].0;
    s.poll(ms(0).add(HALF_OPEN), app);
    syn_ack
}

/// Runs the server's timers from `now` until it sends a RST (at most `rounds` deadlines);
/// returns when, and the RST.
fn until_reset(
    s: &mut Server,
    app: &mut Echo,
    mut now: Instant,
    rounds: usize,
) -> (Instant, Outgoing) {
    for _ in 0..rounds {
        let Some(at) = s.deadline(app) else { break };
        now = at;
        s.poll(now, app);
        if let Some((rst, _)) = drain(s, now).into_iter().find(|(o, _)| o.flags.rst) {
            return (now, rst);
        }
    }
    panic!("no reset by {now:?}");
}

#[test]
fn a_peer_that_sends_nothing_for_the_give_up_time_is_reset_not_before() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    s.process(&seg(peer(5000), 101, iss, ACK, b"abcd"), ms(2), &mut app);
    drain(&mut s, ms(2));
    // Retransmitted at 1, 3, 7, 15, 31 and 63 s (the timeout doubling), then given up: a
    // link down for a minute ends no session.
    let (at, rst) = until_reset(&mut s, &mut app, ms(2), 10);
    assert_eq!(at, ms(2).add(GIVE_UP));
    assert!(GIVE_UP >= Duration::from_secs(100), "RFC 1122 4.2.3.5");
    assert_eq!(rst.seq, iss + 4, "after what was sent");
    assert_eq!(app.events.last(), Some(&Event::Closed(0)));
    assert_eq!(s.deadline(&app), None);
}

#[test]
fn a_peer_that_answers_probes_of_a_closed_window_is_reset_after_the_write_timeout() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    let closed = |seq, now, s: &mut Server, app: &mut Echo| {
        let ack = with_window(0, seg(peer(5000), seq, iss, ACK, &[]));
        s.process(&ack, now, app);
    };
    let request = with_window(0, seg(peer(5000), 101, iss, ACK, b"abcd"));
    s.process(&request, ms(2), &mut app);
    drain(&mut s, ms(2));
    // Every probe answered, the window still closed: a client that stopped reading.
    let mut reset = None;
    for _ in 0..10 {
        let at = s.deadline(&app).expect("a probe or the reset");
        assert!(at <= ms(2).add(WRITE_TIMEOUT), "{at:?}");
        s.poll(at, &mut app);
        let sent = drain(&mut s, at);
        if let Some((rst, _)) = sent.iter().find(|(o, _)| o.flags.rst) {
            reset = Some((at, *rst));
            break;
        }
        assert_eq!(sent[0].1, b"a", "a probe");
        closed(105, at, &mut s, &mut app);
    }
    let (now, rst) = reset.expect("a reset");
    assert_eq!(now, ms(2).add(WRITE_TIMEOUT));
    // At the byte the closed window waits for, not past the probe's: the peer takes it.
    assert_eq!(rst.seq, iss);
    assert_eq!(app.events.last(), Some(&Event::Closed(0)));
}

#[test]
fn a_new_client_takes_the_place_of_a_peer_silent_for_the_write_timeout() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let quiet = connect(&mut s, &mut app, peer(5000), 100);
    connect(&mut s, &mut app, peer(5001), 200);
    // Both taken; the first peer's reply waits, unacknowledged.
    s.process(&seg(peer(5000), 101, quiet, ACK, b"abcd"), ms(2), &mut app);
    drain(&mut s, ms(2));
    let syn = seg(peer(6000), 300, 0, SYN, &[]);
    let refused = s.process(&syn, ms(2).add(Duration::from_secs(4)), &mut app);
    assert!(
        refused.is_some_and(|o| o.flags.rst),
        "not silent long enough"
    );
    let now = ms(2).add(WRITE_TIMEOUT);
    let cookie = s.process(&syn, now, &mut app).expect("a SYN-ACK");
    assert!(cookie.flags.syn && cookie.flags.ack);
    assert_eq!(
        app.events.len(),
        3,
        "a SYN evicts nothing (its source may be forged)"
    );
    // The client proves its address: the silent peer is reset for it, and its first
    // segment dropped (no RST: the client is in).
    let request = seg(peer(6000), 301, cookie.seq.wrapping_add(1), ACK, b"wxyz");
    assert_eq!(s.process(&request, now, &mut app), None);
    assert_eq!(app.events.last(), Some(&Event::Closed(0)), "the silent one");
    let sent = drain(&mut s, now);
    assert!(sent
        .iter()
        .any(|(o, _)| o.flags.rst && o.peer == peer(5000)));
    // Its request again (retransmitted) proves the cookie again and finds the place.
    assert_eq!(s.process(&request, now, &mut app), None);
    assert_eq!(
        app.events[app.events.len() - 2..],
        [
            Event::Accepted(0, peer(6000)),
            Event::Received(0, b"wxyz".to_vec())
        ]
    );
}

#[test]
fn a_syn_flood_evicts_no_silent_peer_and_answers_do_not_make_one_stale() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let alive = connect(&mut s, &mut app, peer(5000), 100);
    let quiet = connect(&mut s, &mut app, peer(5001), 200);
    for (from, seq, ack) in [(peer(5000), 101, alive), (peer(5001), 201, quiet)] {
        s.process(&seg(from, seq, ack, ACK, b"abcd"), ms(2), &mut app);
    }
    drain(&mut s, ms(2));
    // The first peer's replies are lost, but it keeps talking (duplicate ACKs): it is
    // heard, so never stale.
    for k in 1..=6u64 {
        let at = ms(2).add(Duration::from_secs(k));
        s.process(&seg(peer(5000), 105, alive, ACK, &[]), at, &mut app);
        s.poll(at, &mut app);
        drain(&mut s, at);
    }
    let now = ms(2).add(Duration::from_secs(6));
    // Forged SYNs: cookies, and nobody reset.
    for port in 7000..7010 {
        let answer = s.process(&seg(peer(port), 1, 0, SYN, &[]), now, &mut app);
        assert!(answer.is_some_and(|o| o.flags.syn && o.flags.ack));
    }
    assert_eq!(app.events.len(), 4, "{:?}", app.events);
    // A proven client takes the silent peer's place, not the one still talking.
    let syn = seg(peer(6000), 300, 0, SYN, &[]);
    let cookie = s.process(&syn, now, &mut app).expect("a SYN-ACK");
    let request = seg(peer(6000), 301, cookie.seq.wrapping_add(1), ACK, b"wxyz");
    s.process(&request, now, &mut app);
    assert_eq!(app.events.last(), Some(&Event::Closed(1)));
}

#[test]
fn a_late_ack_of_an_earlier_syn_ack_reopens_the_handshake_from_its_cookie() {
    // The SYN-ACK reached the client late: its SYN was sent again after the half-open
    // connection lapsed, in the cookie clock's next tick, and a new half-open connection
    // answered it with another cookie; then the client's ACK of the first comes.
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let first = lapsed_syn_ack(&mut s, &mut app);
    s.process(&seg(peer(5000), 100, 0, SYN, &[]), ms(4_300), &mut app);
    let second = drain(&mut s, ms(4_300))[0].0;
    assert_ne!(first.seq, second.seq, "another tick, another cookie");
    let late = seg(peer(5000), 101, first.seq.wrapping_add(1), ACK, b"abcd");
    assert_eq!(s.process(&late, ms(4_400), &mut app), None, "no RST");
    assert_eq!(
        app.events,
        [
            Event::Accepted(0, peer(5000)),
            Event::Received(0, b"abcd".to_vec())
        ]
    );
    let sent = drain(&mut s, ms(4_400));
    assert_eq!(sent[0].0.seq, first.seq.wrapping_add(1));
}

#[test]
fn replies_held_in_flight_when_the_window_closes_are_probed() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    s.process(
        &seg(peer(5000), 101, iss, ACK, b"abcdefgh"),
        ms(2),
        &mut app,
    );
    assert_eq!(drain(&mut s, ms(2)).len(), 1, "all 8 bytes in flight");
    // A duplicate ACK closes the window: at the timeout the window is probed (the flight
    // rewound first), not left waiting for the write timeout.
    let closed = with_window(0, seg(peer(5000), 109, iss, ACK, &[]));
    s.process(&closed, ms(3), &mut app);
    assert_eq!(probed(&mut s, &mut app), b"a");
}

#[test]
fn half_the_largest_window_offered_is_no_silly_window() {
    // A peer whose window was never more than 8 bytes: 4 of 8 bytes of reply go at once.
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let small = |seq, ack, flags, payload, window| {
        with_window(window, seg(peer(5000), seq, ack, flags, payload))
    };
    s.process(&small(100, 0, SYN, &[], 8), ms(0), &mut app);
    let next = drain(&mut s, ms(0))[0].0.seq.wrapping_add(1);
    s.process(&small(101, next, ACK, &[], 8), ms(1), &mut app);
    s.process(&small(101, next, ACK, b"abcdefgh", 4), ms(2), &mut app);
    let sent = drain(&mut s, ms(2));
    assert_eq!(sent.iter().map(|(_, d)| d.len()).sum::<usize>(), 4);
}

#[test]
fn a_stray_copy_of_a_completed_handshakes_ack_opens_nothing() {
    // Every initial sequence number is a cookie, but a cookie is taken from an ACK of no
    // connection only after its SYN-ACK went alone or its half-open connection lapsed: a
    // duplicate of the handshake's ACK arriving after the connection closed is refused.
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    s.process(&seg(peer(5000), 101, iss, FIN_ACK, &[]), ms(2), &mut app);
    drain(&mut s, ms(2));
    s.process(&seg(peer(5000), 102, iss + 1, ACK, &[]), ms(3), &mut app);
    assert_eq!(s.deadline(&app), None, "free again");
    let stray = seg(peer(5000), 101, iss, ACK, &[]);
    let answer = s.process(&stray, ms(4), &mut app);
    assert!(answer.is_some_and(|o| o.flags.rst), "{answer:?}");
    assert_eq!(s.deadline(&app), None, "no connection opened");
    assert_eq!(
        app.events,
        [Event::Accepted(0, peer(5000)), Event::Closed(0)]
    );
}

#[test]
fn an_ack_of_another_syn_ack_is_reset_and_the_handshake_goes_on() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    s.process(&seg(peer(5000), 100, 0, SYN, &[]), ms(0), &mut app);
    let syn_ack = drain(&mut s, ms(0))[0].0;
    let next = syn_ack.seq.wrapping_add(1);
    let stale = seg(peer(5000), 101, next.wrapping_add(1000), ACK, &[]);
    let rst = s.process(&stale, ms(1), &mut app).expect("a RST");
    assert_eq!((rst.flags, rst.seq), (RST, next.wrapping_add(1000)));
    assert!(app.events.is_empty());
    s.process(&seg(peer(5000), 101, next, ACK, &[]), ms(2), &mut app);
    assert_eq!(app.events, [Event::Accepted(0, peer(5000))]);
}

#[test]
fn a_handshake_completes_from_its_cookie_after_the_half_open_connection_was_dropped() {
    // A client 400 ms away: its ACK, with its first request, comes after the bound.
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let syn_ack = lapsed_syn_ack(&mut s, &mut app);
    assert_eq!(s.deadline(&app), None, "dropped");
    let next = syn_ack.seq.wrapping_add(1);
    let late = ms(400);
    let request = seg(peer(5000), 101, next, ACK, b"abcd");
    assert_eq!(s.process(&request, late, &mut app), None, "no RST");
    assert_eq!(
        app.events,
        [
            Event::Accepted(0, peer(5000)),
            Event::Received(0, b"abcd".to_vec())
        ]
    );
    let sent = drain(&mut s, late);
    assert_eq!((sent[0].0.seq, sent[0].0.ack), (next, 105));
    assert_eq!(sent[0].1, b"abcd");
    // An ACK naming another sequence number proves nothing: refused.
    let forged = seg(peer(5001), 101, next, ACK, &[]);
    assert!(s
        .process(&forged, late, &mut app)
        .is_some_and(|o| o.flags.rst));
}

#[test]
fn a_silly_window_waits_and_one_of_half_the_largest_offered_is_used() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    // The window offered shrinks to 3 bytes: a 4-byte reply does not go 3 bytes at once
    // (RFC 9293 3.8.6.2.1).
    let tiny = with_window(3, seg(peer(5000), 101, iss, ACK, b"abcd"));
    s.process(&tiny, ms(2), &mut app);
    assert!(drain(&mut s, ms(2)).iter().all(|(_, d)| d.is_empty()));
    assert!(!s.owes(), "nothing owed while it waits");
    // A window that takes the whole reply takes it at once (half the largest one offered
    // is `half_the_largest_window_offered_is_no_silly_window`).
    let half = with_window(4096, seg(peer(5000), 105, iss, ACK, &[]));
    s.process(&half, ms(3), &mut app);
    let sent = drain(&mut s, ms(3));
    assert_eq!(sent[0].1, b"abcd");
    // So does a window that takes the whole reply, however small: the rest of the replies
    // is never silly.
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    let exact = with_window(4, seg(peer(5000), 101, iss, ACK, b"abcd"));
    s.process(&exact, ms(2), &mut app);
    assert_eq!(drain(&mut s, ms(2))[0].1, b"abcd");
}

#[test]
fn pipelined_requests_beyond_the_replies_room_wait_acknowledged_and_the_window_never_shrinks() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    // Three requests in one segment: two long replies fill the room (sent, not yet
    // acknowledged), and the third request waits, acknowledged.
    s.process(
        &seg(peer(5000), 101, iss, ACK, b"LxxxLxxxabcd"),
        ms(2),
        &mut app,
    );
    let sent = drain(&mut s, ms(2));
    let last = sent.last().expect("the replies").0;
    assert_eq!(last.ack, 113, "{sent:?}");
    // The window's right edge moved on (it was 101 + 64): it never moves back.
    assert_eq!(last.ack + u32::from(last.window), 113 + 60, "{sent:?}");
    // The whole window offered, while the replies still wait: kept too; the window closes.
    s.process(
        &seg(peer(5000), 113, iss, ACK, &[b'a'; 60]),
        ms(3),
        &mut app,
    );
    let sent = drain(&mut s, ms(3));
    let last = sent.last().expect("an ACK").0;
    assert_eq!((last.ack, last.window), (173, 0), "{sent:?}");
    // Beyond it: not taken.
    s.process(&seg(peer(5000), 173, iss, ACK, b"zzzz"), ms(3), &mut app);
    let sent = drain(&mut s, ms(3));
    assert_eq!(sent.last().map(|(o, _)| o.ack), Some(173), "{sent:?}");
    // The ACK of both replies: what waited is answered in order, and the window opens.
    let acked = seg(peer(5000), 173, iss + 2 * FRAME as u32, ACK, &[]);
    s.process(&acked, ms(4), &mut app);
    let sent = drain(&mut s, ms(4));
    let data: Vec<u8> = sent.iter().flat_map(|(_, d)| d.clone()).collect();
    let mut expected = b"abcd".to_vec();
    expected.extend_from_slice(&[b'a'; 60]);
    assert_eq!(data, expected, "{sent:?}");
    let last = sent.last().expect("the replies").0;
    assert_eq!((last.ack, last.window), (173, FRAME as u16), "{sent:?}");
    let received = app
        .events
        .iter()
        .filter(|e| matches!(e, Event::Received(..)))
        .count();
    assert_eq!(received, 2 + 1 + 15, "every request once, none dropped");
}

#[test]
fn a_fin_after_requests_that_wait_is_acknowledged_at_once_and_taken_once_they_are_answered() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    let last_request = seg(peer(5000), 101, iss, FIN_ACK, b"LxxxLxxxabcd");
    s.process(&last_request, ms(2), &mut app);
    let sent = drain(&mut s, ms(2));
    // The data and the FIN are acknowledged (the peer need not send its FIN again), but the
    // session stays open: the adapter has not had every request.
    assert_eq!(sent.last().map(|(o, _)| o.ack), Some(114), "{sent:?}");
    assert!(sent.iter().all(|(o, _)| !o.flags.fin), "{sent:?}");
    assert!(!app.events.contains(&Event::Closed(0)));
    // Data past the FIN is not taken.
    s.process(&seg(peer(5000), 114, iss, ACK, b"Lzzz"), ms(2), &mut app);
    assert_eq!(drain(&mut s, ms(2)).last().map(|(o, _)| o.ack), Some(114));
    // The replies acknowledged (no FIN again): the last request is answered, the session
    // told it closed and our FIN follows the reply.
    let acked = seg(peer(5000), 114, iss + 2 * FRAME as u32, ACK, &[]);
    s.process(&acked, ms(3), &mut app);
    let sent = drain(&mut s, ms(3));
    assert!(sent.iter().any(|(_, d)| d == b"abcd"), "{sent:?}");
    assert!(sent.iter().any(|(o, _)| o.flags.fin), "{sent:?}");
    assert_eq!(sent.last().map(|(o, _)| o.ack), Some(114), "{sent:?}");
    assert!(app.events.contains(&Event::Closed(0)));
    assert!(
        !app.events
            .iter()
            .any(|e| matches!(e, Event::Received(_, d) if d.starts_with(b"Lzzz"))),
        "{:?}",
        app.events
    );
}

#[test]
fn a_fin_behind_requests_that_wait_is_taken_when_the_adapter_closes_the_session() {
    // The session's inactivity timeout closes it while the request and the FIN wait: both
    // FINs are then exchanged, the peer's acknowledged once.
    let (mut s, mut app, iss) = closed_while_a_request_waits(FIN_ACK);
    let acked = seg(peer(5000), 114, iss + 2 * FRAME as u32, ACK, &[]);
    s.process(&acked, ms(101), &mut app);
    let sent = drain(&mut s, ms(101));
    let fin = sent.iter().find(|(o, _)| o.flags.fin).map(|(o, _)| o.ack);
    assert_eq!(fin, Some(114), "{sent:?}");
    let closed = app
        .events
        .iter()
        .filter(|e| **e == Event::Closed(0))
        .count();
    assert_eq!(closed, 1, "{:?}", app.events);
}

#[test]
fn requests_that_wait_are_dropped_when_the_adapter_closes_the_session() {
    // The session's inactivity timeout closes it while the request waits.
    let (mut s, mut app, iss) = closed_while_a_request_waits(ACK);
    // The peer's FIN before it acknowledged the replies: taken at once (nothing waits for
    // the session any more).
    s.process(&seg(peer(5000), 113, iss, FIN_ACK, &[]), ms(101), &mut app);
    let sent = drain(&mut s, ms(101));
    assert_eq!(sent.last().map(|(o, _)| o.ack), Some(114), "{sent:?}");
    // The replies acknowledged: the waiting request is not handed to a closed session.
    let acked = seg(peer(5000), 114, iss + 2 * FRAME as u32, ACK, &[]);
    s.process(&acked, ms(102), &mut app);
    drain(&mut s, ms(102));
    assert_eq!(
        app.events.last(),
        Some(&Event::Closed(0)),
        "{:?}",
        app.events
    );
    assert!(!app.events.contains(&Event::Received(0, b"abcd".to_vec())));
}

/// A connection whose two long replies fill the room while a third request waits (sent with
/// `flags`), closed by the session's inactivity timeout at 100 ms; the server, the adapter and
/// our initial sequence number.
fn closed_while_a_request_waits(flags: Flags) -> (Server, Echo, u32) {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    s.process(
        &seg(peer(5000), 101, iss, flags, b"LxxxLxxxabcd"),
        ms(2),
        &mut app,
    );
    drain(&mut s, ms(2));
    app.idle_at = Some(ms(100));
    s.poll(ms(100), &mut app);
    assert!(app.events.contains(&Event::Closed(0)), "{:?}", app.events);
    (s, app, iss)
}
