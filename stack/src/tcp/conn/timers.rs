//! A connection's timers: the half-open and linger bounds, the adapter's inactivity
//! timeout, retransmission, giving up on a silent peer or one whose window stays closed,
//! and the Identity Reset handed over once its reply is acknowledged.

use super::super::{TcpApp, GIVE_UP, HALF_OPEN, LINGER, WRITE_TIMEOUT};
use super::{Conn, State, MAX_RTO};
use crate::{Duration, Instant, SocketId};

impl<const F: usize> Conn<F> {
    /// The connection's timers at `now`: the half-open and linger bounds, the adapter's
    /// inactivity timeout, retransmission, and giving up on the peer ([`Self::give_up_at`]).
    pub(in crate::tcp) fn poll(&mut self, id: SocketId, now: Instant, app: &mut impl TcpApp) {
        match self.state {
            State::Free | State::LastAckOwed => return,
            State::SynReceived if now >= self.since.add(HALF_OPEN) => {
                // Dropped without a RST: a forged source would not read it, and a client
                // whose SYN-ACK was lost sends its SYN again and finds a free connection.
                self.state = State::Free;
                return;
            }
            State::FinWait1 | State::FinWait2 | State::Closing | State::LastAck
                if now >= self.since.add(LINGER) =>
            {
                self.abort(id, now, app);
                return;
            }
            State::Established if app.idle_deadline(id).is_some_and(|at| at <= now) => {
                self.close(id, now, app);
            }
            _ => {}
        }
        if self.give_up_at().is_some_and(|at| now >= at) {
            self.abort(id, now, app);
            return;
        }
        if self.retransmit_at.is_some_and(|at| at <= now) {
            // Go back to the oldest unacknowledged byte, with the timeout doubled (RFC 6298
            // 5.4-5.6); a window closed or too small for what waits is probed (or what it
            // takes goes: the silly window avoidance's override).
            self.snd_nxt = self.snd_una;
            self.probe_owed = self.window_holds_replies();
            self.rtt_probe = None;
            self.rto = Duration::from_micros(self.rto.as_micros().saturating_mul(2)).min(MAX_RTO);
            self.retransmit_at = None;
        }
    }

    /// Replies or our FIN wait for the peer's acknowledgment.
    fn waiting(&self) -> bool {
        self.state != State::SynReceived && (self.tx_len > 0 || self.flight() > 0)
    }

    /// Since when the peer has sent nothing while something waits for it.
    fn quiet_since(&self) -> Instant {
        self.heard_at.max(self.progress_at)
    }

    /// When the connection is reset for its peer, while something waits for it: silent for
    /// [`GIVE_UP`], or its window closed to the replies for [`WRITE_TIMEOUT`].
    fn give_up_at(&self) -> Option<Instant> {
        if !self.waiting() {
            return None;
        }
        let silent = self.quiet_since().add(GIVE_UP);
        let closed = self.snd_wnd == 0 && self.tx_len > 0;
        let stalled = closed.then(|| self.progress_at.add(WRITE_TIMEOUT));
        Some(stalled.map_or(silent, |at| at.min(silent)))
    }

    /// True if the peer has sent nothing for [`WRITE_TIMEOUT`] while something waits for
    /// it: a new client may take its place.
    pub(in crate::tcp) fn stale(&self, now: Instant) -> bool {
        self.waiting() && now >= self.quiet_since().add(WRITE_TIMEOUT)
    }

    /// When [`Self::poll`] has something to do, for the adapter `app` (its inactivity
    /// timeout on connection `id`).
    pub(in crate::tcp) fn deadline(&self, id: SocketId, app: &impl TcpApp) -> Option<Instant> {
        let bound = match self.state {
            State::Free | State::LastAckOwed => return None,
            State::SynReceived => Some(self.since.add(HALF_OPEN)),
            State::Established => app.idle_deadline(id),
            _ => Some(self.since.add(LINGER)),
        };
        [bound, self.give_up_at(), self.retransmit_at]
            .into_iter()
            .flatten()
            .min()
    }

    /// The Identity Reset accepted on this connection, once its reply is acknowledged or
    /// the connection ended (or is being reset).
    pub(in crate::tcp) fn take_reset(&mut self) -> Option<u8> {
        let flushed =
            self.tx_len == 0 || self.rst_owed || !matches!(self.state, State::Established);
        if flushed {
            self.reset.take()
        } else {
            None
        }
    }
}
