//! The server against scripted peers: the handshake, requests and replies, retransmission,
//! both closes, resets, refusals, the timers, and the adapter's outcomes.

extern crate std;

use core::net::{Ipv4Addr, SocketAddrV4};
use std::vec::Vec;

use super::*;

/// Replies of up to this many bytes (the adapter's frame size in the tests).
pub(super) const FRAME: usize = 64;
/// Connections in the tests.
const CONNS: usize = 2;

pub(super) type Server = TcpServer<CONNS, FRAME>;

/// What the stand-in adapter saw.
#[derive(Debug, PartialEq, Eq, Clone)]
pub(super) enum Event {
    Accepted(u8, SocketAddrV4),
    Received(u8, Vec<u8>),
    Closed(u8),
}

/// A stand-in adapter: takes up to 4 bytes a call and echoes them; a request starting with
/// `C` closes the connection after its reply, one with `R` asks for an Identity Reset; one
/// with `L` replies with 100 bytes.
#[derive(Default)]
pub(super) struct Echo {
    pub(super) events: Vec<Event>,
    pub(super) idle_at: Option<Instant>,
}

impl TcpApp for Echo {
    fn accepted(&mut self, id: SocketId, peer: SocketAddrV4, _now: Instant) {
        self.events.push(Event::Accepted(id.0, peer));
    }

    fn receive(&mut self, id: SocketId, data: &[u8], _: Instant, reply: &mut [u8]) -> TcpOutcome {
        let n = data.len().min(4);
        let request = &data[..n];
        self.events.push(Event::Received(id.0, request.to_vec()));
        let reply_len = if request.first() == Some(&b'L') {
            reply[..FRAME].fill(b'l');
            FRAME
        } else {
            reply[..n].copy_from_slice(request);
            n
        };
        TcpOutcome {
            consumed: n,
            reply_len,
            close: request.first() == Some(&b'C'),
            reset: (request.first() == Some(&b'R')).then_some(1),
        }
    }

    fn closed(&mut self, id: SocketId, _now: Instant) {
        self.events.push(Event::Closed(id.0));
    }

    fn idle_deadline(&self, _id: SocketId) -> Option<Instant> {
        self.idle_at
    }
}

pub(super) fn peer(port: u16) -> SocketAddrV4 {
    SocketAddrV4::new(Ipv4Addr::new(198, 18, 0, 1), port)
}

pub(super) fn ms(n: u64) -> Instant {
    Instant(n * 1000)
}

const NONE: Flags = Flags {
    syn: false,
    ack: false,
    fin: false,
    rst: false,
    psh: false,
};
pub(super) const SYN: Flags = Flags { syn: true, ..NONE };
pub(super) const ACK: Flags = Flags { ack: true, ..NONE };
pub(super) const FIN_ACK: Flags = Flags {
    fin: true,
    ack: true,
    ..NONE
};
pub(super) const RST: Flags = Flags { rst: true, ..NONE };

pub(super) fn seg(
    from: SocketAddrV4,
    seq: u32,
    ack: u32,
    flags: Flags,
    payload: &[u8],
) -> Segment<'_> {
    Segment {
        peer: from,
        seq,
        ack,
        flags,
        window: 8192,
        mss: flags.syn.then_some(1460),
        payload,
    }
}

