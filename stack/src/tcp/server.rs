//! The server of `N` connections: finds the connection of each segment, takes SYNs into
//! free connections (or, when every one is taken and one is half-open or has a silent peer,
//! answers them with a SYN cookie alone, and a client that proves its cookie takes a
//! half-open connection's place or a silent peer's), answers other segments of no
//! connection with a RST (RFC 9293 3.10.7.1), and hands out the connections' segments in
//! turn.
//!
//! Every SYN-ACK's initial sequence number is a SYN cookie, the one kept in a connection
//! too (as FreeBSD's syncache makes them): a handshake whose half-open connection was
//! dropped ([`super::HALF_OPEN`], a client more than that round trip away, or a SYN flood
//! taking its place) still completes when its ACK comes, from the cookie.

use super::conn::{Conn, State};
use super::cookie::{self, Cookies};
use super::{Flags, Outgoing, Segment, TcpApp, MSS};
use crate::rng::Rng;
use crate::{Instant, SocketId};

/// The encapsulation port's TCP: `N` connections (the adapter's sessions, at most 255),
/// replies of up to `F` bytes (its frame size). Its connection `i` is the adapter's
/// `SocketId(i)`.
pub struct TcpServer<const N: usize, const F: usize> {
    conns: [Conn<F>; N],
    /// The SYN cookies' key: every initial sequence number is a cookie.
    cookies: Cookies,
    /// The connection [`Self::transmit`] looks at first (each gets its turn).
    next: usize,
    /// An Identity Reset whose reply went out: for [`Self::take_reset`].
    reset: Option<u8>,
    /// Until when an ACK of no connection may prove a SYN cookie: [`cookie::LIFETIME`] after
    /// the last one that went alone or whose half-open connection lapsed or gave its place
    /// (ACKs of no connection are not hashed otherwise: an ACK flood costs no hashing while
    /// handshakes complete in their connections).
    cookies_until: Option<Instant>,
}

/// A segment to send, from [`TcpServer::transmit`], and its data.
#[derive(Debug)]
pub struct Transmit<'a> {
    /// The segment's headers.
    pub segment: Outgoing,
    /// Its data.
    pub payload: &'a [u8],
}

impl<const N: usize, const F: usize> TcpServer<N, F> {
    /// No connections; initial sequence numbers drawn from `seed` (the runtime's hardware
    /// RNG or clock: RFC 6528 asks that they be hard to guess).
    ///
    /// Built at run time, not `const`: a constant connection table would be an image of
    /// every buffer in flash, copied at start (2.2 KiB on the NUCLEO-F767ZI).
    pub fn new(seed: u64) -> Self {
        TcpServer {
            conns: core::array::from_fn(|_| Conn::new()),
            cookies: Cookies::new(seed),
            next: 0,
            reset: None,
            cookies_until: None,
        }
    }

    /// Mixes `seed` (the runtime's hardware RNG or clock at start) into the key of the SYN
    /// cookies, which are the initial sequence numbers (hard to guess: RFC 6528's aim).
    pub fn seed(&mut self, seed: u64) {
        let mut rng = Rng::new(seed);
        self.cookies.mix(rng.next_u64(), rng.next_u64());
    }

    /// The initial sequence number answering the SYN `seg` at `now`: its SYN cookie, from
    /// which an ACK of no connection at that number proves the handshake for
    /// [`cookie::LIFETIME`] once [`Self::accept_cookies`] says so.
    fn cookie(&self, seg: &Segment<'_>, now: Instant) -> u32 {
        self.cookies.make(seg.peer, seg.seq, seg.peer_mss(), now)
    }

    /// ACKs of no connection may prove a cookie made at `made`: its SYN-ACK went alone, or
    /// its half-open connection lapsed or gave its place.
    fn accept_cookies(&mut self, made: Instant) {
        let until = made.add(cookie::LIFETIME);
        self.cookies_until = Some(self.cookies_until.map_or(until, |u| u.max(until)));
    }

