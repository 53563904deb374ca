//! Cyclic producers that follow their originator: a cyclic T->O producer whose connection
//! has O->T data at the same RPI keeps its production grid just before that data's arrivals,
//! so the wake-up that receives an O->T datagram also sends the T->O datagram due: one
//! wake-up a cycle where the two streams' independent phases would otherwise take two.
//!
//! Two rules, each a pure function of the instants involved:
//! - the *slack*: once its O->T data has come, the runtime is woken for a following producer
//!   at its nominal instant plus the slack (1/8 of the RPI, at most 2 ms) when no wake-up
//!   comes sooner; any wake-up from its nominal instant on sends it. A datagram never goes
//!   before its nominal instant, and at most the slack after it.
//! - the *correction*, at each O->T arrival: an arrival within the slack after the grid's
//!   instant it belongs to is in step, and nothing moves (the production path pays nothing).
//!   Any other moves that instant toward one an eighth of the slack before the arrival, by
//!   1/16 of the RPI at most: so the grid is found within eight RPIs, drift between the two
//!   clocks is followed as it leaves the slack, and an instant moved to the arrival or
//!   before it is due at once, in the arrival's wake-up. Nominal instants are 15/16 to
//!   17/16 of the RPI apart.
//!
//! Before any O->T data comes the producer is on the adapter's grid without slack; when the
//! data stops, its grid stays where it was, and its datagrams go out the slack after their
//! instants until the watchdog closes the connection.

use crate::time::Instant;

/// The longest slack, microseconds: a following producer's datagram goes out at most this
/// long after its nominal instant. (The emulated board under the bench's trace sees its O->T
/// data spread over about a millisecond: 500 us kept half its cycles at two wake-ups.)
pub(crate) const MAX_SLACK_US: u32 = 2000;

/// The longest RPI followed (microseconds, about 4.5 minutes): the offsets stay far from
/// overflow.
const MAX_FOLLOWED_RPI: u64 = 1 << 28;

/// The slack (microseconds) of a following producer of `rpi`: 1/8 of it, at most
/// [`MAX_SLACK_US`].
pub(crate) const fn slack(rpi: u32) -> u16 {
    let s = rpi / 8;
    (if s < MAX_SLACK_US { s } else { MAX_SLACK_US }) as u16
}

/// True if O->T data arriving at `now` is in step with a following producer of `rpi` with
/// `slack` next due at `next`: within the slack after `next` (its production waiting), or
/// after the instant one RPI before it. The common case, inline and in 32 bits (the offsets
/// modulo 2^32 us: an arrival over 35 minutes from `next` may pass for in step, and moves
/// nothing).
#[inline]
pub(crate) fn in_step(now: Instant, next: Instant, rpi: u32, slack: u16) -> bool {
    // `now - next` modulo 2^32; one RPI more is the offset from the instant before.
    let after = (now.as_micros() as u32).wrapping_sub(next.as_micros() as u32);
    let slack = u32::from(slack);
    after <= slack || after.wrapping_add(rpi) <= slack
}

/// The new nominal instant of a following producer of `rpi` with `slack`, next due at
/// `next`, when its O->T data arrives at `now`; `None` if the arrival is in step (within the
/// slack after the instant it belongs to), the producer is not scheduled, or it is overdue by
/// more than an RPI (a stall: nothing to learn from it).
#[inline(never)]
pub(crate) fn correction(now: Instant, next: Instant, rpi: u32, slack: u16) -> Option<Instant> {
    let r = u64::from(rpi);
    if r == 0 || r > MAX_FOLLOWED_RPI || next == Instant::NEVER {
        return None;
    }
    let (now_us, next_us) = (now.as_micros(), next.as_micros());
    // The arrival's offset from the instant it belongs to: `next` itself if that has come
    // (its production waits) or is less than half an RPI ahead, else the one before it.
    let lag = if next_us <= now_us {
        let late = now_us.wrapping_sub(next_us);
        if late > r {
            return None;
        }
        late as i64
    } else {
        let ahead = next_us.wrapping_sub(now_us);
        if ahead < r / 2 || ahead > r {
            (ahead as i64).wrapping_neg()
        } else {
            r.wrapping_sub(ahead) as i64
        }
    };
    let slack = i64::from(slack);
    if (0..=slack).contains(&lag) {
        return None;
    }
    let most = (r / 16) as i64;
    let step = lag.wrapping_sub(slack / 8).clamp(most.wrapping_neg(), most);
    next_us.checked_add_signed(step).map(Instant)
}