/// `segment` offering the window `window`.
pub(super) fn with_window(window: u16, segment: Segment<'_>) -> Segment<'_> {
    Segment { window, ..segment }
}

/// The data of the first segment sent at the server's next deadline (a window probe).
pub(super) fn probed(s: &mut Server, app: &mut Echo) -> Vec<u8> {
    let at = s.deadline(app).expect("the probe is armed");
    s.poll(at, app);
    drain(s, at)
        .first()
        .map(|(_, d)| d.clone())
        .unwrap_or_default()
}

/// Everything the server sends at `now`, with the data, asked as the link task asks: only
/// while it says it owes a segment.
pub(super) fn drain(server: &mut Server, now: Instant) -> Vec<(Outgoing, Vec<u8>)> {
    let mut out = Vec::new();
    for _ in 0..16 {
        if !server.owes() {
            assert!(
                server.transmit(now).is_none(),
                "a segment it did not own up to"
            );
            break;
        }
        let Some(t) = server.transmit(now) else {
            panic!("owes a segment and sends none");
        };
        out.push((t.segment, t.payload.to_vec()));
    }
    out
}

/// A connection from `from`, its client's sequence numbers starting at `isn`; returns the
/// server's next sequence number.
pub(super) fn connect(server: &mut Server, app: &mut Echo, from: SocketAddrV4, isn: u32) -> u32 {
    assert_eq!(
        server.process(&seg(from, isn, 0, SYN, &[]), ms(0), app),
        None
    );
    let sent = drain(server, ms(0));
    assert_eq!(sent.len(), 1, "one SYN-ACK: {sent:?}");
    let syn_ack = sent[0].0;
    assert!(syn_ack.flags.syn && syn_ack.flags.ack);
    assert_eq!(syn_ack.ack, isn.wrapping_add(1));
    assert_eq!(syn_ack.mss, Some(MSS));
    let next = syn_ack.seq.wrapping_add(1);
    let ack = seg(from, isn.wrapping_add(1), next, ACK, &[]);
    assert_eq!(server.process(&ack, ms(1), app), None);
    assert!(
        drain(server, ms(1)).is_empty(),
        "nothing answers the handshake's ACK"
    );
    next
}

#[test]
fn a_request_is_answered_with_its_reply_and_the_ack_of_the_request() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    assert_eq!(app.events, [Event::Accepted(0, peer(5000))]);
    s.process(&seg(peer(5000), 101, iss, ACK, b"abcd"), ms(2), &mut app);
    let sent = drain(&mut s, ms(2));
    assert_eq!(sent.len(), 1);
    let (reply, data) = &sent[0];
    assert_eq!((reply.seq, reply.ack), (iss, 105));
    assert!(reply.flags.ack && reply.flags.psh && !reply.flags.fin);
    assert_eq!(data, b"abcd");
    assert_eq!(reply.window, FRAME as u16);
    // Acknowledged: nothing left, no retransmission.
    s.process(&seg(peer(5000), 105, iss + 4, ACK, &[]), ms(3), &mut app);
    s.poll(ms(5000), &mut app);
    assert!(drain(&mut s, ms(5000)).is_empty());
}

#[test]
fn several_requests_in_one_segment_each_get_their_reply() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    s.process(
        &seg(peer(5000), 101, iss, ACK, b"abcdefghij"),
        ms(2),
        &mut app,
    );
    let received: Vec<_> = app.events[1..].to_vec();
    assert_eq!(
        received,
        [
            Event::Received(0, b"abcd".to_vec()),
            Event::Received(0, b"efgh".to_vec()),
            Event::Received(0, b"ij".to_vec()),
        ]
    );
    let sent = drain(&mut s, ms(2));
    assert_eq!(sent.len(), 1);
    assert_eq!(sent[0].1, b"abcdefghij");
    assert_eq!(sent[0].0.ack, 111);
}

#[test]
fn an_unacknowledged_reply_is_sent_again_from_its_first_byte_with_the_timeout_doubled() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    s.process(&seg(peer(5000), 101, iss, ACK, b"abcd"), ms(2), &mut app);
    assert_eq!(drain(&mut s, ms(2)).len(), 1);
    let first = s.deadline(&app).expect("retransmission armed");
    assert_eq!(first, ms(2).add(INITIAL_RTO));
    s.poll(first, &mut app);
    let again = drain(&mut s, first);
    assert_eq!(again.len(), 1);
    assert_eq!((again[0].0.seq, again[0].1.as_slice()), (iss, &b"abcd"[..]));
    assert_eq!(s.deadline(&app), Some(first.add(Duration::from_secs(2))));
}

