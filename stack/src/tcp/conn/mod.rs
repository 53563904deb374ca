//! One connection of the server: its state (RFC 9293 3.3.2), sequence numbers, the replies
//! not yet acknowledged, and its timers. The server ([`super::TcpServer`]) finds the
//! connection a segment belongs to; this file does what RFC 9293 3.10.7.4 says of it,
//! [`send`] what the connection sends, and [`timers`] its timers.

mod send;
mod timers;

use core::net::{Ipv4Addr, SocketAddrV4};

use super::seq::{distance, le, lt, within};
use super::{Flags, Segment, TcpApp, DEFAULT_MSS, INITIAL_RTO, MIN_RTO};
use crate::{Duration, Instant, SocketId};

/// Shortest time between two challenge ACKs of one connection (RFC 5961 section 7's
/// throttling; per connection, as Linux's `tcp_invalid_ratelimit`: a count shared by every
/// connection would tell an off-path attacker when another connection answered).
const CHALLENGE_INTERVAL: Duration = Duration::from_millis(500);
/// The longest retransmission timeout (RFC 6298 2.5).
const MAX_RTO: Duration = Duration::from_secs(60);

/// Where a connection is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum State {
    /// No connection: the slot listens.
    Free,
    /// The SYN came and the SYN-ACK went; waiting for its acknowledgment.
    SynReceived,
    /// Open both ways.
    Established,
    /// The adapter closed: our FIN follows the replies; waiting for its acknowledgment.
    FinWait1,
    /// Our FIN is acknowledged; waiting for the peer's.
    FinWait2,
    /// Both FINs came and went; ours not yet acknowledged.
    Closing,
    /// The peer closed first: our FIN follows the replies; waiting for its acknowledgment.
    LastAck,
    /// Both FINs are acknowledged but for ours of the peer's: sent next, and the slot is free.
    LastAckOwed,
}

/// One connection; `F` is the adapter's largest reply (its frame size).
pub(super) struct Conn<const F: usize> {
    pub(super) state: State,
    pub(super) peer: SocketAddrV4,
    /// When the SYN came (the half-open bound) or the close began (the linger bound).
    pub(super) since: Instant,
    iss: u32,
    irs: u32,
    /// The oldest sequence number not acknowledged.
    snd_una: u32,
    /// The next sequence number to send.
    snd_nxt: u32,
    /// The highest sequence number sent (a segment below it is a retransmission).
    snd_max: u32,
    /// The window the peer offers, and the segment it was last learned from.
    snd_wnd: u32,
    snd_wl1: u32,
    snd_wl2: u32,
    /// The largest window the peer has offered (RFC 5961's MAX.SND.WND).
    max_snd_wnd: u32,
    /// The next sequence number expected.
    rcv_nxt: u32,
    /// The peer's maximum segment size.
    mss: u16,
    /// The replies from `snd_una` on (once the SYN is acknowledged): sent and not yet
    /// acknowledged, then not yet sent. Two frames: a reply always finds room for the next
    /// request's while the last one waits for its acknowledgment.
    tx: [[u8; F]; 2],
    tx_len: usize,
    /// Data received in order and acknowledged that the adapter has not taken yet (the
    /// replies had no room for another): handed to it before anything newer once the
    /// replies' acknowledgments make room. The window offered is the room it has left, so
    /// pipelined requests never shrink the window (RFC 9293 3.8.6.2.2).
    rx: [u8; F],
    rx_len: usize,
    /// The peer's FIN came, in order, behind data that waits in `rx`: acknowledged, and
    /// taken (the session told it closed) once the adapter has had that data.
    peer_fin_waits: bool,
    /// Our FIN follows the replies.
    fin: bool,
    ack_owed: bool,
    syn_ack_owed: bool,
    /// A RST is owed: the slot is free once it is sent.
    rst_owed: bool,
    /// A window probe is owed (the peer's window is closed, or too small for the replies
    /// that wait: what it takes goes then, the silly window avoidance's override).
    probe_owed: bool,
    /// The adapter has the connection as a session (accepted, not yet told it closed).
    open: bool,
    rto: Duration,
    /// Smoothed round trip and its variation, in microseconds (RFC 6298).
    srtt: Option<(u64, u64)>,
    /// The acknowledgment that times a round trip, and when its segment went.
    rtt_probe: Option<(u32, Instant)>,
    retransmit_at: Option<Instant>,
    /// When the peer last acknowledged something new (or replies began to wait).
    progress_at: Instant,
    /// When the peer last sent a segment within the window.
    heard_at: Instant,
    /// An Identity Reset accepted on this connection, performed once its reply is
    /// acknowledged (or could not be).
    reset: Option<u8>,
    /// When the last challenge ACK was owed (RFC 5961).
    challenged: Option<Instant>,
}