    /// The segment `seg`, arrived at `now`, for `app`; returns the segment answering it if
    /// it belongs to no connection (a RST, or a SYN cookie's SYN-ACK) or is an ACK a
    /// half-open connection refuses (a RST); the connections' own segments come from
    /// [`Self::transmit`].
    pub fn process(
        &mut self,
        seg: &Segment<'_>,
        now: Instant,
        app: &mut impl TcpApp,
    ) -> Option<Outgoing> {
        if let Some(i) = self.find(seg) {
            if self.conns.get(i).is_some_and(|c| c.refuses_ack(seg)) {
                // RFC 9293 3.10.7.4, SYN-RECEIVED: an ACK of anything but our SYN-ACK is
                // answered with a RST from its acknowledgment number, and the handshake goes
                // on; unless it proves the cookie of this peer's earlier SYN-ACK, whose
                // half-open connection lapsed before a repeated SYN opened this one: the
                // client took that one, and the connection is reopened from it.
                let Some(mss) = self.proven(seg, now) else {
                    return Some(refusal(seg));
                };
                self.open_proven(i, seg, mss, now, app);
                return None;
            }
            self.deliver(i, seg, now, app);
            return None;
        }
        let flags = seg.flags;
        if flags.rst {
            return None;
        }
        if flags.syn && !flags.ack {
            // A SYN with a FIN opens nothing a client would ask for: a scanner's probe,
            // dropped as BSD and Linux drop it.
            return (!flags.fin).then(|| self.take_syn(seg, now)).flatten();
        }
        if flags.ack && !flags.syn && self.take_cookie(seg, now, app) {
            return None;
        }
        // The port listens (RFC 9293 3.10.7.2): a segment with an ACK is answered with a RST,
        // one with neither ACK nor SYN (a FIN, NULL or Xmas scan) dropped.
        flags.ack.then(|| refusal(seg))
    }

    /// `seg` to connection `i`.
    fn deliver(&mut self, i: usize, seg: &Segment<'_>, now: Instant, app: &mut impl TcpApp) {
        if let Some(conn) = self.conns.get_mut(i) {
            conn.process(id(i), seg, now, app);
            self.reset = self.reset.or(conn.take_reset());
        }
    }

    /// A SYN of no connection: a free connection takes it; with none free, a SYN cookie
    /// alone answers it if a connection is half-open (a SYN flood, or a handshake under way)
    /// or has a peer silent for [`super::WRITE_TIMEOUT`] while replies wait (whose place the
    /// cookie's ACK may take: [`Self::take_cookie`]), else a RST refuses it (every
    /// connection is in use). A SYN itself evicts nothing: its source may be forged.
    fn take_syn(&mut self, seg: &Segment<'_>, now: Instant) -> Option<Outgoing> {
        if let Some(i) = self.conns.iter().position(|c| c.state == State::Free) {
            let iss = self.cookie(seg, now);
            if let Some(conn) = self.conns.get_mut(i) {
                conn.open(seg, iss, now);
            }
            return None;
        }
        let room = self
            .conns
            .iter()
            .any(|c| c.state == State::SynReceived || c.stale(now));
        if !room {
            return Some(refusal(seg));
        }
        self.accept_cookies(now);
        Some(Outgoing {
            peer: seg.peer,
            seq: self.cookie(seg, now),
            ack: seg.seq.wrapping_add(1),
            flags: Flags {
                syn: true,
                ack: true,
                ..Flags::default()
            },
            window: u16::try_from(F).unwrap_or(u16::MAX),
            mss: Some(MSS),
        })
    }

    /// The segment size named by the SYN cookie `seg` (an ACK) proves, if ACKs may prove
    /// cookies now ([`Self::accept_cookies`]).
    fn proven(&self, seg: &Segment<'_>, now: Instant) -> Option<u16> {
        if self.cookies_until.is_none_or(|until| now >= until) {
            return None;
        }
        let (isn, iss) = initial_numbers(seg);
        self.cookies.check(seg.peer, isn, iss, now)
    }

    /// An ACK of no connection that proves a SYN cookie (sent lately: a SYN-ACK whose
    /// connection was dropped half-open, or that went alone) opens a connection in a free
    /// one's place or the oldest half-open one's, and goes to it. With every connection
    /// open, one whose peer has been silent for [`super::WRITE_TIMEOUT`] while replies wait
    /// is reset for the proven client, and the ACK is dropped: the client's next segment
    /// (its request) proves the cookie again and finds the place free. False if it proves
    /// nothing or finds no place.
    fn take_cookie(&mut self, seg: &Segment<'_>, now: Instant, app: &mut impl TcpApp) -> bool {
        let Some(mss) = self.proven(seg, now) else {
            return false;
        };
        if let Some(i) = self.slot_for_syn() {
            if let Some(since) = self.half_open_since(i) {
                // Its handshake may yet complete from its cookie.
                self.accept_cookies(since);
            }
            self.open_proven(i, seg, mss, now, app);
            return true;
        }
        let Some(i) = self.conns.iter().position(|c| c.stale(now)) else {
            return false;
        };
        if let Some(conn) = self.conns.get_mut(i) {
            conn.abort(id(i), now, app);
            self.reset = self.reset.or(conn.take_reset());
        }
        true
    }