#[test]
fn a_segment_ahead_of_the_next_byte_is_dropped_and_the_ack_says_what_is_expected() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    s.process(&seg(peer(5000), 105, iss, ACK, b"efgh"), ms(2), &mut app);
    assert_eq!(app.events.len(), 1, "nothing reached the adapter");
    let sent = drain(&mut s, ms(2));
    assert_eq!(sent.len(), 1);
    assert_eq!((sent[0].0.ack, sent[0].1.len()), (101, 0));
    // A retransmission overlapping what was taken gives only the new bytes.
    s.process(&seg(peer(5000), 101, iss, ACK, b"ab"), ms(3), &mut app);
    s.process(&seg(peer(5000), 101, iss, ACK, b"abcd"), ms(4), &mut app);
    assert_eq!(app.events[2], Event::Received(0, b"cd".to_vec()));
}

#[test]
fn the_peers_close_ends_the_session_and_our_fin_follows() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    s.process(&seg(peer(5000), 101, iss, FIN_ACK, &[]), ms(2), &mut app);
    assert_eq!(app.events.last(), Some(&Event::Closed(0)));
    let sent = drain(&mut s, ms(2));
    assert_eq!(sent.len(), 1);
    assert!(sent[0].0.flags.fin && sent[0].0.flags.ack);
    assert_eq!((sent[0].0.seq, sent[0].0.ack), (iss, 102));
    s.process(&seg(peer(5000), 102, iss + 1, ACK, &[]), ms(3), &mut app);
    assert_eq!(s.deadline(&app), None, "free again");
    // The port's next client gets the slot.
    connect(&mut s, &mut app, peer(5001), 900);
}

#[test]
fn the_adapters_close_sends_the_reply_then_our_fin_and_waits_for_the_peers() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    s.process(&seg(peer(5000), 101, iss, ACK, b"Cxyz"), ms(2), &mut app);
    assert_eq!(app.events.last(), Some(&Event::Closed(0)));
    let sent = drain(&mut s, ms(2));
    assert_eq!(sent.len(), 1);
    assert!(sent[0].0.flags.fin, "the FIN rides on the reply");
    assert_eq!(sent[0].1, b"Cxyz");
    s.process(&seg(peer(5000), 105, iss + 5, ACK, &[]), ms(3), &mut app);
    assert!(drain(&mut s, ms(3)).is_empty());
    s.process(
        &seg(peer(5000), 105, iss + 5, FIN_ACK, &[]),
        ms(4),
        &mut app,
    );
    let last = drain(&mut s, ms(4));
    assert_eq!(last.len(), 1);
    assert_eq!((last[0].0.flags, last[0].0.ack), (ACK, 106));
    assert_eq!(s.deadline(&app), None);
    assert_eq!(
        app.events
            .iter()
            .filter(|e| **e == Event::Closed(0))
            .count(),
        1
    );
}

#[test]
fn a_close_the_peer_never_completes_is_reset_after_the_linger() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    s.process(&seg(peer(5000), 101, iss, ACK, b"Cxyz"), ms(2), &mut app);
    drain(&mut s, ms(2));
    s.process(&seg(peer(5000), 105, iss + 5, ACK, &[]), ms(3), &mut app);
    assert_eq!(s.deadline(&app), Some(ms(2).add(LINGER)));
    s.poll(ms(2).add(LINGER), &mut app);
    let sent = drain(&mut s, ms(2).add(LINGER));
    assert!(sent[0].0.flags.rst);
    assert_eq!(s.deadline(&app), None);
}

#[test]
fn only_the_exact_next_sequence_number_resets_other_rsts_and_syns_get_a_challenge_ack() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    s.process(&seg(peer(5000), 110, 0, RST, &[]), ms(2), &mut app);
    s.process(&seg(peer(5000), 5, 0, SYN, &[]), ms(2), &mut app);
    let sent = drain(&mut s, ms(2));
    assert_eq!(sent.len(), 1, "one challenge ACK covers both: {sent:?}");
    assert_eq!(
        (sent[0].0.flags, sent[0].0.seq, sent[0].0.ack),
        (ACK, iss, 101)
    );
    assert!(!app.events.contains(&Event::Closed(0)));
    // Out of the window altogether: not even a challenge.
    s.process(&seg(peer(5000), 100_000, 0, RST, &[]), ms(3), &mut app);
    assert!(drain(&mut s, ms(3)).is_empty());
    s.process(&seg(peer(5000), 101, 0, RST, &[]), ms(4), &mut app);
    assert_eq!(app.events.last(), Some(&Event::Closed(0)));
    assert!(drain(&mut s, ms(4)).is_empty(), "a RST is never answered");
    assert_eq!(s.deadline(&app), None);
}