impl<const F: usize> Conn<F> {
    /// A free slot.
    pub(super) const fn new() -> Self {
        Conn {
            state: State::Free,
            peer: SocketAddrV4::new(Ipv4Addr::UNSPECIFIED, 0),
            since: Instant(0),
            iss: 0,
            irs: 0,
            snd_una: 0,
            snd_nxt: 0,
            snd_max: 0,
            snd_wnd: 0,
            snd_wl1: 0,
            snd_wl2: 0,
            max_snd_wnd: 0,
            rcv_nxt: 0,
            mss: DEFAULT_MSS,
            tx: [[0; F]; 2],
            tx_len: 0,
            rx: [0; F],
            rx_len: 0,
            peer_fin_waits: false,
            fin: false,
            ack_owed: false,
            syn_ack_owed: false,
            rst_owed: false,
            probe_owed: false,
            open: false,
            rto: INITIAL_RTO,
            srtt: None,
            rtt_probe: None,
            retransmit_at: None,
            progress_at: Instant(0),
            heard_at: Instant(0),
            reset: None,
            challenged: None,
        }
    }

    /// Takes the SYN `seg` with our initial sequence number `iss`: SYN-RECEIVED, the
    /// SYN-ACK owed.
    pub(super) fn open(&mut self, seg: &Segment<'_>, iss: u32, now: Instant) {
        self.state = State::SynReceived;
        self.peer = seg.peer;
        self.since = now;
        self.iss = iss;
        self.irs = seg.seq;
        self.snd_una = iss;
        self.snd_nxt = iss.wrapping_add(1);
        self.snd_max = self.snd_nxt;
        self.snd_wnd = u32::from(seg.window);
        self.snd_wl1 = seg.seq;
        self.snd_wl2 = iss;
        self.max_snd_wnd = self.snd_wnd;
        self.rcv_nxt = seg.seq.wrapping_add(1);
        self.mss = seg.peer_mss();
        self.tx_len = 0;
        self.rx_len = 0;
        self.peer_fin_waits = false;
        self.fin = false;
        self.ack_owed = false;
        self.syn_ack_owed = true;
        self.rst_owed = false;
        self.probe_owed = false;
        self.open = false;
        self.rto = INITIAL_RTO;
        self.srtt = None;
        self.rtt_probe = None;
        self.retransmit_at = None;
        self.progress_at = now;
        self.heard_at = now;
        self.reset = None;
        self.challenged = None;
    }

    /// Takes the SYN `syn` that a SYN cookie answered with `iss` (its SYN-ACK went already):
    /// SYN-RECEIVED, waiting for the ACK that proved the cookie.
    pub(super) fn open_answered(&mut self, syn: &Segment<'_>, iss: u32, now: Instant) {
        self.open(syn, iss, now);
        self.syn_ack_owed = false;
    }

    /// The window offered: the room left for data the adapter cannot take yet (it takes a
    /// request only while the replies have room for its largest reply).
    fn window(&self) -> u16 {
        u16::try_from(F.saturating_sub(self.rx_len)).unwrap_or(u16::MAX)
    }

