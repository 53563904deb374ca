//! The production schedule: when each producer of the connection table is next due, and the
//! producers in the order they are due (a list linked both ways, kept in order as they move),
//! so the first is known without a scan. A producer that stays between its neighbours (a
//! single producer, or one faster than the rest) compares with them alone; the first going
//! behind the last (equal RPIs taking turns) moves there after one more comparison; any other
//! move is placed from the back of the list, where a scan of every deadline used to find the
//! new first.

use crate::time::Instant;

/// The producers' deadlines by table slot (`C` slots), and their order.
#[derive(Debug, Clone)]
pub(crate) struct Schedule<const C: usize> {
    /// Per slot: when its producer is next due (`Instant::NEVER` for none).
    due: [Instant; C],
    /// The scheduled slots (those with a deadline), by deadline and the lower slot first on
    /// a tie, linked through [`Self::END`] both ways: `next[s]` follows `s`, `prev[s]`
    /// precedes it. The links of a slot without a deadline mean nothing.
    next: [u8; C],
    prev: [u8; C],
    /// `next[END]` and `prev[END]`: the first and the last producer.
    end: (u8, u8),
    /// The head of the list and its deadline, as every poll asks for them: a summary that
    /// every [`Schedule::set`] keeps.
    first: (usize, Instant),
    /// The offset of the adapter's production grids (`io/timing.rs`), kept here where it
    /// takes no room of its own (the links leave two bytes spare).
    grid_offset: u16,
}

impl<const C: usize> Schedule<C> {
    /// The end of the list, in both directions: `next[END]` is the first producer,
    /// `prev[END]` the last; `END` itself as a slot is never due.
    pub(crate) const END: usize = C;
    /// Nothing scheduled; the production grids have the offset `grid_offset`.
    pub(crate) const fn new(grid_offset: u16) -> Self {
        const { assert!(C < u8::MAX as usize, "slots fit the list's links") };
        Schedule {
            due: [Instant::NEVER; C],
            next: [C as u8; C],
            prev: [C as u8; C],
            end: (C as u8, C as u8),
            first: (C, Instant::NEVER),
            grid_offset,
        }
    }

    /// The phase of the adapter's production grid of `rpi`: the offset modulo `rpi`.
    #[inline]
    pub(crate) fn grid_phase(&self, rpi: u32) -> u32 {
        u32::from(self.grid_offset).checked_rem(rpi).unwrap_or(0)
    }

    /// The slot due first and when (`Instant::NEVER`, and no slot of the table, if none
    /// produces).
    #[inline]
    pub(crate) fn first(&self) -> (usize, Instant) {
        self.first
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
        let listed = *d != Instant::NEVER;
        *d = at;
        // Alone in the list, it stays first.
        if self.first.0 == slot && usize::from(self.end.1) == slot && listed && at != Instant::NEVER
        {
            self.first.1 = at;
            return;
        }
        self.moved(slot, at, listed);
    }

    /// [`Self::set`] of `slot` to `at` (`listed` before) among others, or into or out of the
    /// list. Out of line: a single producer never comes here.
    #[inline(never)]
    fn moved(&mut self, slot: usize, at: Instant, listed: bool) {
        if listed && at != Instant::NEVER {
            let last = usize::from(self.end.1);
            if slot == usize::from(self.end.0) {
                // Behind the last now (producers of one RPI taking turns): moved there,
                // asked first as the commonest move of a first with others behind it.
                let n = self.next(slot);
                if self.before(last, slot) {
                    self.join(Self::END, n);
                    self.join(last, slot);
                    self.join(slot, Self::END);
                    self.first = (n, self.at(n));
                    return;
                }
                // Still before the next: the order stands.
                if self.before(slot, n) {
                    self.first.1 = at;
                    return;
                }
            } else {
                // Still after the one before it and before the one after it.
                let (p, n) = (self.prev(slot), self.next(slot));
                if self.before(p, slot) && (n == Self::END || self.before(slot, n)) {
                    return;
                }
            }
        }
        self.reorder(slot, listed);
    }

    /// Takes `slot` out of the list if it is `listed`, and puts it back in its place if it
    /// has a deadline. Inline in [`Self::moved`], whose common moves (one that stays first,
    /// or goes behind the last) return before it.
    #[inline(always)]
    fn reorder(&mut self, slot: usize, listed: bool) {
        if listed {
            self.join(self.prev(slot), self.next(slot));
        }
        if self.at(slot) != Instant::NEVER {
            self.insert(slot);
        }
        let head = self.next(Self::END);
        self.first = (head, self.at(head));
    }