#[test]
fn segments_of_no_connection_are_refused_as_rfc_9293_says() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let with_ack = s.process(&seg(peer(6000), 10, 777, ACK, b"zz"), ms(0), &mut app);
    let rst = with_ack.expect("refused");
    assert_eq!((rst.seq, rst.flags), (777, RST));
    // The port listens: a FIN (or NULL, or Xmas) segment without an ACK is dropped.
    let fin = seg(peer(6000), 10, 0, FIN_ACK.without_ack(), b"zz");
    assert_eq!(s.process(&fin, ms(0), &mut app), None);
    assert_eq!(
        s.process(&seg(peer(6000), 10, 0, RST, &[]), ms(0), &mut app),
        None
    );
    // A SYN with a FIN (a scanner's probe) opens nothing and is not answered.
    let syn_fin = Flags { fin: true, ..SYN };
    let probe = seg(peer(6001), 10, 0, syn_fin, &[]);
    assert_eq!(s.process(&probe, ms(0), &mut app), None);
    assert!(drain(&mut s, ms(0)).is_empty() && app.events.is_empty());
}

#[test]
fn segments_to_a_closed_port_are_reset_whatever_their_flags() {
    let rst_ack = Flags { ack: true, ..RST };
    let answer = |flags, payload: &[u8]| {
        closed_port_answer(&seg(peer(6000), 10, 777, flags, payload))
            .map(|o| (o.peer, o.seq, o.ack, o.flags, o.mss))
    };
    let p = peer(6000);
    // A SYN takes one number, a FIN one more, data its length (RFC 9293 3.10.7.1).
    assert_eq!(answer(SYN, &[]), Some((p, 0, 11, rst_ack, None)));
    assert_eq!(answer(ACK, b"zz"), Some((p, 777, 0, RST, None)));
    // Unlike a listening port's, a FIN, NULL or Xmas segment without an ACK is answered.
    assert_eq!(
        answer(FIN_ACK.without_ack(), b"zz"),
        Some((p, 0, 13, rst_ack, None))
    );
    assert_eq!(answer(NONE, &[]), Some((p, 0, 10, rst_ack, None)));
    assert_eq!(answer(RST, &[]), None);
    assert_eq!(answer(Flags { ack: true, ..RST }, &[]), None);
}

impl Flags {
    fn without_ack(self) -> Flags {
        Flags { ack: false, ..self }
    }
}

#[test]
fn a_syn_when_every_connection_is_open_is_refused() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    connect(&mut s, &mut app, peer(5000), 100);
    connect(&mut s, &mut app, peer(5001), 200);
    let refused = s.process(&seg(peer(5002), 300, 0, SYN, &[]), ms(2), &mut app);
    let rst = refused.expect("refused");
    assert!(rst.flags.rst && rst.flags.ack);
    assert_eq!(rst.ack, 301);
}

#[test]
fn a_half_open_connection_is_dropped_after_the_bound_and_its_syn_ack_repeated_on_a_repeated_syn() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    s.process(&seg(peer(5000), 100, 0, SYN, &[]), ms(0), &mut app);
    let first = drain(&mut s, ms(0));
    s.process(&seg(peer(5000), 100, 0, SYN, &[]), ms(100), &mut app);
    let again = drain(&mut s, ms(100));
    assert_eq!(first[0].0, again[0].0);
    assert_eq!(s.deadline(&app), Some(ms(0).add(HALF_OPEN)));
    s.poll(ms(0).add(HALF_OPEN), &mut app);
    assert!(
        drain(&mut s, ms(0).add(HALF_OPEN)).is_empty(),
        "dropped without a RST"
    );
    assert!(app.events.is_empty(), "the adapter never heard of it");
    assert_eq!(s.deadline(&app), None);
}

