//! Position arithmetic on the resolver's counts: how far a speed travels in a time, windows
//! that wrap at the scale factor, crossings during a tick, speed compensation.

use super::super::params::OUTPUTS;

/// Microseconds per minute: RPM to revolutions per microsecond.
const US_PER_MIN: u128 = 60_000_000;

/// The counts of angle (2^32 per revolution) `rpm` travels in `dt_us`, with the remainder
/// carried from the last call.
pub fn advance(rpm: u16, dt_us: u64, rem: u128) -> (u64, u128) {
    let total = u128::from(rpm) * u128::from(dt_us) * (1u128 << 32) + rem;
    ((total / US_PER_MIN) as u64, total % US_PER_MIN)
}

/// `p` moved earlier by `counts` (advance), modulo `sf`.
pub fn shift(p: u16, counts: i32, sf: u16) -> u16 {
    (i32::from(p) - counts).rem_euclid(i32::from(sf.max(1))) as u16
}

/// True inside the window on (inclusive) .. off (exclusive), wrapping when on > off; an
/// empty window when on = off (\[R\] 14).
pub fn window(pos: u16, on: u16, off: u16) -> bool {
    match on.cmp(&off) {
        core::cmp::Ordering::Less => (on..off).contains(&pos),
        core::cmp::Ordering::Greater => pos >= on || pos < off,
        core::cmp::Ordering::Equal => false,
    }
}

/// True if position `x` was reached during the last `travel` counts that ended at `pos`.
pub fn crossed(pos: u16, travel: u32, x: u16, sf: u16) -> bool {
    if travel == 0 {
        return false;
    }
    let back = (u32::from(pos) + u32::from(sf) - u32::from(x) % u32::from(sf)) % u32::from(sf);
    back < travel
}

/// Linear speed compensation: `start` counts at `rpm_start` and below, `end` at `rpm_end`
/// and above, linear between (\[R\] 14: clamped).
pub fn interpolate(rpm: u16, rpm_start: u16, rpm_end: u16, start: u16, end: u16) -> i32 {
    let (s, e) = (i32::from(start), i32::from(end));
    if rpm <= rpm_start || rpm_end <= rpm_start {
        s
    } else if rpm >= rpm_end {
        e
    } else {
        let span = i32::from(rpm_end - rpm_start);
        s + (e - s) * i32::from(rpm - rpm_start) / span
    }
}

/// The indices of the set bits of `mask`.
pub fn bits(mask: u32) -> impl Iterator<Item = usize> {
    (0..OUTPUTS).filter(move |&o| mask & (1 << o) != 0)
}
