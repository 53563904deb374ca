//! The server under a SYN flood from forged sources: the connections it holds half-open,
//! the SYN cookies that answer the SYNs beyond them, and the clients those cookies let in.

extern crate std;

use std::vec::Vec;

use super::tests::{
    connect, drain, ms, peer, seg, Echo, Event, Server, ACK, FIN_ACK, FRAME, RST, SYN,
};
use super::*;

/// Forged SYNs from `count` ports at `at`: the first take the free connections (their
/// SYN-ACKs drained), the rest are answered with cookies, returned.
fn flood(s: &mut Server, app: &mut Echo, count: u16, at: Instant) -> Vec<Outgoing> {
    let mut cookies = Vec::new();
    for port in 40_000..40_000 + count {
        if let Some(answer) = s.process(&seg(peer(port), 1, 0, SYN, &[]), at, app) {
            cookies.push(answer);
        }
        drain(s, at);
    }
    cookies
}

/// A client's SYN during the flood: its cookie SYN-ACK, checked.
fn cookie_for(s: &mut Server, app: &mut Echo, port: u16, isn: u32, at: Instant) -> u32 {
    let answer = s
        .process(&seg(peer(port), isn, 0, SYN, &[]), at, app)
        .expect("a SYN-ACK answers at once");
    assert!(answer.flags.syn && answer.flags.ack && !answer.flags.rst);
    assert_eq!((answer.peer, answer.ack), (peer(port), isn + 1));
    assert_eq!((answer.mss, answer.window), (Some(MSS), FRAME as u16));
    assert!(drain(s, at).is_empty(), "nothing kept for it");
    answer.seq
}

#[test]
fn a_syn_flood_holds_no_client_out_the_cookies_let_it_in() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let cookies = flood(&mut s, &mut app, 50, ms(0));
    assert_eq!(
        cookies.len(),
        48,
        "both connections half-open, a cookie for each other SYN"
    );
    assert!(cookies.iter().all(|c| c.flags.syn && c.flags.ack));
    // A client's SYN gets its cookie; its ACK, carrying a request, opens a connection in the
    // oldest half-open one's place, and the request is answered.
    let cookie = cookie_for(&mut s, &mut app, 5000, 100, ms(1));
    let next = cookie.wrapping_add(1);
    s.process(&seg(peer(5000), 101, next, ACK, b"abcd"), ms(2), &mut app);
    assert_eq!(
        app.events,
        [
            Event::Accepted(0, peer(5000)),
            Event::Received(0, b"abcd".to_vec())
        ]
    );
    let sent = drain(&mut s, ms(2));
    assert_eq!(sent.len(), 1, "{sent:?}");
    assert_eq!((sent[0].0.seq, sent[0].0.ack), (next, 105));
    assert_eq!(sent[0].1, b"abcd");
    // The flood goes on: the other half-open connection gives way to the next client.
    flood(&mut s, &mut app, 20, ms(3));
    let cookie = cookie_for(&mut s, &mut app, 5001, 900, ms(4));
    s.process(&seg(peer(5001), 901, cookie + 1, ACK, &[]), ms(5), &mut app);
    assert_eq!(app.events.last(), Some(&Event::Accepted(1, peer(5001))));
    // Both connections open, none half-open: a SYN is refused, as before any flood.
    let refused = s.process(&seg(peer(5002), 7, 0, SYN, &[]), ms(6), &mut app);
    assert!(refused.is_some_and(|r| r.flags.rst));
}

#[test]
fn an_ack_that_proves_no_cookie_is_refused() {
    let refused = |s: &mut Server, app: &mut Echo, seq, ack, at| {
        let answer = s.process(&seg(peer(5000), seq, ack, ACK, &[]), at, app);
        answer.is_some_and(|r| r.flags.rst && r.seq == ack)
    };
    let (mut s, mut app) = (Server::new(7), Echo::default());
    flood(&mut s, &mut app, 3, ms(0));
    let cookie = cookie_for(&mut s, &mut app, 5000, 100, ms(1));
    // Another cookie, or another initial sequence number: a RST.
    assert!(refused(&mut s, &mut app, 101, cookie ^ 0x100, ms(2)));
    assert!(refused(&mut s, &mut app, 102, cookie + 1, ms(2)));
    assert!(app.events.is_empty());
    // In time it opens its connection.
    assert!(!refused(&mut s, &mut app, 101, cookie + 1, ms(3)));
    assert_eq!(app.events, [Event::Accepted(0, peer(5000))]);
    // Too late: refused.
    let (mut s, mut app) = (Server::new(7), Echo::default());
    flood(&mut s, &mut app, 3, ms(0));
    let cookie = cookie_for(&mut s, &mut app, 5000, 100, ms(1));
    let late = ms(1).add(cookie::LIFETIME).add(Duration::from_secs(5));
    assert!(refused(&mut s, &mut app, 101, cookie + 1, late));
    assert!(app.events.is_empty());
}