    /// The least window worth announcing (RFC 9293 3.8.6.2.2's receiver silly window
    /// avoidance): half the room, or a segment.
    fn announced_window(&self) -> u16 {
        let half = u16::try_from(F / 2).unwrap_or(u16::MAX);
        half.min(self.mss)
    }

    /// Free bytes after the replies.
    fn room(&self) -> usize {
        F.saturating_mul(2).saturating_sub(self.tx_len)
    }

    /// Sequence numbers sent and not acknowledged (our FIN included, once sent).
    fn flight(&self) -> usize {
        distance(self.snd_una, self.snd_nxt) as usize
    }

    /// The segment `seg` of this connection, as RFC 9293 3.10.7.4 says, from the sequence
    /// check on; `id` is the connection's number for the adapter.
    pub(super) fn process(
        &mut self,
        id: SocketId,
        seg: &Segment<'_>,
        now: Instant,
        app: &mut impl TcpApp,
    ) {
        let flags = seg.flags;
        if self.state == State::SynReceived && flags.syn && !flags.ack && !flags.rst {
            // The SYN again: its SYN-ACK was lost. Another SYN from the same port is left to
            // the half-open bound.
            self.syn_ack_owed |= seg.seq == self.irs;
            return;
        }
        if !self.acceptable(seg) {
            // RFC 9293's ACK, but never for a RST; for a SYN (RFC 5961 4.2) or a segment
            // without data, which no retransmission needs answered, a throttled one.
            if flags.rst {
                return;
            }
            if flags.syn || seg.len() == 0 {
                self.challenge(now);
            } else {
                self.ack_owed = true;
            }
            return;
        }
        self.heard_at = now;
        if flags.rst {
            // RFC 5961 3.2: only the exact next sequence number resets; any other in the
            // window is answered with a challenge ACK.
            if seg.seq == self.rcv_nxt {
                self.end(id, now, app);
            } else {
                self.challenge(now);
            }
            return;
        }
        if flags.syn {
            // RFC 5961 4.2: a SYN on a synchronized connection gets a challenge ACK.
            self.challenge(now);
            return;
        }
        if !flags.ack || !self.take_ack(id, seg, now, app) {
            return;
        }
        self.take_data(id, seg, now, app);
    }

    /// Owes a challenge ACK (RFC 5961) unless one was owed less than [`CHALLENGE_INTERVAL`]
    /// ago: a stream of forged segments draws a few, not one each.
    fn challenge(&mut self, now: Instant) {
        if self
            .challenged
            .is_none_or(|at| now.since(at) >= CHALLENGE_INTERVAL)
        {
            self.ack_owed = true;
            self.challenged = Some(now);
        }
    }

    /// True if `seg` is an ACK, within the window, of something a half-open connection did
    /// not send: RFC 9293 3.10.7.4 answers it with a RST.
    pub(super) fn refuses_ack(&self, seg: &Segment<'_>) -> bool {
        let Flags { ack, syn, rst, .. } = seg.flags;
        self.state == State::SynReceived
            && ack
            && !syn
            && !rst
            && seg.ack != self.snd_nxt
            && self.acceptable(seg)
    }

    /// RFC 9293 3.10.7.4's test of the segment's sequence numbers against the window.
    fn acceptable(&self, seg: &Segment<'_>) -> bool {
        let window = u32::from(self.window());
        let len = seg.len();
        match (len, window) {
            (0, 0) => seg.seq == self.rcv_nxt,
            (0, _) => within(seg.seq, self.rcv_nxt, window),
            // RFC 9293's allowance for a closed window: a segment at the next byte is taken
            // for its ACK, RST and FIN (its data waits: the replies have no room).
            (_, 0) => seg.seq == self.rcv_nxt,
            _ => {
                within(seg.seq, self.rcv_nxt, window)
                    || within(
                        seg.seq.wrapping_add(len).wrapping_sub(1),
                        self.rcv_nxt,
                        window,
                    )
            }
        }
    }