    /// Puts `slot` (not in the list) in its place, looking from the back.
    fn insert(&mut self, slot: usize) {
        let mut p = self.prev(Self::END);
        // Bounded: the list holds at most every slot once.
        for _ in 0..C {
            if p == Self::END || self.before(p, slot) {
                break;
            }
            p = self.prev(p);
        }
        let n = self.next(p);
        self.join(p, slot);
        self.join(slot, n);
    }

    /// True if `a` is due before `b`: earlier, or at the same time with the lower slot.
    #[inline]
    fn before(&self, a: usize, b: usize) -> bool {
        (self.at(a), a) < (self.at(b), b)
    }

    /// The slot after `s` in the list (`END` after the last).
    #[inline]
    fn next(&self, s: usize) -> usize {
        usize::from(self.next.get(s).copied().unwrap_or(self.end.0))
    }

    /// The slot before `s` in the list (`END` before the first).
    #[inline]
    fn prev(&self, s: usize) -> usize {
        usize::from(self.prev.get(s).copied().unwrap_or(self.end.1))
    }

    /// Links `a` to `b`: `b` follows `a`.
    #[inline]
    fn join(&mut self, a: usize, b: usize) {
        let n = self.next.get_mut(a).unwrap_or(&mut self.end.0);
        *n = b as u8;
        let p = self.prev.get_mut(b).unwrap_or(&mut self.end.1);
        *p = a as u8;
    }
}

#[cfg(test)]
mod tests {
    use super::Instant;
    use crate::config::MAX_CONNECTIONS;

    /// The schedule of the default table.
    type Schedule = super::Schedule<MAX_CONNECTIONS>;

    /// Checks `s` against the deadlines themselves: the first is the earliest (lowest slot on
    /// a tie), and the list holds every scheduled slot once, in order, linked both ways.
    fn check<const C: usize>(s: &super::Schedule<C>) -> (usize, Instant) {
        let end = C;
        let first_at = s.due.iter().copied().min().unwrap();
        let (slot, at) = s.first();
        assert_eq!(
            (slot, at),
            (s.next(end), s.at(s.next(end))),
            "the summary is the head"
        );
        assert_eq!(at, first_at);
        if at != Instant::NEVER {
            assert_eq!(slot, s.due.iter().position(|&d| d == first_at).unwrap());
        } else {
            assert_eq!(slot, end, "nothing scheduled");
        }
        let mut listed = heapless::Vec::<usize, C>::new();
        let mut p = end;
        loop {
            let n = s.next(p);
            assert_eq!(s.prev(n), p, "links both ways");
            if n == end {
                break;
            }
            listed.push(n).expect("no loop");
            p = n;
        }
        let mut expected: heapless::Vec<usize, C> =
            (0..C).filter(|&i| s.due[i] != Instant::NEVER).collect();
        expected.sort_unstable_by_key(|&i| (s.due[i], i));
        assert_eq!(listed, expected);
        (slot, at)
    }

    #[test]
    fn the_earliest_comes_first_and_the_lower_slot_on_a_tie() {
        let mut s = Schedule::new(0);
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
        take_turns::<MAX_CONNECTIONS>();
        take_turns::<64>();
    }

    /// Every one of `C` slots due at once, then each one RPI later: they go in slot order.
    fn take_turns<const C: usize>() {
        let mut s = super::Schedule::<C>::new(0);
        for slot in 0..C {
            s.set(slot, Instant(0));
        }
        for n in 0..5 * C {
            let (slot, at) = check(&s);
            assert_eq!(slot, n % C);
            s.set(slot, Instant(at.0 + 1_000));
        }
    }

    #[test]
    fn a_producer_faster_than_the_others_stays_first_until_they_are_due() {
        let mut s = Schedule::new(0);
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
        any_sequence_of_moves::<MAX_CONNECTIONS>();
        any_sequence_of_moves::<64>();
    }

    /// Random deadlines for random slots of `C`, checked after each move.
    fn any_sequence_of_moves<const C: usize>() {
        let mut s = super::Schedule::<C>::new(0);
        let mut x = 0x2545_F491_4F6C_DD1Du64;
        for _ in 0..20_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let slot = (x % C as u64) as usize;
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