#[test]
fn a_proven_cookie_finding_every_connection_open_is_refused() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    flood(&mut s, &mut app, 3, ms(0));
    let cookie = cookie_for(&mut s, &mut app, 5000, 100, ms(1));
    // Both half-open connections give way to clients proving cookies.
    for (port, isn) in [(5001, 300), (5002, 400)] {
        let c = cookie_for(&mut s, &mut app, port, isn, ms(2));
        s.process(&seg(peer(port), isn + 1, c + 1, ACK, &[]), ms(2), &mut app);
    }
    assert_eq!(app.events.len(), 2);
    let answer = s.process(&seg(peer(5000), 101, cookie + 1, ACK, &[]), ms(3), &mut app);
    assert!(answer.is_some_and(|r| r.flags.rst), "{answer:?}");
    assert_eq!(app.events.len(), 2);
}

#[test]
fn either_cookie_of_a_repeated_syn_opens_and_a_fin_with_it_closes() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    flood(&mut s, &mut app, 2, ms(0));
    let first = cookie_for(&mut s, &mut app, 5000, 100, ms(1));
    // The SYN again, a tick later: another cookie; the first still proves itself.
    let later = ms(1).add(Duration::from_micros(cookie::LIFETIME.as_micros() / 2));
    let second = cookie_for(&mut s, &mut app, 5000, 100, later);
    assert_ne!(first, second);
    // The ACK of the first, with a request and a FIN.
    let mut fin = seg(peer(5000), 101, first + 1, FIN_ACK, b"abcd");
    fin.flags.psh = true;
    s.process(&fin, later, &mut app);
    assert_eq!(
        app.events,
        [
            Event::Accepted(0, peer(5000)),
            Event::Received(0, b"abcd".to_vec()),
            Event::Closed(0)
        ]
    );
    let sent = drain(&mut s, later);
    let last = sent.last().expect("the reply and our FIN");
    assert!(last.0.flags.fin && last.0.ack == 106, "{sent:?}");
}

#[test]
fn a_cookie_connection_keeps_to_the_segment_size_its_cookie_named() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    flood(&mut s, &mut app, 2, ms(0));
    let mut syn = seg(peer(5000), 100, 0, SYN, &[]);
    syn.mss = Some(100);
    let cookie = s.process(&syn, ms(1), &mut app).expect("a cookie").seq;
    s.process(&seg(peer(5000), 101, cookie + 1, ACK, &[]), ms(2), &mut app);
    assert_eq!(app.events, [Event::Accepted(0, peer(5000))]);
    // A cookie names 100 as the smallest size it knows, 48: a 64-byte reply goes in two.
    s.process(
        &seg(peer(5000), 101, cookie + 1, ACK, b"L"),
        ms(3),
        &mut app,
    );
    let sent = drain(&mut s, ms(3));
    let sizes: Vec<usize> = sent.iter().map(|(_, data)| data.len()).collect();
    assert_eq!(sizes, [48, FRAME - 48]);
}

#[test]
fn forged_segments_draw_one_challenge_ack_each_half_second() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    let old_ack = iss.wrapping_sub(100_000);
    let unsent_ack = iss.wrapping_add(100_000);
    let challenges = |s: &mut Server, app: &mut Echo, at: Instant| {
        // An in-window RST that is not exact, a SYN, data with an ACK far back, and segments
        // acknowledging what was never sent, with and without data.
        s.process(&seg(peer(5000), 105, 0, RST, &[]), at, app);
        s.process(&seg(peer(5000), 7, 0, SYN, &[]), at, app);
        s.process(&seg(peer(5000), 101, old_ack, ACK, b"evil"), at, app);
        for _ in 0..10 {
            s.process(&seg(peer(5000), 101, unsent_ack, ACK, &[]), at, app);
            s.process(&seg(peer(5000), 101, unsent_ack, ACK, b"evil"), at, app);
        }
        drain(s, at).len()
    };
    assert_eq!(challenges(&mut s, &mut app, ms(10)), 1);
    for t in [20, 200, 509] {
        assert_eq!(challenges(&mut s, &mut app, ms(t)), 0, "at {t} ms");
    }
    assert_eq!(challenges(&mut s, &mut app, ms(510)), 1);
    // None of it reached the session, which goes on.
    assert_eq!(app.events, [Event::Accepted(0, peer(5000))]);
    s.process(&seg(peer(5000), 101, iss, ACK, b"abcd"), ms(511), &mut app);
    assert_eq!(drain(&mut s, ms(511))[0].1, b"abcd");
}