    /// The acknowledgment of `seg`; false if the segment goes no further.
    fn take_ack(
        &mut self,
        id: SocketId,
        seg: &Segment<'_>,
        now: Instant,
        app: &mut impl TcpApp,
    ) -> bool {
        let ack = seg.ack;
        if self.state == State::SynReceived {
            if ack != self.snd_nxt {
                // Not our SYN-ACK's: the server answers it before it comes here
                // (`refuses_ack`); dropped if it ever does.
                return false;
            }
            self.state = State::Established;
            self.snd_una = ack;
            self.open = true;
            self.progress_at = now;
            self.learn_window(seg);
            app.accepted(id, self.peer, now);
            return true;
        }
        if lt(self.snd_max, ack) {
            // Acknowledges what was not sent (RFC 5961 5.2: past SND.NXT): an ACK, throttled
            // as a challenge ACK (its section 7: a stream of such forged segments draws a
            // few, not one each), and the segment is dropped.
            self.challenge(now);
            return false;
        }
        if lt(ack, self.snd_una.wrapping_sub(self.max_snd_wnd)) {
            // Older than any window the peer offered (RFC 5961 5.2, against blind data
            // injection): a challenge ACK, and the segment is dropped.
            self.challenge(now);
            return false;
        }
        if lt(self.snd_una, ack) {
            self.acknowledged(ack, now);
        }
        self.learn_window(seg);
        self.state != State::Free
    }

    /// The peer acknowledged up to `ack` (new, and not past what was sent).
    fn acknowledged(&mut self, ack: u32, now: Instant) {
        let acked = ack.wrapping_sub(self.snd_una) as usize;
        let data = acked.min(self.tx_len);
        let tx = self.tx.as_flattened_mut();
        tx.copy_within(data..self.tx_len, 0);
        self.tx_len = self.tx_len.saturating_sub(data);
        self.snd_una = ack;
        if lt(self.snd_nxt, ack) {
            self.snd_nxt = ack;
        }
        self.progress_at = now;
        if let Some((probe, sent)) = self.rtt_probe {
            if le(probe, ack) {
                self.sample_rtt(now.since(sent));
                self.rtt_probe = None;
            }
        }
        // Armed while replies wait, sent or not: a closed window is probed at it.
        let waiting = self.flight() > 0 || self.tx_len > 0;
        self.retransmit_at = waiting.then(|| now.add(self.rto));
        if acked > data {
            // Our FIN, which follows the data, is acknowledged.
            self.fin = false;
            self.state = match self.state {
                State::FinWait1 => State::FinWait2,
                // An ACK still owed (the peer's FIN came in the same burst) goes first.
                State::Closing | State::LastAck if self.ack_owed => State::LastAckOwed,
                State::Closing | State::LastAck => State::Free,
                other => other,
            };
        }
    }

    /// Learns the peer's window from `seg` unless an older segment than the last one
    /// taught it (RFC 9293 3.10.7.4, SND.WL1 and SND.WL2).
    fn learn_window(&mut self, seg: &Segment<'_>) {
        if lt(self.snd_wl1, seg.seq) || (self.snd_wl1 == seg.seq && le(self.snd_wl2, seg.ack)) {
            self.snd_wnd = u32::from(seg.window);
            self.max_snd_wnd = self.max_snd_wnd.max(self.snd_wnd);
            self.snd_wl1 = seg.seq;
            self.snd_wl2 = seg.ack;
        }
    }

    /// A round trip of `rtt` measured (RFC 6298 2.2, 2.3).
    fn sample_rtt(&mut self, rtt: Duration) {
        let r = rtt.as_micros();
        let (srtt, rttvar) = match self.srtt {
            None => (r, r / 2),
            Some((s, v)) => (
                s.saturating_mul(7).saturating_add(r) / 8,
                v.saturating_mul(3).saturating_add(s.abs_diff(r)) / 4,
            ),
        };
        self.srtt = Some((srtt, rttvar));
        let rto = Duration::from_micros(srtt.saturating_add(rttvar.saturating_mul(4)));
        self.rto = rto.clamp(MIN_RTO, MAX_RTO);
    }