#[test]
fn a_reply_longer_than_the_peers_segment_size_goes_in_pieces() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let syn = Segment {
        mss: Some(20),
        ..seg(peer(5000), 100, 0, SYN, &[])
    };
    s.process(&syn, ms(0), &mut app);
    let iss = drain(&mut s, ms(0))[0].0.seq.wrapping_add(1);
    s.process(&seg(peer(5000), 101, iss, ACK, &[]), ms(1), &mut app);
    s.process(&seg(peer(5000), 101, iss, ACK, b"L"), ms(2), &mut app);
    let sent = drain(&mut s, ms(2));
    let sizes: Vec<_> = sent.iter().map(|(_, d)| d.len()).collect();
    assert_eq!(sizes, [48, 16], "20 is raised to 48");
    assert_eq!(sent[1].0.seq, iss + 48);
    assert!(!sent[0].0.flags.psh && sent[1].0.flags.psh);
}

#[test]
fn a_closed_window_is_probed_and_replies_go_once_it_opens() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    let closed = with_window(0, seg(peer(5000), 101, iss, ACK, b"abcd"));
    s.process(&closed, ms(2), &mut app);
    let ack_only = drain(&mut s, ms(2));
    assert_eq!((ack_only.len(), ack_only[0].1.len()), (1, 0));
    let probe_at = s.deadline(&app).expect("probe armed");
    s.poll(probe_at, &mut app);
    let probe = drain(&mut s, probe_at);
    assert_eq!(probe[0].1, b"a");
    let open = seg(peer(5000), 105, iss + 1, ACK, &[]);
    s.process(&open, probe_at, &mut app);
    let rest = drain(&mut s, probe_at);
    assert_eq!(rest[0].1, b"bcd");
}

#[test]
fn an_idle_connection_is_closed_at_the_adapters_inactivity_deadline() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    app.idle_at = Some(ms(30_000));
    assert_eq!(s.deadline(&app), Some(ms(30_000)));
    s.poll(ms(30_000), &mut app);
    assert_eq!(app.events.last(), Some(&Event::Closed(0)));
    let fin = drain(&mut s, ms(30_000));
    assert_eq!((fin[0].0.flags, fin[0].0.seq), (FIN_ACK, iss));
}

#[test]
fn an_identity_reset_is_handed_over_once_its_reply_is_acknowledged() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    s.process(&seg(peer(5000), 101, iss, ACK, b"R"), ms(2), &mut app);
    drain(&mut s, ms(2));
    assert_eq!(s.take_reset(), None, "not before the reply is acknowledged");
    s.process(&seg(peer(5000), 102, iss + 1, ACK, &[]), ms(3), &mut app);
    assert_eq!(s.take_reset(), Some(1));
    assert_eq!(s.take_reset(), None);
}

#[test]
fn sequence_numbers_wrap() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), u32::MAX - 1);
    s.process(
        &seg(peer(5000), u32::MAX, iss, ACK, b"abcd"),
        ms(2),
        &mut app,
    );
    let sent = drain(&mut s, ms(2));
    assert_eq!(sent[0].0.ack, 3);
    assert_eq!(sent[0].1, b"abcd");
    s.process(
        &seg(peer(5000), 3, iss.wrapping_add(4), ACK, b"efgh"),
        ms(3),
        &mut app,
    );
    let sent = drain(&mut s, ms(3));
    assert_eq!((sent[0].0.ack, sent[0].1.as_slice()), (7, &b"efgh"[..]));
}

#[test]
fn the_ack_of_the_peers_fin_goes_even_when_ours_is_acknowledged_in_the_same_burst() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    // The adapter closes on the request; our FIN goes out with its reply.
    s.process(&seg(peer(5000), 101, iss, ACK, b"Cxyz"), ms(2), &mut app);
    assert!(drain(&mut s, ms(2))[0].0.flags.fin);
    // The peer's FIN, then its ACK of ours, both read before anything is sent.
    s.process(
        &seg(peer(5000), 105, iss + 4, FIN_ACK, &[]),
        ms(3),
        &mut app,
    );
    s.process(&seg(peer(5000), 106, iss + 5, ACK, &[]), ms(3), &mut app);
    let last = drain(&mut s, ms(3));
    assert_eq!(last.len(), 1, "{last:?}");
    assert_eq!((last[0].0.flags, last[0].0.ack), (ACK, 106));
    assert_eq!(s.deadline(&app), None);
    // A FIN sent again finds no connection: refused, as a late FIN is.
    let late = s.process(
        &seg(peer(5000), 105, iss + 5, FIN_ACK, &[]),
        ms(4),
        &mut app,
    );
    assert!(late.is_some_and(|r| r.flags.rst));
}

