//! The trajectory generator of the simulated drive: what it is doing ([`Motion`]), and the
//! speed of the next control tick of a ramp or a trapezoidal move.

use super::config::TICKS_PER_S;

/// Slowest speed of a move's last counts (counts/s), so every move reaches its target.
pub const CREEP: i64 = TICKS_PER_S;

/// What the drive is doing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Motion {
    Idle,
    /// A trapezoidal move to `target` counts.
    Move {
        target: i64,
        v: i64,
        acc: i64,
        dec: i64,
    },
    /// A ramp to the signed velocity `v`.
    Jog {
        v: i64,
        acc: i64,
        dec: i64,
    },
    /// A ramp to standstill; `emergency` for a hard stop; `watch` the target of the move
    /// it interrupted.
    Stop {
        dec: i64,
        emergency: bool,
        watch: Option<i64>,
    },
    /// Homing (mode 0: the current position becomes HOME.P).
    Homing {
        ticks_left: u32,
    },
    /// Torque mode following the torque command.
    Torque,
}

/// Integer square root (floor).
fn isqrt(n: u128) -> u128 {
    if n < 2 {
        return n;
    }
    let mut x = n;
    let mut y = x.div_ceil(2);
    while y < x {
        x = y;
        y = x.saturating_add(n.checked_div(x).unwrap_or(0)) / 2;
    }
    x
}

/// The velocity after one tick of a ramp from `cur` towards `v` with `acc` (speeding up)
/// or `dec` (slowing down).
pub fn ramp(cur: i64, v: i64, acc: i64, dec: i64) -> i64 {
    let reversing = (v > 0 && cur < 0) || (v < 0 && cur > 0);
    let speeding_up = !reversing && v.unsigned_abs() > cur.unsigned_abs();
    let step = (if speeding_up { acc } else { dec } / TICKS_PER_S).max(1);
    if v > cur {
        cur.saturating_add(step).min(v)
    } else {
        cur.saturating_sub(step).max(v)
    }
}

/// The speed (along the move) of the next tick of a trapezoidal move with `remaining`
/// counts to go (not 0) at `velocity`: the speed the remaining distance allows at `dec`,
/// reached with `acc`, at most `v`.
pub fn move_speed(remaining: i64, velocity: i64, v: i64, acc: i64, dec: i64) -> i64 {
    let dir = remaining.signum();
    let along = velocity.saturating_mul(dir);
    let braking = isqrt(
        (dec.unsigned_abs() as u128)
            .saturating_mul(2)
            .saturating_mul(remaining.unsigned_abs() as u128),
    );
    let allowed = i64::try_from(braking).unwrap_or(i64::MAX).min(v).max(CREEP);
    if along < 0 {
        along.saturating_add((dec / TICKS_PER_S).max(1))
    } else if allowed >= along {
        allowed.min(along.saturating_add((acc / TICKS_PER_S).max(1)))
    } else {
        allowed
    }
}
