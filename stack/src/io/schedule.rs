//! The production schedule: when each producer of the connection table is next due, and which
//! is due first, known without a scan. Only a production that lets another producer come
//! first looks at the others; a single producer, or one faster than the rest, never does.

use crate::config::MAX_CONNECTIONS;
use crate::time::Instant;

/// The producers' deadlines by table slot, and the first of them.
#[derive(Debug, Clone)]
pub(crate) struct Schedule {
    /// Per slot: when its producer is next due (`Instant::NEVER` for none).
    due: [Instant; MAX_CONNECTIONS],
    /// The earliest deadline and its slot, the lowest of equal ones: exact at all times.
    first_at: Instant,
    first_slot: usize,
    /// No slot but `first_slot` is due before this: a lower bound, exact after a scan.
    others: Instant,
    /// One past the highest slot a scan found scheduled; later ones are scheduled only by a
    /// `set`, which moves it.
    end: usize,
}

impl Schedule {
    /// Nothing scheduled.
    pub(crate) const fn new() -> Self {
        Schedule {
            due: [Instant::NEVER; MAX_CONNECTIONS],
            first_at: Instant::NEVER,
            first_slot: 0,
            others: Instant::NEVER,
            end: 0,
        }
    }

    /// The slot due first and when (`Instant::NEVER` if none produces).
    #[inline]
    pub(crate) fn first(&self) -> (usize, Instant) {
        (self.first_slot, self.first_at)
    }

    /// When the producer in `slot` is next due (`Instant::NEVER` for none).
    #[inline]
    pub(crate) fn at(&self, slot: usize) -> Instant {
        self.due.get(slot).copied().unwrap_or(Instant::NEVER)
    }

    /// The producer in `slot` is next due `at` (`Instant::NEVER`: it no longer produces).
    #[inline]
    pub(crate) fn set(&mut self, slot: usize, at: Instant) {
        let Some(d) = self.due.get_mut(slot) else {
            return;
        };
        *d = at;
        if slot == self.first_slot {
            // Still before every other (its production, when it is the only one or the
            // fastest), or else one of the others may now come first.
            if at <= self.first_at || at < self.others {
                self.first_at = at;
            } else {
                self.scan();
            }
        } else if at < self.first_at || (at == self.first_at && slot < self.first_slot) {
            // It comes first; the former first is now the earliest of the others.
            self.others = self.first_at;
            (self.first_at, self.first_slot) = (at, slot);
        } else {
            self.others = self.others.min(at);
        }
        if at != Instant::NEVER && slot >= self.end {
            self.end = slot.saturating_add(1);
        }
    }

    /// Finds the first producer and the earliest of the others.
    fn scan(&mut self) {
        let (mut slot, mut first, mut others, mut end) = (0, Instant::NEVER, Instant::NEVER, 0);
        let scheduled = self.due.get(..self.end).unwrap_or(&self.due);
        for (i, &at) in scheduled.iter().enumerate() {
            if at < first {
                (slot, first, others) = (i, at, first);
            } else if at < others {
                others = at;
            }
            if at != Instant::NEVER {
                end = i.saturating_add(1);
            }
        }
        (self.first_slot, self.first_at, self.others, self.end) = (slot, first, others, end);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Checks `s` against the deadlines themselves: the first is the earliest (lowest slot on
    /// a tie), no other is due before `others`, every scheduled slot is below `end`.
    fn check(s: &Schedule) -> (usize, Instant) {
        let first_at = s.due.iter().copied().min().unwrap();
        let (slot, at) = s.first();
        assert_eq!(at, first_at);
        if at != Instant::NEVER {
            assert_eq!(slot, s.due.iter().position(|&d| d == first_at).unwrap());
        }
        for (i, &d) in s.due.iter().enumerate() {
            if i != slot {
                assert!(d >= s.others, "slot {i} due {d:?} before {:?}", s.others);
            }
            if d != Instant::NEVER {
                assert!(i < s.end);
            }
        }
        (slot, at)
    }

    #[test]
    fn the_earliest_comes_first_and_the_lower_slot_on_a_tie() {
        let mut s = Schedule::new();
        assert_eq!(check(&s).1, Instant::NEVER);
        s.set(3, Instant(30));
        s.set(2, Instant(10));
        s.set(1, Instant(10));
        s.set(0, Instant(20));
        assert_eq!(check(&s), (1, Instant(10)));
        s.set(1, Instant(40));
        assert_eq!(check(&s), (2, Instant(10)));
        s.set(2, Instant::NEVER);
        assert_eq!(check(&s), (0, Instant(20)));
        s.set(MAX_CONNECTIONS, Instant(1)); // no such slot: nothing
        assert_eq!(check(&s), (0, Instant(20)));
    }

    #[test]
    fn equal_rpi_producers_take_turns_in_slot_order() {
        let mut s = Schedule::new();
        for slot in 0..MAX_CONNECTIONS {
            s.set(slot, Instant(0));
        }
        for n in 0..5 * MAX_CONNECTIONS {
            let (slot, at) = check(&s);
            assert_eq!(slot, n % MAX_CONNECTIONS);
            s.set(slot, Instant(at.0 + 1_000));
        }
    }

    #[test]
    fn a_producer_faster_than_the_others_stays_first_until_they_are_due() {
        let mut s = Schedule::new();
        s.set(4, Instant(10_000));
        s.set(7, Instant(1_000));
        for k in 2..10 {
            s.set(7, Instant(k * 1_000));
            assert_eq!(check(&s), (7, Instant(k * 1_000)));
        }
        s.set(7, Instant(10_000));
        assert_eq!(check(&s), (4, Instant(10_000)), "the lower slot on the tie");
        s.set(4, Instant(20_000));
        assert_eq!(check(&s), (7, Instant(10_000)));
    }

    #[test]
    fn any_sequence_of_moves_keeps_the_first_exact() {
        let mut s = Schedule::new();
        let mut x = 0x2545_F491_4F6C_DD1Du64;
        for _ in 0..20_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let slot = (x % MAX_CONNECTIONS as u64) as usize;
            let at = match (x >> 8) % 8 {
                0 => Instant::NEVER,
                1 => s.first().1, // a tie with the first
                _ => Instant((x >> 16) % 64),
            };
            s.set(slot, at);
            check(&s);
        }
    }
}
