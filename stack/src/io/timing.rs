//! The connection table's timing state, each instant stored once: per slot, when its
//! watchdog fires, when its originator was last heard, when its producer is next due and
//! whether a trigger waits; and the summaries that say what comes first without a scan (the
//! first producer, a lower bound of the watchdogs). Only [`super::table::ConnectionTable`]
//! holds one, and it changes it only through the intents here (opened, closed, fed,
//! triggered, produced), each of which keeps the summaries right.
//!
//! The production deadline is the instant the producer is due. Without a trigger it lies on
//! the grid `previous + RPI`; a trigger brings it forward to the end of the inhibit time
//! (never later than the grid's), and a production that carried a trigger starts a new grid
//! one RPI later. So the grid's own next point need not be kept beside it: while a trigger
//! waits nothing reads it, and without one it is the deadline.
//!
//! A cyclic producer is due at once when it opens; its second production moves it onto the
//! adapter's grid of its RPI, where it stays: the instants `phase + k * RPI` on the adapter's
//! clock, the phase the adapter's own (from its seed, so that two adapters, or the devices of
//! a fleet in one process, do not all produce at the same instants).
//! Cyclic producers of one RPI (or of RPIs that are multiples of each other) then come due at
//! the same instants, and the runtime serves them in one wake-up instead of one each. The
//! interval between the first two productions is from one RPI up to two, never shorter; every
//! later one is the RPI. Change-of-state and application-triggered producers keep their own
//! grid: their RPI is a heartbeat, one RPI after each production at most.

use super::schedule::Schedule;
use crate::config::FIRST_PACKET_GRACE_US;
use crate::time::{Duration, Instant};

/// The first deadline on the grid `previous + k * rpi` that is after `now` (k >= 1): a late
/// production keeps the grid, skipping the points already past.
fn advance(previous: Instant, rpi: u32, now: Instant) -> Instant {
    let rpi = u64::from(rpi.max(1));
    let next = previous.add(Duration::from_micros(rpi));
    if next > now {
        return next;
    }
    let missed = now
        .since(previous)
        .as_micros()
        .checked_div(rpi)
        .unwrap_or(0)
        .saturating_add(1);
    previous.add(Duration::from_micros(missed.saturating_mul(rpi)))
}

/// The first point of the grid `phase + k * rpi` (`phase` below `rpi`, from
/// [`Schedule::grid_phase`]) that is at `from` or later and after `now`: where a cyclic
/// producer moves at its second production. One 64-bit remainder, once per connection.
fn onto_clock_grid(from: Instant, rpi: u32, now: Instant, phase: u32) -> Instant {
    let phase = u64::from(phase);
    let earliest = from.as_micros().max(now.as_micros().saturating_add(1));
    let Some(since) = earliest.checked_sub(phase) else {
        return Instant(phase);
    };
    // How far `earliest` is past a point of the grid; the next point is the rest of the way.
    let past = since.checked_rem(u64::from(rpi)).unwrap_or(0);
    let ahead = if past == 0 {
        0
    } else {
        u64::from(rpi).saturating_sub(past)
    };
    Instant(earliest.saturating_add(ahead))
}

/// What an opened connection produces, for its timing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Produces {
    /// Nothing of its own (no producer, or it listens to another's).
    Nothing,
    /// Cyclic data: at once, then on the adapter's grid of its RPI.
    Cyclic,
    /// Change-of-state or application-triggered data: at once, then at each trigger and one
    /// RPI (its heartbeat) after each production at most.
    OnTrigger,
}

/// A producer's trigger state: a change of state or application trigger waiting, and the
/// end of the production inhibit time it waits for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Pending {
    triggered: bool,
    inhibit_until: Instant,
    /// A cyclic producer not on the adapter's grid yet: its next production moves it there.
    to_clock_grid: bool,
}

impl Pending {
    const NONE: Pending = Pending {
        triggered: false,
        inhibit_until: Instant(0),
        to_clock_grid: false,
    };
}

