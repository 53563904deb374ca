//! The simulated drive in virtual time: velocity ramps, indexing moves, status bits, faults.

use enip_stack::cip::{CipError, General};
use enip_stack::device::{CloseReason, ConnectionEvent};
use enip_stack::{Device, Instant};

use crate::position_servo::device::status;
use crate::position_servo::params::{id, Value};
use crate::position_servo::PositionServo;

/// A servo and a virtual clock in milliseconds.
struct Sim {
    servo: PositionServo,
    ms: u64,
}

impl Sim {
    fn new() -> Self {
        let mut s = Sim {
            servo: PositionServo::new(),
            ms: 0,
        };
        s.run(1);
        s
    }
    fn set(&mut self, id: u16, v: f32) {
        self.servo.write(id, Value::Real(v), false).unwrap();
    }
    fn try_set(&mut self, id: u16, v: f32) -> Result<(), CipError> {
        self.servo.write(id, Value::Real(v), false)
    }
    /// Polls once per millisecond for `ms` milliseconds.
    fn run(&mut self, ms: u64) {
        for _ in 0..ms {
            self.ms += 1;
            self.servo.poll(Instant::from_micros(self.ms * 1000));
        }
    }
    fn get(&self, id: u16) -> f32 {
        self.servo.variables().real(id)
    }
    fn status(&self) -> u32 {
        self.servo.variables().raw(id::STATUS)
    }
    /// Runs until `done` holds (at most `limit` ms); returns the milliseconds it took.
    fn until(&mut self, limit: u64, done: impl Fn(&Sim) -> bool) -> u64 {
        let start = self.ms;
        while !done(self) {
            assert!(self.ms - start < limit, "not done within {limit} ms");
            self.run(1);
        }
        self.ms - start
    }
    /// Velocity mode with the internal reference and the limits of example 8.3.
    fn velocity_mode(&mut self, ramp: bool) {
        self.set(id::DRIVE_MODE, 1.0);
        self.set(id::REFERENCE_SOURCE, 1.0);
        self.set(id::ENABLE_ACCEL_DECEL, if ramp { 1.0 } else { 0.0 });
        self.set(id::ACCEL_LIMIT, 1000.0);
        self.set(id::DECEL_LIMIT, 1000.0);
        self.set(id::ENABLE, 1.0);
    }
    /// Position mode with the internal reference, enabled.
    fn position_mode(&mut self) {
        self.set(id::DRIVE_MODE, 2.0);
        self.set(id::REFERENCE_SOURCE, 1.0);
        self.set(id::ENABLE, 1.0);
        self.run(1);
    }
}

fn conflict() -> CipError {
    CipError::new(General::DeviceStateConflict)
}

#[test]
fn velocity_ramps_at_the_accel_and_decel_limits() {
    let mut s = Sim::new();
    s.velocity_mode(true);
    s.set(id::REFERENCE, 100.0);
    s.run(50);
    // 1000 units/s² for 50 ms, less the servo lag of 3 ms.
    let v = s.get(id::ACTUAL_VELOCITY);
    assert!((46.0..=48.0).contains(&v), "v(50 ms) = {v}");
    let t = s.until(100, |s| s.get(id::ACTUAL_VELOCITY) == 100.0);
    assert!((52..=54).contains(&t), "reached 100 after {} ms", 50 + t);
    assert_eq!(s.status() & status::MOTION_COMPLETED, 0);
    s.set(id::REFERENCE, 0.0);
    let t = s.until(200, |s| s.get(id::ACTUAL_VELOCITY) == 0.0);
    assert!((100..=104).contains(&t), "stopped after {t} ms");
    assert_ne!(s.status() & status::MOTION_COMPLETED, 0);
    // 0.1 s up and 0.1 s down at 100 units/s cover 10 units, plus the cruise.
    assert!(s.get(id::ACTUAL_POSITION) > 10.0);
}