#[cfg(test)]
mod tests {
    use super::*;

    const RPI: u32 = 10_000;
    /// The slack at 10 ms, and where a correction puts the grid's instant before an arrival.
    const SLACK: u16 = 1_250;
    const TARGET: u64 = 156;

    /// The correction for an arrival at `now` with the producer next due at 20 ms.
    fn at(now: u64) -> Option<u64> {
        correction(Instant(now), Instant(20_000), RPI, SLACK).map(Instant::as_micros)
    }

    #[test]
    fn the_slack_is_an_eighth_of_the_rpi_and_2_ms_at_most() {
        assert_eq!(slack(1_000), 125);
        assert_eq!(slack(2_000), 250);
        assert_eq!(slack(RPI), SLACK);
        assert_eq!(slack(100_000), 2_000);
        assert_eq!(slack(u32::MAX), 2_000);
        assert_eq!(slack(0), 0);
    }

    #[test]
    fn an_arrival_within_the_slack_after_its_instant_moves_nothing() {
        assert_eq!(at(20_000), None, "at the instant, its production waiting");
        assert_eq!(at(21_250), None, "the slack after it");
        // After the instant's production went (the next is one RPI on).
        assert_eq!(
            correction(Instant(20_700), Instant(30_000), RPI, SLACK),
            None
        );
    }

    #[test]
    fn an_early_arrival_brings_the_instant_to_it_and_it_is_due_at_once() {
        assert_eq!(at(19_700), Some(19_700 - TARGET));
        assert_eq!(at(19_000), Some(20_000 - 625), "1/16 of the RPI at most");
        assert_eq!(
            at(15_001),
            Some(20_000 - 625),
            "just under half an RPI early"
        );
    }

    #[test]
    fn a_late_one_moves_the_instant_later() {
        // Still waiting for its production past the slack (a late runtime): due at once,
        // the grid later by 1/16 of the RPI at most.
        assert_eq!(at(21_300), Some(20_625));
        assert_eq!(at(23_000), Some(20_625));
        // After the previous instant's production went: the next one moves.
        assert_eq!(
            correction(Instant(22_000), Instant(30_000), RPI, SLACK),
            Some(Instant(30_625))
        );

        assert_eq!(
            correction(Instant(25_000), Instant(30_000), RPI, SLACK),
            Some(Instant(30_625))
        );
    }

    #[test]
    fn in_step_is_exactly_where_no_correction_comes() {
        for rpi in [1_000u32, 10_000, 100_000] {
            let s = slack(rpi);
            let r = u64::from(rpi);
            for now in (0..3 * r).step_by(7) {
                let next = Instant(r + r / 3);
                let step = in_step(Instant(now), next, rpi, s);
                let moved = correction(Instant(now), next, rpi, s);
                if step {
                    assert_eq!(moved, None, "{rpi} {now}");
                } else {
                    // Out of step: a correction, unless overdue by over an RPI.
                    assert_eq!(moved.is_none(), now > next.as_micros() + r, "{rpi} {now}");
                }
            }
        }
    }

    #[test]
    fn nothing_to_follow_after_a_stall_or_without_a_schedule() {
        assert_eq!(at(30_001), None, "overdue by more than an RPI");
        assert_eq!(
            correction(Instant(0), Instant(50_000), RPI, SLACK),
            Some(Instant(49_375)),
            "more than an RPI ahead (just opened): as early"
        );
        assert_eq!(correction(Instant(5), Instant::NEVER, RPI, SLACK), None);
        assert_eq!(correction(Instant(5), Instant(9), 0, 0), None);
        assert_eq!(correction(Instant(5), Instant(9), 1 << 29, 2_000), None);
    }
}