    /// Opens connection `i` for `seg`, an ACK proving the cookie of a SYN that named `mss`,
    /// and gives it the segment.
    fn open_proven(
        &mut self,
        i: usize,
        seg: &Segment<'_>,
        mss: u16,
        now: Instant,
        app: &mut impl TcpApp,
    ) {
        let (isn, iss) = initial_numbers(seg);
        let syn = Segment {
            seq: isn,
            flags: Flags {
                syn: true,
                ..Flags::default()
            },
            mss: Some(mss),
            payload: &[],
            ..*seg
        };
        if let Some(conn) = self.conns.get_mut(i) {
            conn.open_answered(&syn, iss, now);
        }
        self.deliver(i, seg, now, app);
    }

    /// The connection `seg` belongs to.
    fn find(&self, seg: &Segment<'_>) -> Option<usize> {
        self.conns
            .iter()
            .position(|c| c.state != State::Free && c.peer == seg.peer)
    }

    /// When connection `i`'s SYN came, if it is half-open.
    fn half_open_since(&self, i: usize) -> Option<Instant> {
        let conn = self.conns.get(i)?;
        (conn.state == State::SynReceived).then_some(conn.since)
    }

    /// A free connection for a proven SYN cookie, or the one half-open the longest.
    fn slot_for_syn(&self) -> Option<usize> {
        let free = self.conns.iter().position(|c| c.state == State::Free);
        free.or_else(|| {
            let half_open = self.conns.iter().enumerate();
            half_open
                .filter(|(_, c)| c.state == State::SynReceived)
                .min_by_key(|(_, c)| c.since)
                .map(|(i, _)| i)
        })
    }

    /// The next segment to send at `now`, if any: call again until there is none (a
    /// runtime calls it once it has room to send one). Its sequence numbers count as sent.
    pub fn transmit(&mut self, now: Instant) -> Option<Transmit<'_>> {
        let found = (0..N).find_map(|k| {
            let i = self.next.wrapping_add(k).checked_rem(N)?;
            let (segment, range) = self.conns.get_mut(i)?.transmit(now)?;
            Some((i, segment, range))
        });
        let (i, segment, range) = found?;
        self.next = i.wrapping_add(1).checked_rem(N).unwrap_or(0);
        let payload = self.conns.get(i).map_or(&[][..], |c| c.bytes(range));
        Some(Transmit { segment, payload })
    }

    /// True if [`Self::transmit`] has a segment now.
    pub fn owes(&self) -> bool {
        self.conns.iter().any(Conn::owes)
    }

    /// The timers at `now`: half-open, linger and inactivity bounds, retransmissions.
    pub fn poll(&mut self, now: Instant, app: &mut impl TcpApp) {
        for i in 0..N {
            let half_open = self.half_open_since(i);
            let Some(conn) = self.conns.get_mut(i) else {
                continue;
            };
            conn.poll(id(i), now, app);
            self.reset = self.reset.or(conn.take_reset());
            if let Some(since) = half_open.filter(|_| conn.state == State::Free) {
                // Lapsed: its handshake may yet complete from its cookie.
                self.accept_cookies(since);
            }
        }
    }

    /// When [`Self::poll`] has something to do next.
    pub fn deadline(&self, app: &impl TcpApp) -> Option<Instant> {
        let each = self.conns.iter().enumerate();
        each.filter_map(|(i, c)| c.deadline(id(i), app)).min()
    }

    /// An Identity Reset accepted on a connection, once its reply went out (or could not):
    /// the runtime performs it.
    pub fn take_reset(&mut self) -> Option<u8> {
        self.reset.take()
    }
}

/// The initial sequence numbers `seg`, an ACK completing a handshake, names: the peer's
/// and ours (its SYN cookie).
fn initial_numbers(seg: &Segment<'_>) -> (u32, u32) {
    (seg.seq.wrapping_sub(1), seg.ack.wrapping_sub(1))
}

/// The adapter's number of connection `i`.
fn id(i: usize) -> SocketId {
    SocketId(u8::try_from(i).unwrap_or(u8::MAX))
}

/// What answers `seg`, a segment to a port nobody listens on (RFC 9293 3.10.7.1, the
/// CLOSED state): a RST for anything but a RST, so a scanner sees the port closed.
pub fn closed_port_answer(seg: &Segment<'_>) -> Option<Outgoing> {
    (!seg.flags.rst).then(|| refusal(seg))
}

/// The RST answering `seg`, which belongs to no connection (RFC 9293 3.10.7.1).
fn refusal(seg: &Segment<'_>) -> Outgoing {
    let (seq, ack, flags) = if seg.flags.ack {
        let rst = Flags {
            rst: true,
            ..Flags::default()
        };
        (seg.ack, 0, rst)
    } else {
        let rst_ack = Flags {
            rst: true,
            ack: true,
            ..Flags::default()
        };
        (0, seg.seq.wrapping_add(seg.len()), rst_ack)
    };
    Outgoing {
        peer: seg.peer,
        seq,
        ack,
        flags,
        window: 0,
        mss: None,
    }
}