#[test]
fn velocity_without_ramp_or_with_external_reference() {
    let mut s = Sim::new();
    s.velocity_mode(false);
    s.set(id::REFERENCE, 20.0);
    let t = s.until(50, |s| s.get(id::ACTUAL_VELOCITY) == 20.0);
    assert!(t <= 4, "no ramp: {t} ms");
    s.set(id::REFERENCE_SOURCE, 0.0);
    s.until(50, |s| s.get(id::ACTUAL_VELOCITY) == 0.0);
    s.run(10);
    assert_eq!(s.get(id::ACTUAL_VELOCITY), 0.0);
}

#[test]
fn example_8_2_moved_moves_by_10_units_then_completes() {
    let mut s = Sim::new();
    s.position_mode();
    assert_ne!(s.status() & status::MOTION_COMPLETED, 0);
    let start = s.get(id::ACTUAL_POSITION);
    s.set(id::MOVED, 10.0);
    assert_eq!(s.status() & status::MOTION_COMPLETED, 0);
    assert_eq!(s.status() & status::STACK_EMPTY, 0);
    s.run(500);
    let mid = s.get(id::ACTUAL_POSITION);
    assert!(mid > start + 3.0 && mid < start + 6.0, "at 0.5 s: {mid}");
    assert_eq!(s.status() & status::IN_POSITION, 0);
    // 0.1 s accel to 10 units/s, 0.9 s cruise, 0.1 s decel, plus the servo lag.
    let t = s.until(1000, |s| s.status() & status::MOTION_COMPLETED != 0);
    assert!(
        (598..=606).contains(&t),
        "completed {} ms after the write",
        500 + t
    );
    assert_eq!(s.get(id::ACTUAL_POSITION), start + 10.0);
    assert_eq!(s.get(id::POSITION_ERROR), 0.0);
    assert_ne!(s.status() & status::IN_POSITION, 0);
}

#[test]
fn movep_is_absolute_and_moves_queue_on_the_motion_stack() {
    let mut s = Sim::new();
    s.position_mode();
    s.set(id::MOVED, 2.0);
    s.set(id::MOVED, 3.0);
    s.set(id::MOVEP, -1.5);
    s.until(5000, |s| s.status() & status::MOTION_COMPLETED != 0);
    assert_eq!(s.get(id::ACTUAL_POSITION), -1.5);
    for _ in 0..crate::position_servo::device::MOTION_STACK {
        s.set(id::MOVED, 1.0);
    }
    assert_ne!(s.status() & status::STACK_FULL, 0);
    assert_eq!(
        s.try_set(id::MOVED, 1.0),
        Err(CipError::new(General::ResourceUnavailable))
    );
    s.set(id::ENABLE, 0.0);
    assert_ne!(s.status() & status::STACK_EMPTY, 0);
}

/// Runs until motion completes and returns the largest change of the velocity step between
/// ticks (the jerk, in units/s per tick²).
fn max_jerk(s: &mut Sim) -> f32 {
    let (mut v, mut dv, mut jerk) = (0.0f32, 0.0f32, 0.0f32);
    for _ in 0..5000 {
        s.run(1);
        let v2 = s.get(id::ACTUAL_VELOCITY);
        jerk = jerk.max((v2 - v - dv).abs());
        dv = v2 - v;
        v = v2;
        if s.status() & status::MOTION_COMPLETED != 0 {
            break;
        }
    }
    jerk
}

#[test]
fn s_curve_moves_reach_the_target_with_limited_jerk() {
    let mut s = Sim::new();
    s.position_mode();
    s.set(id::MOVEDS, 1.0);
    let smooth = max_jerk(&mut s);
    assert_eq!(s.get(id::ACTUAL_POSITION), 1.0);
    s.set(id::MOVEPS, -1.0);
    assert!(max_jerk(&mut s) < 0.01);
    assert_eq!(s.get(id::ACTUAL_POSITION), -1.0);
    s.set(id::MOVEP, 0.0);
    let trapezoid = max_jerk(&mut s);
    assert_eq!(s.get(id::ACTUAL_POSITION), 0.0);
    // The trapezoid changes acceleration in one tick (0.1 units/s per tick at 100 units/s²).
    assert!(smooth < 0.01 && trapezoid > 0.09, "{smooth} vs {trapezoid}");
}