    /// The data and FIN of `seg`, in order only: the data goes to the adapter while the
    /// replies have room for another.
    fn take_data(&mut self, id: SocketId, seg: &Segment<'_>, now: Instant, app: &mut impl TcpApp) {
        if !self.receiving() {
            // The peer's FIN came already: whatever follows it (its FIN again) is answered.
            self.ack_owed |= seg.len() > 0;
            return;
        }
        // What waits goes first, now that the acknowledgment may have made room.
        self.drain(id, now, app);
        if self.peer_fin_waits || !self.receiving() {
            // The peer's FIN came (acknowledged; taken, or behind data that waits): nothing
            // follows it.
            self.ack_owed |= seg.len() > 0;
            return;
        }
        if lt(self.rcv_nxt, seg.seq) {
            // Ahead of what is expected: not kept; the ACK says what is.
            self.ack_owed = true;
            return;
        }
        let skip = distance(seg.seq, self.rcv_nxt) as usize;
        let data = seg.payload.get(skip..).unwrap_or(&[]);
        let taken = self.feed(id, data, now, app);
        self.ack_owed |= !data.is_empty();
        // The FIN, acknowledged at once; taken once the adapter has had every request
        // before it.
        if seg.flags.fin && taken == data.len() && skip <= seg.payload.len() {
            self.rcv_nxt = self.rcv_nxt.wrapping_add(1);
            self.ack_owed = true;
            if self.rx_len == 0 {
                self.peer_fin(id, now, app);
            } else {
                self.peer_fin_waits = true;
            }
        }
    }

    /// True in the states where the peer may still send data and its FIN.
    fn receiving(&self) -> bool {
        matches!(
            self.state,
            State::Established | State::FinWait1 | State::FinWait2
        )
    }

    /// Takes `data`, received in order: hands it to the adapter while the replies have room
    /// (unless older data waits) and keeps what is left, within the window offered; returns
    /// the bytes taken.
    fn feed(&mut self, id: SocketId, data: &[u8], now: Instant, app: &mut impl TcpApp) -> usize {
        if !self.open {
            // Closed by the adapter: what still arrives is acknowledged and dropped.
            self.advance(data.len());
            return data.len();
        }
        let handed = if self.rx_len == 0 {
            self.hand(id, data, now, app)
        } else {
            Some(0)
        };
        let Some(handed) = handed else {
            // The adapter closed the connection: the rest is acknowledged and dropped.
            self.advance(data.len());
            return data.len();
        };
        let rest = data.get(handed..).unwrap_or(&[]);
        // Nearly always nothing is left: no call, no copy of nothing on the request's path.
        let kept = if rest.is_empty() { 0 } else { self.keep(rest) };
        let taken = handed.saturating_add(kept);
        self.advance(taken);
        taken
    }

    /// Keeps what of `rest` the window offered has room for; returns its length.
    fn keep(&mut self, rest: &[u8]) -> usize {
        let free = self.rx.get_mut(self.rx_len..).unwrap_or(&mut []);
        let kept = rest.len().min(free.len());
        if let (Some(to), Some(from)) = (free.get_mut(..kept), rest.get(..kept)) {
            to.copy_from_slice(from);
        }
        self.rx_len = self.rx_len.saturating_add(kept);
        kept
    }

