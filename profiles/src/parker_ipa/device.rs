//! The simulated axes: while an axis's jog velocity (P12348 + 256a, units per second) is
//! not zero, its current and actual positions (P12288/P12290 + 256a, longs) move by it, so
//! the Class 1 input data visibly changes. Nothing else moves (the manual's examples need
//! no motion; the AOIs' AcroBASIC programs are not in the manual).

use enip_stack::{Duration, Instant};

use super::params::{
    Slot, Store, Value, ACTUAL_POSITION, AXES, AXIS_FIRST, AXIS_STRIDE, CURRENT_POSITION, JOG_VEL,
};

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

impl Axes {
    /// Advances every axis to `now`; true if a position changed. Returns the next step too.
    pub fn poll(&mut self, now: Instant, store: &mut Store) -> (bool, Instant) {
        let elapsed = self
            .last
            .map_or(0, |last| now.as_micros().saturating_sub(last.as_micros()));
        self.last = Some(now);
        let mut changed = false;
        let mut moving = false;
        for (axis, residue) in self.residue.iter_mut().enumerate() {
            let velocity = slot(axis, JOG_VEL)
                .and_then(|s| store.load(s))
                .map_or(0.0, Value::as_float);
            if velocity == 0.0 || !velocity.is_finite() {
                *residue = 0;
                continue;
            }
            moving = true;
            *residue = residue.saturating_add((f64::from(velocity) * elapsed as f64) as i64);
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
