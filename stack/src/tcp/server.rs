//! The server of `N` connections: finds the connection of each segment, takes SYNs into
//! free (or the oldest half-open) connections, answers segments of no connection with a RST
//! (RFC 9293 3.10.7.1), and hands out the connections' segments in turn.

use super::conn::{Conn, State};
use super::{Flags, Outgoing, Segment, TcpApp};
use crate::rng::Rng;
use crate::{Instant, SocketId};

/// The encapsulation port's TCP: `N` connections (the adapter's sessions, at most 255),
/// replies of up to `F` bytes (its frame size). Its connection `i` is the adapter's
/// `SocketId(i)`.
pub struct TcpServer<const N: usize, const F: usize> {
    conns: [Conn<F>; N],
    /// Initial sequence numbers.
    rng: Rng,
    /// The connection [`Self::transmit`] looks at first (each gets its turn).
    next: usize,
    /// An Identity Reset whose reply went out: for [`Self::take_reset`].
    reset: Option<u8>,
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
    pub const fn new(seed: u64) -> Self {
        TcpServer {
            conns: [const { Conn::new() }; N],
            rng: Rng::new(seed),
            next: 0,
            reset: None,
        }
    }

    /// Mixes `seed` (the runtime's hardware RNG or clock at start) into the initial
    /// sequence numbers.
    pub fn seed(&mut self, seed: u64) {
        self.rng = Rng::new(self.rng.next_u64() ^ seed);
    }

    /// The segment `seg`, arrived at `now`, for `app`; returns the RST to send if it belongs
    /// to no connection (its own segments come from [`Self::transmit`]).
    pub fn process(
        &mut self,
        seg: &Segment<'_>,
        now: Instant,
        app: &mut impl TcpApp,
    ) -> Option<Outgoing> {
        if let Some(i) = self.find(seg) {
            let conn = self.conns.get_mut(i)?;
            conn.process(id(i), seg, now, app);
            self.reset = self.reset.or(conn.take_reset());
            return None;
        }
        let flags = seg.flags;
        if flags.rst {
            return None;
        }
        if flags.syn && !flags.ack {
            let Some(conn) = self.slot_for_syn().and_then(|i| self.conns.get_mut(i)) else {
                return Some(refusal(seg));
            };
            // RFC 6528 wants the clock in; the generator's state moves at every SYN anyway.
            let iss = (self.rng.next_u64() >> 32) as u32;
            conn.open(seg, iss, now);
            return None;
        }
        Some(refusal(seg))
    }

    /// The connection `seg` belongs to.
    fn find(&self, seg: &Segment<'_>) -> Option<usize> {
        self.conns
            .iter()
            .position(|c| c.state != State::Free && c.peer == seg.peer)
    }

    /// A free connection for a SYN, or the one half-open the longest.
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
        for (i, conn) in self.conns.iter_mut().enumerate() {
            conn.poll(id(i), now, app);
            self.reset = self.reset.or(conn.take_reset());
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

    /// Resets every connection (the device restarts, or the address changed): each sends a
    /// RST ([`Self::transmit`]) and the adapter is told it closed.
    pub fn abort_all(&mut self, now: Instant, app: &mut impl TcpApp) {
        for (i, conn) in self.conns.iter_mut().enumerate() {
            conn.abort(id(i), now, app);
        }
    }
}

/// The adapter's number of connection `i`.
fn id(i: usize) -> SocketId {
    SocketId(u8::try_from(i).unwrap_or(u8::MAX))
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
