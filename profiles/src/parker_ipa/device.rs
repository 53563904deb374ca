//! The simulated axes. Axis `a` jogs while its jog command says so: bit 16 (jog forward)
//! or bit 17 (jog reverse) of its quaternary axis flags P(4360 + a), exactly one of them,
//! with a non-zero jog velocity P(12348 + 256a) (units per second, its magnitude; the
//! direction comes from the bit). Its current and actual positions (P12288/P12290 + 256a,
//! longs) then move by it and bit 18 (jog active) of the same flags is set; with neither bit,
//! both, or a zero velocity the axis stands still and bit 18 is clear. Writing a jog profile
//! (the manual's figure 4) starts nothing. The bit numbers are this simulation's choice
//! (the public ACR documents at hand do not give them); acceleration, deceleration and jerk
//! are stored but not simulated (the velocity applies at once).

use enip_stack::{Duration, Instant};

use super::params::{
    Slot, Store, Value, ACTUAL_POSITION, AXES, AXIS_FIRST, AXIS_STRIDE, CURRENT_POSITION, JOG_VEL,
    QUATERNARY_FLAGS_FIRST,
};

/// Quaternary axis flag: jog forward (command).
pub const JOG_FORWARD: i32 = 1 << 16;
/// Quaternary axis flag: jog reverse (command).
pub const JOG_REVERSE: i32 = 1 << 17;
/// Quaternary axis flag: jog active (status, set while the axis moves).
pub const JOG_ACTIVE: i32 = 1 << 18;

/// Step while an axis moves.
pub const MOVING_PERIOD: Duration = Duration::from_millis(1);
/// Step while every axis stands still.
pub const IDLE_PERIOD: Duration = Duration::from_millis(10);
/// Position units are counted in millionths between steps.
const MICRO: i64 = 1_000_000;

/// The motion state of the axes.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Axes {
    last: Option<Instant>,
    /// Fractions of a position unit not yet applied, in millionths.
    residue: [i64; AXES],
}

fn slot(axis: usize, index: u32) -> Option<Slot> {
    let offset = (axis as u32)
        .saturating_mul(AXIS_STRIDE)
        .saturating_add(index);
    Slot::of(AXIS_FIRST.saturating_add(offset))
}

fn flags(axis: usize) -> Option<Slot> {
    Slot::of(QUATERNARY_FLAGS_FIRST.saturating_add(axis as u32))
}

/// The signed velocity axis `axis` is commanded to jog at (0 when it stands still).
fn commanded(store: &Store, axis: usize) -> f64 {
    let bits = flags(axis)
        .and_then(|s| store.load(s))
        .map_or(0, Value::as_long);
    let speed = slot(axis, JOG_VEL)
        .and_then(|s| store.load(s))
        .map_or(0.0, |v| f64::from(v.as_float()).abs());
    if !speed.is_finite() {
        return 0.0;
    }
    match (bits & JOG_FORWARD != 0, bits & JOG_REVERSE != 0) {
        (true, false) => speed,
        (false, true) => -speed,
        _ => 0.0,
    }
}

/// Sets or clears the jog-active flag of `axis`; true if it changed.
fn show_active(store: &mut Store, axis: usize, active: bool) -> bool {
    let Some(s) = flags(axis) else {
        return false;
    };
    let old = store.load(s).map_or(0, Value::as_long);
    let new = if active {
        old | JOG_ACTIVE
    } else {
        old & !JOG_ACTIVE
    };
    store.store(s, Value::Long(new));
    new != old
}

impl Axes {
    /// Advances every axis to `now`; true if a position or a jog-active flag changed.
    /// Returns the next step too.
    pub fn poll(&mut self, now: Instant, store: &mut Store) -> (bool, Instant) {
        let elapsed = self
            .last
            .map_or(0, |last| now.as_micros().saturating_sub(last.as_micros()));
        self.last = Some(now);
        let mut changed = false;
        let mut moving = false;
        for (axis, residue) in self.residue.iter_mut().enumerate() {
            let velocity = commanded(store, axis);
            changed |= show_active(store, axis, velocity != 0.0);
            if velocity == 0.0 {
                *residue = 0;
                continue;
            }
            moving = true;
            *residue = residue.saturating_add((velocity * elapsed as f64) as i64);
            let whole = *residue / MICRO;
            *residue %= MICRO;
            if whole == 0 {
                continue;
            }
            for index in [CURRENT_POSITION, ACTUAL_POSITION] {
                if let Some(s) = slot(axis, index) {
                    let old = store.load(s).map_or(0, Value::as_long);
                    store.store(s, Value::Long(old.wrapping_add(whole as i32)));
                }
            }
            changed = true;
        }
        let period = if moving { MOVING_PERIOD } else { IDLE_PERIOD };
        (changed, now.add(period))
    }
}