#[test]
fn a_fin_after_a_quiet_spell_is_not_overdue() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    s.process(&seg(peer(5000), 101, iss, ACK, b"abcd"), ms(2), &mut app);
    drain(&mut s, ms(2));
    s.process(&seg(peer(5000), 105, iss + 4, ACK, &[]), ms(3), &mut app);
    // Two minutes of quiet, then the inactivity timeout closes: the FIN waits its own
    // timeouts, not the last reply's.
    app.idle_at = Some(ms(120_000));
    s.poll(ms(120_000), &mut app);
    let fin = drain(&mut s, ms(120_000));
    assert_eq!(fin[0].0.flags, FIN_ACK);
    let next = s.deadline(&app).expect("the FIN's retransmission");
    assert_eq!(
        next,
        ms(120_000).add(MIN_RTO),
        "the round trip measured (1 ms) sets it"
    );
    s.poll(next, &mut app);
    let again = drain(&mut s, next);
    assert_eq!(again.len(), 1, "{again:?}");
    assert_eq!(again[0].0.flags, FIN_ACK, "sent again, not reset");
}

#[test]
fn a_closed_window_is_probed_even_when_everything_sent_was_acknowledged() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    // The peer's window takes 4 of the 8 bytes of reply: a silly window against the 8 192
    // it offered, taken at the timeout.
    let small = with_window(4, seg(peer(5000), 101, iss, ACK, b"abcdefgh"));
    s.process(&small, ms(2), &mut app);
    let sent = drain(&mut s, ms(2));
    assert_eq!(sent.iter().map(|(_, d)| d.len()).sum::<usize>(), 0);
    let at = s.deadline(&app).expect("the override is armed");
    s.poll(at, &mut app);
    let sent = drain(&mut s, at);
    assert_eq!(sent.iter().map(|(_, d)| d.len()).sum::<usize>(), 4);
    // A pure ACK of those 4 that closes the window: the other 4 wait, and the window is
    // probed at the timeout.
    let closed = with_window(0, seg(peer(5000), 109, iss + 4, ACK, &[]));
    s.process(&closed, at, &mut app);
    assert!(drain(&mut s, at).is_empty());
    assert_eq!(probed(&mut s, &mut app), b"e");
}

#[test]
fn data_with_an_ack_older_than_any_window_offered_gets_a_challenge_ack_and_is_dropped() {
    let (mut s, mut app) = (Server::new(7), Echo::default());
    let iss = connect(&mut s, &mut app, peer(5000), 100);
    // RFC 5961 5.2: the peer offered 8 192 bytes at most; an ACK further back than that
    // before the oldest unacknowledged byte is a blind injection's guess.
    let guess = iss.wrapping_sub(8_193);
    s.process(&seg(peer(5000), 101, guess, ACK, b"evil"), ms(2), &mut app);
    assert_eq!(app.events, [Event::Accepted(0, peer(5000))]);
    let sent = drain(&mut s, ms(2));
    assert_eq!(sent.len(), 1, "one challenge ACK: {sent:?}");
    assert_eq!(
        (sent[0].0.flags, sent[0].0.seq, sent[0].0.ack),
        (ACK, iss, 101)
    );
    // An old ACK within the largest window is acceptable: its data is taken.
    let old = iss.wrapping_sub(8_192);
    s.process(&seg(peer(5000), 101, old, ACK, b"abcd"), ms(3), &mut app);
    assert_eq!(
        app.events.last(),
        Some(&Event::Received(0, b"abcd".to_vec()))
    );
    let sent = drain(&mut s, ms(3));
    assert_eq!((sent.len(), sent[0].0.ack), (1, 105));
    assert_eq!(sent[0].1, b"abcd");
}
