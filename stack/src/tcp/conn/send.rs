//! What a connection sends: its next segment (the SYN-ACK, a RST, data from the replies
//! within the peer's window and segment size, our FIN, an ACK), and whether it owes one.

use core::ops::Range;

use super::super::seq::{le, lt};
use super::super::{Flags, Outgoing, MSS};
use super::{Conn, State};
use crate::Instant;

impl<const F: usize> Conn<F> {
    /// The next segment this connection sends, and the range of its data in
    /// [`Self::bytes`]; its sequence numbers count as sent.
    pub(in crate::tcp) fn transmit(&mut self, now: Instant) -> Option<(Outgoing, Range<usize>)> {
        let ack = Flags {
            ack: true,
            ..Flags::default()
        };
        match self.state {
            State::Free => return None,
            _ if self.rst_owed => {
                self.rst_owed = false;
                self.state = State::Free;
                // With the ACK: a peer whose SYN-ACK was lost (still in SYN-SENT) takes it too.
                // A closed window took nothing past the oldest unacknowledged byte (a probe's
                // byte included), and only a RST at its next byte resets it (RFC 5961 3.2).
                let seq = if self.snd_wnd == 0 {
                    self.snd_una
                } else {
                    self.snd_max
                };
                let mut out = self.segment(seq, Flags { rst: true, ..ack });
                out.window = 0;
                return Some((out, 0..0));
            }
            State::SynReceived => {
                if !core::mem::take(&mut self.syn_ack_owed) {
                    return None;
                }
                let mut out = self.segment(self.iss, Flags { syn: true, ..ack });
                out.mss = Some(MSS);
                return Some((out, 0..0));
            }
            State::LastAckOwed => {
                self.state = State::Free;
                return Some((self.segment(self.snd_max, ack), 0..0));
            }
            _ => {}
        }
        let flight = self.flight();
        let sent = flight.min(self.tx_len);
        let unsent = self.tx_len.saturating_sub(sent);
        let len = if core::mem::take(&mut self.probe_owed) {
            // The probe, or what a small window takes once it has waited (RFC 9293
            // 3.8.6.2.1's override timeout): at least a byte.
            unsent.min(self.usable().max(1)).min(usize::from(self.mss))
        } else {
            self.sendable(unsent)
        };
        let fin_due = self.fin && flight <= self.tx_len && unsent == len;
        if len > 0 || fin_due {
            let seq = self.snd_nxt;
            if self.snd_una == self.snd_max && len == 0 {
                // Our FIN alone, and nothing was waiting for the peer: its wait starts now (a
                // FIN after a quiet spell is not overdue). Replies started theirs when they
                // were written, and a closed window's probe does not restart it.
                self.progress_at = now;
            }
            let step = u32::try_from(len)
                .unwrap_or(0)
                .saturating_add(u32::from(fin_due));
            self.snd_nxt = seq.wrapping_add(step);
            if lt(self.snd_max, self.snd_nxt) {
                if le(self.snd_max, seq) && self.rtt_probe.is_none() {
                    // New data only (Karn): its acknowledgment times a round trip.
                    self.rtt_probe = Some((self.snd_nxt, now));
                }
                self.snd_max = self.snd_nxt;
            }
            if self.retransmit_at.is_none() {
                self.retransmit_at = Some(now.add(self.rto));
            }
            self.ack_owed = false;
            let flags = Flags {
                psh: len > 0 && unsent == len,
                fin: fin_due,
                ..ack
            };
            return Some((self.segment(seq, flags), sent..sent.saturating_add(len)));
        }
        if unsent > 0 && self.retransmit_at.is_none() {
            // The peer's window is closed: probed at the retransmission timeout.
            self.retransmit_at = Some(now.add(self.rto));
        }
        if core::mem::take(&mut self.ack_owed) {
            // From the highest number sent: a retransmission timeout rewinds `snd_nxt`, and
            // a peer drops a segment below what it has received.
            return Some((self.segment(self.snd_max, ack), 0..0));
        }
        None
    }

    /// What the peer's window takes now beyond what is in flight.
    fn usable(&self) -> usize {
        (self.snd_wnd as usize).saturating_sub(self.flight())
    }

    /// The bytes of the `unsent` replies a segment carries now: a whole segment or the rest
    /// of the replies, or at least half the largest window the peer offered; less waits
    /// (RFC 9293 3.8.6.2.1, the sender's silly window avoidance), to go at the timeout.
    fn sendable(&self, unsent: usize) -> usize {
        let whole = unsent.min(usize::from(self.mss));
        let len = whole.min(self.usable());
        let half_window = (self.max_snd_wnd / 2) as usize;
        if len == whole || (len > 0 && len >= half_window) {
            len
        } else {
            0
        }
    }

    /// True if replies wait for a window too small for them (or closed): probed at the
    /// retransmission timeout.
    pub(super) fn window_holds_replies(&self) -> bool {
        let unsent = self.tx_len.saturating_sub(self.flight());
        unsent > 0 && self.sendable(unsent) == 0
    }

    /// A segment of this connection from `seq` with `flags`, acknowledging what came.
    fn segment(&self, seq: u32, flags: Flags) -> Outgoing {
        Outgoing {
            peer: self.peer,
            seq,
            ack: self.rcv_nxt,
            flags,
            window: self.window(),
            mss: None,
        }
    }

    /// The replies' bytes in `range` (from [`Self::transmit`]).
    pub(in crate::tcp) fn bytes(&self, range: Range<usize>) -> &[u8] {
        self.tx.as_flattened().get(range).unwrap_or(&[])
    }

    /// True if a segment is owed now ([`Self::transmit`] has one).
    pub(in crate::tcp) fn owes(&self) -> bool {
        match self.state {
            State::Free => false,
            State::SynReceived => self.syn_ack_owed || self.rst_owed,
            State::LastAckOwed => true,
            _ => {
                let flight = self.flight();
                let unsent = self.tx_len.saturating_sub(flight);
                self.rst_owed
                    || self.ack_owed
                    || self.probe_owed
                    || self.sendable(unsent) > 0
                    || (self.fin && flight <= self.tx_len && unsent == 0)
            }
        }
    }
}