/// The timing state of every slot of the connection table, and its summaries.
#[derive(Debug, Clone)]
pub(super) struct Timing<const C: usize> {
    /// Per slot: when its watchdog fires (`Instant::NEVER` for an empty slot).
    expiry: [Instant; C],
    /// No watchdog fires before this instant: a lower bound that every move of an expiry
    /// keeps and a sweep ([`Timing::swept`]) makes exact, so the watchdogs are looked at
    /// only once it is reached, and [`Timing::next_deadline`] only while it is not after the
    /// first production.
    expiry_bound: Instant,
    /// Per slot: when its originator was last heard (O->T data, a Class 3 request), or when
    /// it opened.
    last_activity: [Instant; C],
    /// Per slot: the production deadline (`Instant::NEVER` for no producer of its own), and
    /// which comes first.
    schedule: Schedule<C>,
    /// Per slot: the producer's trigger state.
    pending: [Pending; C],
}

impl<const C: usize> Timing<C> {
    /// No slot open; the grids of cyclic producers have the phase `grid_offset` (modulo each
    /// RPI).
    pub(super) const fn new(grid_offset: u16) -> Self {
        Timing {
            expiry: [Instant::NEVER; C],
            expiry_bound: Instant::NEVER,
            last_activity: [Instant(0); C],
            schedule: Schedule::new(grid_offset),
            pending: [Pending::NONE; C],
        }
    }

    /// A connection opened in `slot` at `now`: its watchdog runs `timeout`, but at least the
    /// first-packet grace; if it `produces`, its producer is due at once.
    pub(super) fn open(
        &mut self,
        slot: usize,
        now: Instant,
        timeout: Duration,
        produces: Produces,
    ) {
        let grace = Duration::from_micros(timeout.as_micros().max(FIRST_PACKET_GRACE_US));
        self.heard(slot, now, now.add(grace));
        if let Some(p) = self.pending.get_mut(slot) {
            *p = Pending {
                triggered: false,
                inhibit_until: now,
                to_clock_grid: produces == Produces::Cyclic,
            };
        }
        let first = match produces {
            Produces::Nothing => Instant::NEVER,
            Produces::Cyclic | Produces::OnTrigger => now,
        };
        self.reschedule(slot, first);
    }

    /// The connection in `slot` closed: it is never due and never expires.
    pub(super) fn close(&mut self, slot: usize) {
        if let Some(e) = self.expiry.get_mut(slot) {
            // Later than any bound: the bound stays a lower bound.
            *e = Instant::NEVER;
        }
        if let Some(p) = self.pending.get_mut(slot) {
            *p = Pending::NONE;
        }
        self.reschedule(slot, Instant::NEVER);
    }

    /// The producer of `from` goes on in `to`, a connection sharing its multicast data: the
    /// same deadline and trigger state (the caller then closes `from`).
    pub(super) fn hand_over(&mut self, from: usize, to: usize) {
        let pending = self.pending.get(from).copied().unwrap_or(Pending::NONE);
        if let Some(p) = self.pending.get_mut(to) {
            *p = pending;
        }
        let at = self.schedule.at(from);
        self.reschedule(to, at);
    }

    /// The originator of `slot` was heard at `now`: its watchdog fires `timeout` later.
    #[inline]
    pub(super) fn feed(&mut self, slot: usize, now: Instant, timeout: Duration) {
        self.heard(slot, now, now.add(timeout));
    }

    /// Heard at `now`, the watchdog of `slot` now fires `expires` (traffic can bring it
    /// earlier than the first-packet grace: the bound follows).
    #[inline]
    fn heard(&mut self, slot: usize, now: Instant, expires: Instant) {
        if let (Some(e), Some(a)) = (self.expiry.get_mut(slot), self.last_activity.get_mut(slot)) {
            (*e, *a) = (expires, now);
        }
        self.expiry_bound = self.expiry_bound.min(expires);
    }

    /// New data for the producer in `slot`: it is due at the end of its inhibit time, if that
    /// is before its deadline. A slot without a producer (never due) stays so.
    pub(super) fn trigger(&mut self, slot: usize) {
        let due = self.schedule.at(slot);
        let Some(p) = self.pending.get_mut(slot).filter(|_| due != Instant::NEVER) else {
            return;
        };
        p.triggered = true;
        if p.inhibit_until < due {
            let at = p.inhibit_until;
            self.reschedule(slot, at);
        }
    }

