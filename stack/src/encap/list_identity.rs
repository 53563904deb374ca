//! ListIdentity replies: the identity item, the queue of replies to broadcast requests
//! that wait a random delay bounded by the requester's maximum (sender context bytes 0-1),
//! and the byte budget every ListIdentity reply over UDP is charged to
//! ([`LIST_IDENTITY_UDP_BYTES_PER_SECOND`]).

use core::net::SocketAddrV4;

use crate::config::{LIST_IDENTITY_UDP_BYTES_PER_SECOND, MAX_PENDING_LIST_IDENTITY};
use crate::rng::Rng;
use crate::time::{Duration, Instant};

/// The longest delay a requester may ask for, and the delay used when it asks for 0.
const MAX_DELAY_MS: u64 = 2000;
/// The delay used when the requester asks for 1..=499 ms.
const MIN_DELAY_MS: u64 = 500;

/// The upper bound of the reply delay for a request with `sender_context`.
pub fn max_delay(sender_context: &[u8; 8]) -> Duration {
    let asked = u64::from(u16::from_le_bytes([sender_context[0], sender_context[1]]));
    Duration::from_millis(match asked {
        0 => MAX_DELAY_MS,
        1..=499 => MIN_DELAY_MS,
        n => n.min(MAX_DELAY_MS),
    })
}

/// A reply waiting for its moment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pending {
    /// Where to send it.
    pub to: SocketAddrV4,
    /// The request's sender context, echoed.
    pub sender_context: [u8; 8],
    /// The request's session handle field, echoed.
    pub session_handle: u32,
    /// When to send it.
    pub due: Instant,
}

/// A token bucket of reply bytes: [`LIST_IDENTITY_UDP_BYTES_PER_SECOND`] a second, at most
/// one second's worth saved up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReplyBudget {
    /// Bytes that may go out now, in millionths of a byte (the refill is per microsecond).
    micro_bytes: u64,
    /// When `micro_bytes` was last brought up to date (`None`: never, the bucket is full).
    at: Option<Instant>,
}

impl ReplyBudget {
    /// The most the bucket holds, in millionths of a byte.
    const FULL: u64 = LIST_IDENTITY_UDP_BYTES_PER_SECOND as u64 * 1_000_000;

    /// A full bucket.
    pub const fn new() -> Self {
        ReplyBudget {
            micro_bytes: Self::FULL,
            at: None,
        }
    }

    /// Takes `len` bytes from the budget at `now`; false (nothing taken) if it holds fewer.
    pub fn take(&mut self, len: usize, now: Instant) -> bool {
        let refill = self.at.map_or(Self::FULL, |at| {
            now.since(at)
                .as_micros()
                .saturating_mul(u64::from(LIST_IDENTITY_UDP_BYTES_PER_SECOND))
        });
        self.micro_bytes = self.micro_bytes.saturating_add(refill).min(Self::FULL);
        self.at = Some(now);
        let cost = (len as u64).saturating_mul(1_000_000);
        match self.micro_bytes.checked_sub(cost) {
            Some(left) => {
                self.micro_bytes = left;
                true
            }
            None => false,
        }
    }
}

impl Default for ReplyBudget {
    fn default() -> Self {
        Self::new()
    }
}

/// The fixed-size queue of delayed replies (at most `L` wait at once), and the byte budget
/// of all UDP replies.
#[derive(Debug, Clone, Default)]
pub struct DelayedReplies<const L: usize = MAX_PENDING_LIST_IDENTITY> {
    queue: heapless::Vec<Pending, L>,
    /// What every ListIdentity reply over UDP, delayed or not, is charged to.
    pub budget: ReplyBudget,
}

impl<const L: usize> DelayedReplies<L> {
    /// An empty queue.
    pub const fn new() -> Self {
        DelayedReplies {
            queue: heapless::Vec::new(),
            budget: ReplyBudget::new(),
        }
    }
    /// True if another reply can wait.
    pub fn has_room(&self) -> bool {
        !self.queue.is_full()
    }
    /// Queues a reply due at a random instant within the requester's bound; `false` if full.
    pub fn schedule(
        &mut self,
        to: SocketAddrV4,
        sender_context: [u8; 8],
        session_handle: u32,
        now: Instant,
        rng: &mut Rng,
    ) -> bool {
        let delay = rng.below_or_equal(max_delay(&sender_context).as_micros());
        let due = now.add(Duration::from_micros(delay));
        self.queue
            .push(Pending {
                to,
                sender_context,
                session_handle,
                due,
            })
            .is_ok()
    }
    /// Removes and returns a reply that is due at `now`.
    pub fn take_due(&mut self, now: Instant) -> Option<Pending> {
        let i = self.queue.iter().position(|p| p.due <= now)?;
        Some(self.queue.swap_remove(i))
    }
    /// The earliest due instant.
    pub fn next_due(&self) -> Option<Instant> {
        self.queue.iter().map(|p| p.due).min()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn delay_bounds_follow_the_rule() {
        let ctx = |ms: u16| {
            let mut c = [0u8; 8];
            c[..2].copy_from_slice(&ms.to_le_bytes());
            c
        };
        assert_eq!(max_delay(&ctx(0)), Duration::from_millis(2000));
        assert_eq!(max_delay(&ctx(1)), Duration::from_millis(500));
        assert_eq!(max_delay(&ctx(499)), Duration::from_millis(500));
        assert_eq!(max_delay(&ctx(800)), Duration::from_millis(800));
        assert_eq!(max_delay(&ctx(9000)), Duration::from_millis(2000));
    }

    #[test]
    fn replies_come_due_within_the_bound() {
        let mut q: DelayedReplies = DelayedReplies::new();
        let mut rng = Rng::new(7);
        let to = SocketAddrV4::new(core::net::Ipv4Addr::new(198, 18, 0, 1), 44818);
        for _ in 0..MAX_PENDING_LIST_IDENTITY {
            assert!(q.schedule(to, [0xF4, 1, 0, 0, 0, 0, 0, 0], 0, Instant(1000), &mut rng));
        }
        assert!(!q.schedule(to, [0; 8], 0, Instant(1000), &mut rng));
        let last = q.next_due().unwrap();
        assert!(last >= Instant(1000) && last <= Instant(1000 + 500_000));
        let mut n = 0;
        while q.take_due(Instant(1000 + 500_000)).is_some() {
            n += 1;
        }
        assert_eq!(n, MAX_PENDING_LIST_IDENTITY);
    }

    #[test]
    fn the_budget_holds_a_second_and_refills_at_its_rate() {
        let rate = u64::from(LIST_IDENTITY_UDP_BYTES_PER_SECOND);
        let mut b = ReplyBudget::new();
        let t0 = Instant(5_000_000);
        let mut sent = 0u64;
        while b.take(100, t0) {
            sent += 100;
        }
        assert_eq!(sent, rate / 100 * 100, "a full second's worth at once");
        assert!(b.take((rate % 100) as usize, t0));
        assert!(!b.take(1, t0), "empty");
        // A quarter second later, a quarter of the rate.
        let t1 = t0.add(Duration::from_millis(250));
        assert!(b.take((rate / 4) as usize, t1));
        assert!(!b.take(1, t1));
        // Long idle: never more than one second's worth.
        let t2 = t1.add(Duration::from_secs(3600));
        assert!(b.take(rate as usize, t2));
        assert!(!b.take(1, t2));
        // A clock that goes backwards gives nothing.
        assert!(!b.take(1, Instant(0)));
    }
}