#[test]
fn moves_and_mode_changes_are_refused_in_the_wrong_state() {
    let mut s = Sim::new();
    s.set(id::DRIVE_MODE, 2.0);
    s.set(id::REFERENCE_SOURCE, 1.0);
    assert_eq!(s.try_set(id::MOVED, 1.0), Err(conflict()), "disabled");
    s.set(id::ENABLE, 1.0);
    assert_eq!(s.try_set(id::DRIVE_MODE, 1.0), Err(conflict()), "enabled");
    s.set(id::DRIVE_MODE, 2.0); // unchanged: fine
    s.set(id::REFERENCE_SOURCE, 0.0);
    assert_eq!(
        s.try_set(id::MOVED, 1.0),
        Err(conflict()),
        "external reference"
    );
    s.set(id::ENABLE, 0.0);
    s.set(id::DRIVE_MODE, 1.0);
    s.set(id::ENABLE, 1.0);
    assert_eq!(s.try_set(id::MOVED, 1.0), Err(conflict()), "velocity mode");
}

#[test]
fn position_error_faults_and_enabling_again_clears_it() {
    let mut s = Sim::new();
    s.velocity_mode(false);
    s.set(id::REFERENCE, 5000.0);
    s.run(20);
    assert_ne!(s.status() & status::FAULT, 0);
    assert_eq!(s.status() & status::ENABLED, 0);
    assert_eq!(s.servo.variables().raw(id::ENABLE), 0);
    s.set(id::REFERENCE, 0.0);
    s.set(id::ENABLE, 1.0);
    assert_eq!(
        s.status() & (status::FAULT | status::ENABLED),
        status::ENABLED
    );
}

#[test]
fn phase_current_and_current_limit() {
    let mut s = Sim::new();
    s.velocity_mode(true);
    s.set(id::REFERENCE, 100.0);
    s.run(50);
    // Idle 0.2 A + 2 mA per unit/s + 1 A for 1000 units/s².
    let accelerating = s.get(id::PHASE_CURRENT);
    assert!((1.2..=1.4).contains(&accelerating), "{accelerating} A");
    s.run(200);
    assert_eq!(s.get(id::PHASE_CURRENT), 0.4);
    s.set(id::ENABLE, 0.0);
    s.set(id::DRIVE_MODE, 0.0);
    s.set(id::CURRENT_LIMIT, 2.5);
    s.set(id::ENABLE, 1.0);
    s.set(id::REFERENCE, -3.0);
    s.run(1);
    assert_eq!(s.get(id::PHASE_CURRENT), 2.5);
    assert_ne!(s.status() & status::CURRENT_LIMIT, 0);
    s.set(id::REFERENCE, 1.0);
    s.run(1);
    assert_eq!(s.get(id::PHASE_CURRENT), 1.0);
    assert_eq!(s.status() & status::CURRENT_LIMIT, 0);
}

#[test]
fn losing_exclusive_ownership_clears_exstatus_and_disables() {
    let mut s = Sim::new();
    s.velocity_mode(true);
    s.servo.connection_event(ConnectionEvent::OwnershipGained);
    assert_eq!(s.servo.variables().raw(id::EXSTATUS), status::EX_OWNED);
    s.set(id::REFERENCE, 10.0);
    s.run(100);
    s.servo
        .connection_event(ConnectionEvent::OwnershipLost(CloseReason::Timeout));
    assert_eq!(s.servo.variables().raw(id::EXSTATUS), 0);
    assert_eq!(s.status() & status::ENABLED, 0);
    s.run(10);
    assert_eq!(s.get(id::ACTUAL_VELOCITY), 0.0);
}

#[test]
fn ticks_are_fixed_and_a_long_stall_resyncs() {
    let mut servo = PositionServo::new();
    assert_eq!(servo.poll(Instant(5_000)), Some(Instant(6_000)));
    assert_eq!(servo.poll(Instant(5_500)), Some(Instant(6_000)));
    assert_eq!(servo.poll(Instant(8_200)), Some(Instant(9_000)));
    assert_eq!(servo.poll(Instant(60_000_000)), Some(Instant(60_001_000)));
}