    /// True if a trigger waits on the producer in `slot`.
    #[inline]
    pub(super) fn triggered(&self, slot: usize) -> bool {
        self.pending.get(slot).is_some_and(|p| p.triggered)
    }

    /// The phase of the adapter's grid of `rpi`: its points are this plus multiples of `rpi`.
    pub(super) fn grid_phase(&self, rpi: u32) -> u32 {
        self.schedule.grid_phase(rpi)
    }

    /// The producer in `slot` produced at `now`: after a trigger, the next production is one
    /// `rpi` later and the next trigger waits out `inhibit`; otherwise the grid moves on to
    /// its first point after `now` (after a cyclic producer's first production, the first
    /// point of the adapter's grid at least one `rpi` on).
    #[inline]
    pub(super) fn produced(&mut self, slot: usize, now: Instant, rpi: u32, inhibit: Duration) {
        let Some(p) = self.pending.get_mut(slot) else {
            return;
        };
        let previous = self.schedule.at(slot);
        let next = if p.triggered {
            *p = Pending {
                triggered: false,
                inhibit_until: now.add(inhibit),
                to_clock_grid: false,
            };
            now.add(Duration::from_micros(u64::from(rpi)))
        } else if p.to_clock_grid {
            p.to_clock_grid = false;
            onto_clock_grid(
                previous.add(Duration::from_micros(u64::from(rpi))),
                rpi,
                now,
                self.schedule.grid_phase(rpi),
            )
        } else {
            advance(previous, rpi, now)
        };
        self.schedule.set(slot, next);
    }

    /// The producer in `slot` is next due `at`, off the production path (opened, closed,
    /// triggered): one shared copy of the schedule's update, where production has its own
    /// inline.
    #[inline(never)]
    fn reschedule(&mut self, slot: usize, at: Instant) {
        self.schedule.set(slot, at);
    }

    /// The slot of the producer due first at `now`, if one is due: the earliest deadline, the
    /// lowest slot of equal ones. The one rule of "a producer is due".
    #[inline]
    pub(super) fn due(&self, now: Instant) -> Option<usize> {
        let (slot, at) = self.schedule.first();
        (now >= at).then_some(slot)
    }

    /// When the watchdog of `slot` fires (`Instant::NEVER` for an empty slot).
    pub(super) fn expires(&self, slot: usize) -> Instant {
        self.expiry.get(slot).copied().unwrap_or(Instant::NEVER)
    }

    /// When the producer of `slot` is next due (`Instant::NEVER` for none).
    pub(super) fn next_production(&self, slot: usize) -> Instant {
        self.schedule.at(slot)
    }

    /// When the originator of `slot` was last heard, or it opened.
    pub(super) fn last_activity(&self, slot: usize) -> Instant {
        self.last_activity.get(slot).copied().unwrap_or(Instant(0))
    }

    /// False if no watchdog can have fired by `now`: the sweep can be skipped.
    #[inline]
    pub(super) fn may_expire(&self, now: Instant) -> bool {
        now >= self.expiry_bound
    }

    /// True if the watchdog of `slot` fired by `now`.
    pub(super) fn expired(&self, slot: usize, now: Instant) -> bool {
        self.expires(slot) <= now
    }

    /// A sweep closed every expired slot: the bound becomes the earliest watchdog left.
    pub(super) fn swept(&mut self) {
        self.expiry_bound = self.expiry.iter().copied().min().unwrap_or(Instant::NEVER);
    }

    /// The earliest watchdog expiry or production deadline among the slots below `end`.
    pub(super) fn next_deadline(&self, end: usize) -> Option<Instant> {
        // No watchdog fires before `expiry_bound`: while that is after the first production,
        // the production is the answer and the watchdogs need no look.
        let (_, production) = self.schedule.first();
        let at = if production < self.expiry_bound {
            production
        } else {
            self.earliest_expiry(end, production)
        };
        (at != Instant::NEVER).then_some(at)
    }