    /// Hands the data that waits to the adapter while the replies have room; a window that
    /// grows from less than [`Self::announced_window`] to at least that is announced.
    fn drain(&mut self, id: SocketId, now: Instant, app: &mut impl TcpApp) {
        if self.rx_len == 0 || self.room() < F {
            return;
        }
        let least = self.announced_window();
        let small = self.window() < least;
        // A copy: the adapter's replies go into the same connection (a rare path: only
        // pipelined requests whose replies outgrew the room wait).
        let rx = self.rx;
        let waiting = rx.get(..self.rx_len).unwrap_or(&[]);
        match self.hand(id, waiting, now, app) {
            Some(handed) => {
                self.rx.copy_within(handed..self.rx_len, 0);
                self.rx_len = self.rx_len.saturating_sub(handed);
            }
            None => self.rx_len = 0,
        }
        self.ack_owed |= small && self.window() >= least;
        // The adapter has had every request before the peer's FIN: the FIN is taken.
        if self.rx_len == 0 && core::mem::take(&mut self.peer_fin_waits) {
            self.peer_fin(id, now, app);
        }
    }

    /// Hands `data` to the adapter while the replies have room for its largest reply;
    /// returns the bytes it took, or `None` if it closed the connection. Inlined: it is the
    /// explicit request's path.
    #[inline(always)]
    fn hand(
        &mut self,
        id: SocketId,
        data: &[u8],
        now: Instant,
        app: &mut impl TcpApp,
    ) -> Option<usize> {
        let mut taken = 0;
        while let Some(rest) = data.get(taken..).filter(|r| !r.is_empty()) {
            if self.room() < F {
                break;
            }
            let was_empty = self.tx_len == 0;
            let room = self
                .tx
                .as_flattened_mut()
                .get_mut(self.tx_len..)
                .unwrap_or(&mut []);
            let outcome = app.receive(id, rest, now, room);
            let consumed = outcome.consumed.min(rest.len());
            let reply = outcome.reply_len.min(room.len());
            self.tx_len = self.tx_len.saturating_add(reply);
            if was_empty && reply > 0 {
                self.progress_at = now;
            }
            taken = taken.saturating_add(consumed);
            if outcome.reset.is_some() {
                self.reset = outcome.reset;
            }
            if outcome.close {
                self.close(id, now, app);
                return None;
            }
            if consumed == 0 {
                break;
            }
        }
        Some(taken)
    }

    /// `n` more bytes received in order.
    fn advance(&mut self, n: usize) {
        let n = u32::try_from(n).unwrap_or(u32::MAX);
        self.rcv_nxt = self.rcv_nxt.wrapping_add(n);
    }

    /// The peer's FIN came, in order.
    fn peer_fin(&mut self, id: SocketId, now: Instant, app: &mut impl TcpApp) {
        match self.state {
            State::Established => {
                self.tell_closed(id, now, app);
                self.fin = true;
                self.since = now;
                self.state = State::LastAck;
            }
            State::FinWait1 => self.state = State::Closing,
            State::FinWait2 => self.state = State::LastAckOwed,
            _ => {}
        }
    }

    /// The adapter, or its inactivity timeout, closes the connection: our FIN follows the
    /// replies.
    pub(super) fn close(&mut self, id: SocketId, now: Instant, app: &mut impl TcpApp) {
        self.tell_closed(id, now, app);
        if self.state == State::Established {
            self.fin = true;
            self.since = now;
            self.state = State::FinWait1;
        }
        // A peer's FIN behind the requests just dropped is taken now.
        if core::mem::take(&mut self.peer_fin_waits) {
            self.peer_fin(id, now, app);
        }
    }

    /// Resets the connection: a RST goes, and the slot is free.
    pub(super) fn abort(&mut self, id: SocketId, now: Instant, app: &mut impl TcpApp) {
        if self.state != State::Free {
            self.tell_closed(id, now, app);
            self.rst_owed = true;
        }
    }

    /// The peer reset the connection: the slot is free.
    fn end(&mut self, id: SocketId, now: Instant, app: &mut impl TcpApp) {
        self.tell_closed(id, now, app);
        self.state = State::Free;
    }

    /// Tells the adapter the session ended, once; requests still waiting are dropped (no
    /// session takes them).
    fn tell_closed(&mut self, id: SocketId, now: Instant, app: &mut impl TcpApp) {
        self.rx_len = 0;
        if core::mem::take(&mut self.open) {
            app.closed(id, now);
        }
    }
}
