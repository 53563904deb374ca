//! Cyclic producers that follow their originator: a cyclic T->O producer whose connection
//! has O->T data at the same RPI keeps its production grid just before that data's arrivals,
//! so the wake-up that receives an O->T datagram also sends the T->O datagram due: one
//! wake-up a cycle where the two streams' independent phases would otherwise take two.
//!
//! Two rules, each a pure function of the instants involved:
//! - the *slack*: when no wake-up comes sooner, the runtime is woken for a following producer
//!   at its nominal instant plus the slack (1/8 of the RPI, at most 2 ms); any wake-up from
//!   its nominal instant on sends it. A datagram never goes before its nominal instant, and
//!   at most the slack after it.
//! - the *step*: at each production the grid moves toward placing the arrivals an eighth of
//!   the slack after its instants: by half the error when the last arrival came before the
//!   instant nearest it (that arrival took a wake-up of its own), by a sixteenth when it came
//!   after (the slack covers it), at most 1/16 of the RPI. So the grid settles at the
//!   earliest of the arrivals, and jitter and drift between the two clocks are followed.
//!   Nominal instants are 15/16 to 17/16 of the RPI apart.
//!
//! Before any O->T data comes the producer stays on the adapter's grid without slack; when
//! the data stops, its grid stays where it was, and its datagrams go out the slack after
//! their instants until the watchdog closes the connection.

use crate::time::Instant;

/// The longest slack, microseconds: a following producer's datagram goes out at most this
/// long after its nominal instant. (The emulated board under the bench's trace sees its O->T
/// data spread over about a millisecond: 500 us kept half its cycles at two wake-ups.)
pub(crate) const MAX_SLACK_US: u32 = 2000;

/// The longest RPI followed (microseconds): its arithmetic stays within 32 bits.
const MAX_FOLLOWED_RPI: i32 = 1 << 28;

/// The slack (microseconds) of a following producer of `rpi`: 1/8 of it, at most
/// [`MAX_SLACK_US`].
pub(crate) const fn slack(rpi: u32) -> u16 {
    let s = rpi / 8;
    (if s < MAX_SLACK_US { s } else { MAX_SLACK_US }) as u16
}

/// How far (signed microseconds) the grid of a following producer of `rpi` with `slack`
/// moves when it produces the instant `nominal` at `now`, its O->T data last `heard`: 0 when
/// nothing was heard within two RPIs of `now`, or it lies more than one and a half RPIs from
/// `nominal` (a production late after a stall: nothing to learn from it). No division by
/// the RPI: it runs at every production.
pub(crate) fn step(heard: Instant, nominal: Instant, now: Instant, rpi: u32, slack: u16) -> i64 {
    // 32-bit arithmetic: an RPI up to 2^28 us (4.5 minutes; none longer is followed) keeps
    // every sum below within +-2^30, so the wrapping operations never wrap.
    let Ok(r) = i32::try_from(rpi) else {
        return 0;
    };
    let heard_within = u64::from(rpi).wrapping_mul(2);
    if !(1..=MAX_FOLLOWED_RPI).contains(&r) || now.since(heard).as_micros() > heard_within {
        return 0;
    }
    let Ok(d) = i32::try_from(heard.as_micros().wrapping_sub(nominal.as_micros()) as i64) else {
        return 0;
    };
    let half = r / 2;
    // The arrival's offset from the grid point nearest it, within half an RPI either way.
    let lag = if d > half.wrapping_add(r) || d <= half.wrapping_sub(r.wrapping_mul(2)) {
        return 0;
    } else if d > half {
        d.wrapping_sub(r)
    } else if d <= half.wrapping_sub(r) {
        d.wrapping_add(r)
    } else {
        d
    };
    // Toward the arrivals' earliest: half of an early error (a wake-up lost), a sixteenth of
    // a late one (its slack covers it).
    let error = lag.wrapping_sub(i32::from(slack / 8));
    let step = if error < 0 { error / 2 } else { error / 16 };
    let most = r / 16;
    i64::from(step.clamp(most.wrapping_neg(), most))
}

#[cfg(test)]
mod tests {
    use super::*;

    const RPI: u32 = 10_000;
    /// The slack at 10 ms, and the arrivals' target offset after the grid's instants.
    const SLACK: u16 = 1_250;
    const TARGET: u64 = 156;

    /// The step for an arrival `offset` us after (or before) the nominal instant 20 ms,
    /// produced at the arrival or at the instant, whichever is later.
    fn at(offset: i64) -> i64 {
        let heard = Instant(20_000u64.checked_add_signed(offset).unwrap());
        let nominal = Instant(20_000);
        step(heard, nominal, heard.max(nominal), RPI, SLACK)
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
    fn an_arrival_at_the_target_moves_nothing() {
        assert_eq!(at(TARGET as i64), 0);
        // The same arrival seen one cycle later (not heard again yet): the same offset.
        let heard = Instant(20_000 + TARGET);
        assert_eq!(step(heard, Instant(30_000), Instant(31_250), RPI, SLACK), 0);
    }

    #[test]
    fn an_early_arrival_moves_the_grid_by_half_a_late_one_by_a_sixteenth() {
        assert_eq!(at(56), -50, "100 us early of the target");
        assert_eq!(at(-300), -228, "before the instant itself");
        assert_eq!(at(1_156), 62, "1 ms late of the target");
        assert_eq!(at(3_156), 187, "3 ms late");
    }

    #[test]
    fn at_most_a_sixteenth_of_the_rpi() {
        assert_eq!(at(-2_000), -625);
        assert_eq!(at(-4_999), -625);
        assert_eq!(at(5_000), 302, "half an RPI late: a sixteenth of the error");
        assert_eq!(
            step(Instant(0), Instant(4_000), Instant(4_000), 1_000, 125),
            0
        );
        assert_eq!(
            step(Instant(4_700), Instant(4_000), Instant(4_700), 1_000, 125),
            -62,
            "300 us before the next instant: early, a sixteenth of 1 ms"
        );
    }

    #[test]
    fn nothing_heard_lately_or_near_nothing_followed() {
        assert_eq!(
            step(Instant(0), Instant(30_000), Instant(31_250), RPI, SLACK),
            0
        );
        assert_eq!(
            step(
                Instant(10_000),
                Instant(30_000),
                Instant(30_001),
                RPI,
                SLACK
            ),
            0
        );
        // A production 40 ms late after a stall, the data heard since.
        assert_eq!(
            step(
                Instant(59_000),
                Instant(20_000),
                Instant(60_000),
                RPI,
                SLACK
            ),
            0
        );
        assert_eq!(
            step(Instant(0), Instant(u64::MAX), Instant(u64::MAX), 0, 0),
            0
        );
        assert_eq!(step(Instant(1), Instant(1), Instant(1), 1 << 29, 2_000), 0);
    }
}