    /// The earliest of `production` and the watchdogs below `end`: out of line, so the many
    /// callers of [`Self::next_deadline`] inline only its common answer.
    #[inline(never)]
    fn earliest_expiry(&self, end: usize, production: Instant) -> Instant {
        let expiry = self.expiry.get(..end).unwrap_or(&self.expiry);
        expiry.iter().fold(production, |a, &b| a.min(b))
    }

    /// Checks the summaries against the per-slot state (tests only): the bound is at most
    /// every expiry, the first producer is the earliest deadline, lowest slot on a tie.
    #[cfg(test)]
    pub(super) fn assert_consistent(&self) {
        let earliest = self.expiry.iter().copied().min().unwrap_or(Instant::NEVER);
        assert!(
            self.expiry_bound <= earliest,
            "bound {:?} after the earliest expiry {earliest:?}",
            self.expiry_bound
        );
        let first = (0..C)
            .map(|s| self.schedule.at(s))
            .min()
            .unwrap_or(Instant::NEVER);
        let (slot, at) = self.schedule.first();
        assert_eq!(at, first, "first production");
        if at != Instant::NEVER {
            assert_eq!(Some(slot), (0..C).position(|s| self.schedule.at(s) == at));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::MAX_CONNECTIONS;

    /// The timing of the default table.
    type Timing = super::Timing<MAX_CONNECTIONS>;

    const RPI: u32 = 1_000;

    #[test]
    fn advance_keeps_the_grid() {
        assert_eq!(advance(Instant(1000), 1000, Instant(1000)), Instant(2000));
        assert_eq!(advance(Instant(1000), 1000, Instant(1999)), Instant(2000));
        assert_eq!(advance(Instant(1000), 1000, Instant(2000)), Instant(3000));
        assert_eq!(advance(Instant(1000), 1000, Instant(4500)), Instant(5000));
    }

    #[test]
    fn an_opened_producer_is_due_at_once_and_then_on_its_grid() {
        let mut t = Timing::new(0);
        t.open(2, Instant(500), Duration(4_000), Produces::OnTrigger);
        assert_eq!(t.due(Instant(499)), None);
        assert_eq!(t.due(Instant(500)), Some(2));
        t.produced(2, Instant(700), RPI, Duration(0));
        assert_eq!(
            t.next_production(2),
            Instant(1_500),
            "on the grid, not 700 + RPI"
        );
        t.produced(2, Instant(3_900), RPI, Duration(0));
        assert_eq!(
            t.next_production(2),
            Instant(4_500),
            "late: the points past are skipped"
        );
        t.assert_consistent();
    }

    #[test]
    fn a_cyclic_producer_moves_onto_the_clock_grid_at_its_second_production() {
        let mut t = Timing::new(0);
        t.open(2, Instant(500), Duration(4_000), Produces::Cyclic);
        assert_eq!(t.due(Instant(500)), Some(2), "at once");
        t.produced(2, Instant(700), RPI, Duration(0));
        assert_eq!(
            t.next_production(2),
            Instant(2_000),
            "the clock's grid, at least one RPI after the first: 1 500 is not on it"
        );
        t.produced(2, Instant(2_000), RPI, Duration(0));
        assert_eq!(t.next_production(2), Instant(3_000), "then the RPI");
        t.produced(2, Instant(5_200), RPI, Duration(0));
        assert_eq!(t.next_production(2), Instant(6_000), "late: still the grid");
        t.assert_consistent();
    }

    #[test]
    fn cyclic_producers_of_one_rpi_come_due_together() {
        let mut t = Timing::new(0);
        let rpi = 10_000;
        // Opened at three different instants; the second starts late, the third on a point.
        for (slot, open) in [(0, 1_234), (1, 7_777), (2, 20_000)] {
            t.open(slot, Instant(open), Duration(40_000), Produces::Cyclic);
            let late = if slot == 1 { 3_000 } else { 0 };
            t.produced(slot, Instant(open + late), rpi, Duration(0));
        }
        assert_eq!(
            [0, 1, 2].map(|s| t.next_production(s)),
            [Instant(20_000), Instant(20_000), Instant(30_000)],
            "never sooner than one RPI after the first production"
        );
        t.produced(0, Instant(20_000), rpi, Duration(0));
        t.produced(1, Instant(20_010), rpi, Duration(0));
        assert_eq!(
            [0, 1, 2].map(|s| t.next_production(s)),
            [Instant(30_000); 3]
        );
        // A producer of twice the RPI meets them at every other point.
        t.open(3, Instant(25_000), Duration(80_000), Produces::Cyclic);
        t.produced(3, Instant(25_000), 2 * rpi, Duration(0));
        assert_eq!(t.next_production(3), Instant(60_000));
        assert_eq!(
            onto_clock_grid(Instant(u64::MAX - 5), rpi, Instant(0), 0),
            Instant(u64::MAX)
        );
        t.assert_consistent();
    }

    #[test]
    fn the_grids_have_the_adapters_phase() {
        let mut t = Timing::new(12_345);
        assert_eq!((t.grid_phase(1_000), t.grid_phase(10_000)), (345, 2_345));
        t.open(0, Instant(0), Duration(40_000), Produces::Cyclic);
        t.produced(0, Instant(0), 1_000, Duration(0));
        assert_eq!(t.next_production(0), Instant(1_345));
        assert_eq!(
            onto_clock_grid(Instant(100), 1_000, Instant(0), 345),
            Instant(345),
            "before the first point"
        );
    }

    #[test]
    fn a_triggered_producer_keeps_its_own_heartbeat() {
        let mut t = Timing::new(0);
        t.open(4, Instant(1_234), Duration(40_000), Produces::OnTrigger);
        t.produced(4, Instant(1_234), 10_000, Duration(0));
        assert_eq!(
            t.next_production(4),
            Instant(11_234),
            "one RPI on, off the clock's grid"
        );
    }

    #[test]
    fn the_watchdog_starts_with_the_grace_and_runs_from_each_feed() {
        let mut t = Timing::new(0);
        t.open(0, Instant(0), Duration(4_000), Produces::Nothing);
        assert_eq!(t.expires(0), Instant(FIRST_PACKET_GRACE_US));
        assert_eq!(t.next_deadline(1), Some(Instant(FIRST_PACKET_GRACE_US)));
        t.feed(0, Instant(100), Duration(4_000));
        assert_eq!(
            (t.expires(0), t.last_activity(0)),
            (Instant(4_100), Instant(100))
        );
        assert_eq!(t.next_deadline(1), Some(Instant(4_100)));
        assert!(!t.expired(0, Instant(4_099)) && t.expired(0, Instant(4_100)));
        t.close(0);
        t.swept();
        assert!(!t.may_expire(Instant(u64::MAX - 1)));
        assert_eq!(t.next_deadline(1), None);
        t.assert_consistent();
    }

    #[test]
    fn a_trigger_waits_out_the_inhibit_time_and_restarts_the_grid() {
        let mut t = Timing::new(0);
        t.open(1, Instant(0), Duration(4_000), Produces::OnTrigger);
        t.produced(1, Instant(0), 10_000, Duration(0));
        t.trigger(1);
        assert!(t.triggered(1));
        assert_eq!(t.next_production(1), Instant(0), "no inhibit yet: at once");
        t.produced(1, Instant(300), 10_000, Duration(2_000));
        assert!(!t.triggered(1));
        assert_eq!(
            t.next_production(1),
            Instant(10_300),
            "a new grid from the production"
        );
        t.trigger(1);
        assert_eq!(
            t.next_production(1),
            Instant(2_300),
            "the inhibit time's end"
        );
        t.trigger(1);
        assert_eq!(
            t.next_production(1),
            Instant(2_300),
            "a second trigger changes nothing"
        );
        t.assert_consistent();
    }

    #[test]
    fn a_slot_without_a_producer_is_never_due_even_when_triggered() {
        let mut t = Timing::new(0);
        t.open(3, Instant(0), Duration(4_000), Produces::Nothing);
        t.trigger(3);
        assert!(!t.triggered(3));
        assert_eq!(t.next_production(3), Instant::NEVER);
        assert_eq!(t.due(Instant(u64::MAX - 1)), None);
    }
}
