//! The simulated drive behind the profile: enable/disable, torque, velocity and position
//! modes, advanced on a fixed 1 ms control tick in integer arithmetic (deterministic in
//! virtual time).
//!
//! - Velocity mode (VAR_DRIVEMODE 1): the velocity follows REFERENCE (139, units/s) when the
//!   reference source is internal (37 = 1; external reads the simulated analog input, 0), at
//!   the accel/decel limits (76/77, units/s²) when VAR_ENABLEACCELDECEL (75) is 1, at once
//!   otherwise.
//! - Position mode (2): MOVED/MOVEP (93/92) queue a relative/absolute move on the motion
//!   stack; MOVEDS/MOVEPS (177/178) the same with S-curve smoothing (a moving average of the
//!   trapezoid over [`S_CURVE_TICKS`] ticks). Moves run a trapezoid at [`MOVE_VELOCITY`]
//!   with the accel/decel limits: the manual gives no variable ID for the indexing profile's
//!   max velocity, so it is a constant here.
//! - Torque mode (0): the phase current follows REFERENCE (A); the shaft is held (no motion).
//!
//! The actual position follows the commanded one [`LAG_TICKS`] ticks late (the servo loop's
//! lag); position error = commanded - actual. A position error beyond
//! [`POSITION_ERROR_LIMIT`] faults and disables the drive; enabling again clears the fault.
//! Phase current = idle + per-velocity + per-acceleration terms, clipped at VAR_CURRENTLIMIT
//! (status bit 13 while clipped). Disabling stops the shaft at once (no coasting model).

use enip_stack::cip::{CipResult, General};
use enip_stack::{Duration, Instant};

use super::params::{self, id, Value, Variables};
use super::storage::EpmCopy;

/// Control tick.
pub const TICK: Duration = Duration::from_micros(1_000);
/// Velocity of indexing moves, units/s.
pub const MOVE_VELOCITY: f32 = 10.0;
/// Ticks the actual position lags the commanded one.
pub const LAG_TICKS: usize = 3;
/// Ticks of the S-curve moving average.
pub const S_CURVE_TICKS: usize = 32;
/// Depth of the motion stack (queued moves).
pub const MOTION_STACK: usize = 8;
/// Largest velocity the drive accepts, units/s.
pub const MAX_VELOCITY: f32 = 100_000.0;
/// Position error that faults the drive, in nano-units (10 units).
pub const POSITION_ERROR_LIMIT: i64 = 10 * NANO;
/// In-position window, in nano-units (0.001 units).
pub const IN_POSITION_WINDOW: i64 = NANO / 1000;

/// Nano-units per unit: positions are kept in nano-units, velocities in micro-units/s
/// (= nano-units per tick), accelerations in milli-units/s² (= micro-units/s per tick).
const NANO: i64 = 1_000_000_000;
/// Phase current while enabled and at rest, mA.
const IDLE_MA: i64 = 200;
/// Extra phase current per unit/s of velocity, mA.
const MA_PER_VELOCITY: i64 = 2;
/// Most ticks one [`Drive::poll`] catches up; after a longer stall the clock resyncs.
const MAX_CATCH_UP: u32 = 1_000;
/// INPUTS: A3 (the hardware enable/inhibit input) energized, nothing else.
const INPUT_A3: u32 = 1 << 2;

/// STATUS (54) bits, table 18.
pub mod status {
    /// Drive enabled.
    pub const ENABLED: u32 = 1 << 0;
    /// Drive fault.
    pub const FAULT: u32 = 1 << 3;
    /// Motion completed and position within the window.
    pub const IN_POSITION: u32 = 1 << 5;
    /// Motion stack full.
    pub const STACK_FULL: u32 = 1 << 7;
    /// Motion stack empty.
    pub const STACK_EMPTY: u32 = 1 << 8;
    /// Current limit reached.
    pub const CURRENT_LIMIT: u32 = 1 << 13;
    /// Motion completed (velocity 0 and stack empty).
    pub const MOTION_COMPLETED: u32 = 1 << 25;
    /// EXSTATUS (83): an EtherNet/IP exclusive owner holds the drive (8.4).
    pub const EX_OWNED: u32 = 1 << 24;
}

/// VAR_DRIVEMODE.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// 0: torque (current) mode.
    Torque,
    /// 1: velocity mode.
    Velocity,
    /// 2: position mode.
    Position,
}

/// How a move's amount is meant.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MoveKind {
    /// By a distance (MOVED, MOVEDS).
    Relative,
    /// To a position (MOVEP, MOVEPS).
    Absolute,
}

/// A queued move.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Move {
    kind: MoveKind,
    amount: i64,
    s_curve: bool,
}

/// The drive settings a tick reads from the variables.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    mode: Mode,
    internal_reference: bool,
    ramp: bool,
    accel: i64,
    decel: i64,
    reference: f32,
    current_limit_ma: i64,
}

/// `f` scaled by `scale` as an integer (saturating, NaN as 0).
fn scaled(f: f32, scale: f64) -> i64 {
    (f64::from(f) * scale) as i64
}

/// Nano-units as units.
fn units(nano: i64) -> f32 {
    (nano as f64 / NANO as f64) as f32
}

impl Settings {
    /// The settings in `vars`.
    pub fn from_vars(vars: &Variables) -> Self {
        Settings {
            mode: match vars.raw(id::DRIVE_MODE) {
                1 => Mode::Velocity,
                2 => Mode::Position,
                _ => Mode::Torque,
            },
            internal_reference: vars.raw(id::REFERENCE_SOURCE) == 1,
            ramp: vars.raw(id::ENABLE_ACCEL_DECEL) != 0,
            accel: scaled(vars.real(id::ACCEL_LIMIT), 1e3).max(1),
            decel: scaled(vars.real(id::DECEL_LIMIT), 1e3).max(1),
            reference: vars.real(id::REFERENCE).clamp(-MAX_VELOCITY, MAX_VELOCITY),
            current_limit_ma: scaled(vars.real(id::CURRENT_LIMIT), 1e3),
        }
    }
}

/// The simulated drive's state.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Drive {
    enabled: bool,
    fault: bool,
    owned: bool,
    /// Trajectory position and velocity.
    profile: i64,
    velocity: i64,
    /// Commanded position (the trajectory, S-curve smoothed when active).
    command: i64,
    actual: i64,
    actual_velocity: i64,
    current_ma: i64,
    current_limited: bool,
    /// The move under way: its target, and whether it is smoothed.
    target: Option<i64>,
    s_curve: bool,
    stack: heapless::Deque<Move, MOTION_STACK>,
    history: [i64; S_CURVE_TICKS],
    head: usize,
    /// Commanded positions of the last [`LAG_TICKS`] ticks.
    lag: [i64; LAG_TICKS],
    lag_head: usize,
    next_tick: Option<Instant>,
}

impl Drive {
    /// A drive at power-up: disabled, at position 0.
    pub const fn new() -> Self {
        Drive {
            enabled: false,
            fault: false,
            owned: false,
            profile: 0,
            velocity: 0,
            command: 0,
            actual: 0,
            actual_velocity: 0,
            current_ma: 0,
            current_limited: false,
            target: None,
            s_curve: false,
            stack: heapless::Deque::new(),
            history: [0; S_CURVE_TICKS],
            head: 0,
            lag: [0; LAG_TICKS],
            lag_head: 0,
            next_tick: None,
        }
    }

    /// True while enabled.
    pub fn enabled(&self) -> bool {
        self.enabled
    }

    /// Enables (clearing a fault) or disables the drive.
    pub fn set_enable(&mut self, on: bool) {
        if on {
            if !self.enabled {
                self.fault = false;
                self.enabled = true;
            }
        } else {
            self.disable();
        }
    }

    /// Disables the drive: motion stops and the motion stack is emptied.
    pub fn disable(&mut self) {
        self.enabled = false;
        self.velocity = 0;
        self.target = None;
        self.stack.clear();
    }

    /// Records whether an exclusive owner holds the drive (EXSTATUS bit 24).
    pub fn set_owned(&mut self, owned: bool) {
        self.owned = owned;
    }

    /// Queues a move by (relative) or to (absolute) `amount` units. Refused with 0x10 unless
    /// enabled in position mode with the internal reference, with 0x02 if the stack is full.
    pub fn start_move(
        &mut self,
        kind: MoveKind,
        amount: f32,
        s_curve: bool,
        s: &Settings,
    ) -> CipResult {
        if !self.enabled || s.mode != Mode::Position || !s.internal_reference {
            return Err(General::DeviceStateConflict.into());
        }
        let amount = scaled(amount, NANO as f64);
        self.stack
            .push_back(Move {
                kind,
                amount,
                s_curve,
            })
            .map_err(|_| General::ResourceUnavailable.into())
    }

    /// Runs the control ticks due by `now` and publishes the result into `vars`; returns
    /// when the next tick is due.
    pub fn poll(&mut self, now: Instant, vars: &mut Variables) -> Instant {
        let s = Settings::from_vars(vars);
        let mut next = self.next_tick.unwrap_or(now);
        let mut ticks = 0;
        while next <= now && ticks < MAX_CATCH_UP {
            self.tick(&s);
            next = next.add(TICK);
            ticks = ticks.saturating_add(1);
        }
        if next <= now {
            next = now.add(TICK);
        }
        self.next_tick = Some(next);
        self.publish(vars);
        next
    }

    /// One control tick.
    pub fn tick(&mut self, s: &Settings) {
        let before = self.velocity;
        if !self.enabled {
            self.profile = self.actual;
            self.command = self.actual;
            self.history = [self.actual; S_CURVE_TICKS];
            self.lag = [self.actual; LAG_TICKS];
        } else {
            match s.mode {
                Mode::Torque => self.velocity = 0,
                Mode::Velocity => self.velocity_step(s),
                Mode::Position => self.position_step(s),
            }
            self.smooth();
            if self
                .target
                .is_some_and(|t| t == self.profile && t == self.command)
            {
                self.target = None;
            }
        }
        let last = self.actual;
        if let Some(slot) = self.lag.get_mut(self.lag_head) {
            self.actual = core::mem::replace(slot, self.command);
        }
        self.lag_head = self.lag_head.wrapping_add(1) % LAG_TICKS;
        self.actual_velocity = self.actual.saturating_sub(last);
        if self.enabled && self.command.saturating_sub(self.actual).abs() > POSITION_ERROR_LIMIT {
            self.fault = true;
            self.disable();
        }
        self.update_current(s, self.velocity.saturating_sub(before).abs());
    }

    fn velocity_step(&mut self, s: &Settings) {
        let target = if s.internal_reference {
            scaled(s.reference, 1e6)
        } else {
            0
        };
        let v = self.velocity;
        self.velocity = if !s.ramp {
            target
        } else {
            let speeding_up = (target > v && v >= 0) || (target < v && v <= 0);
            let step = if speeding_up { s.accel } else { s.decel };
            if target > v {
                v.saturating_add(step).min(target)
            } else {
                v.saturating_sub(step).max(target)
            }
        };
        self.profile = self.profile.saturating_add(self.velocity);
    }

    fn position_step(&mut self, s: &Settings) {
        let next = if self.target.is_none() {
            self.stack.pop_front()
        } else {
            None
        };
        if let Some(m) = next {
            self.target = Some(match m.kind {
                MoveKind::Relative => self.profile.saturating_add(m.amount),
                MoveKind::Absolute => m.amount,
            });
            self.s_curve = m.s_curve;
            self.history = [self.profile; S_CURVE_TICKS];
        }
        let Some(target) = self.target else {
            self.velocity = 0;
            return;
        };
        let remaining = target.saturating_sub(self.profile);
        let distance = remaining.unsigned_abs();
        // Fastest speed that still stops at the target: v² = 2·decel·distance.
        let stop = u128::from(s.decel.unsigned_abs())
            .saturating_mul(2 * u128::from(distance))
            .isqrt();
        let speed = u128::from(self.velocity.unsigned_abs())
            .saturating_add(u128::from(s.accel.unsigned_abs()))
            .min(scaled(MOVE_VELOCITY, 1e6).unsigned_abs().into())
            .min(stop)
            .max(1);
        if speed >= u128::from(distance) {
            self.profile = target;
            self.velocity = 0;
        } else {
            let v = (speed as i64).saturating_mul(remaining.signum());
            self.profile = self.profile.saturating_add(v);
            self.velocity = v;
        }
    }

    /// Commanded position: the trajectory, or its moving average during an S-curve move.
    fn smooth(&mut self) {
        if let Some(slot) = self.history.get_mut(self.head) {
            *slot = self.profile;
        }
        self.head = self.head.wrapping_add(1) % S_CURVE_TICKS;
        self.command = if self.s_curve && self.target.is_some() {
            let sum: i128 = self.history.iter().map(|&p| i128::from(p)).sum();
            sum.checked_div(S_CURVE_TICKS as i128).unwrap_or(0) as i64
        } else {
            self.profile
        };
    }

    fn update_current(&mut self, s: &Settings, accel: i64) {
        let demand = match (self.enabled, s.mode) {
            (false, _) => 0,
            (true, Mode::Torque) => scaled(s.reference.abs(), 1e3),
            (true, _) => {
                let moving = (self.actual_velocity.unsigned_abs() / 1_000_000) as i64;
                IDLE_MA
                    .saturating_add(moving.saturating_mul(MA_PER_VELOCITY))
                    .saturating_add(accel / 1_000)
            }
        };
        self.current_limited = demand > s.current_limit_ma;
        self.current_ma = demand.min(s.current_limit_ma);
    }

    /// STATUS (54), table 18.
    pub fn status(&self) -> u32 {
        let idle = self.target.is_none() && self.stack.is_empty();
        let completed = idle && self.velocity == 0 && self.actual_velocity == 0;
        let in_position =
            completed && self.command.saturating_sub(self.actual).abs() <= IN_POSITION_WINDOW;
        let bits = [
            (self.enabled, status::ENABLED),
            (self.fault, status::FAULT),
            (in_position, status::IN_POSITION),
            (self.stack.is_full(), status::STACK_FULL),
            (self.stack.is_empty(), status::STACK_EMPTY),
            (self.current_limited, status::CURRENT_LIMIT),
            (completed, status::MOTION_COMPLETED),
        ];
        bits.iter()
            .filter(|(on, _)| *on)
            .fold(0, |acc, (_, bit)| acc | bit)
    }

    /// EXSTATUS (83).
    pub fn exstatus(&self) -> u32 {
        if self.owned {
            status::EX_OWNED
        } else {
            0
        }
    }

    /// Writes the drive's state into its read-only variables and VAR_ENABLE.
    pub fn publish(&self, vars: &mut Variables) {
        let status = self.status();
        vars.set(id::ENABLE, u32::from(self.enabled));
        vars.set(id::STATUS, status);
        vars.set(id::STATUS_ALIAS, status);
        vars.set(id::EXSTATUS, self.exstatus());
        vars.set(id::INPUTS, INPUT_A3);
        vars.set_real(id::ACTUAL_POSITION, units(self.actual));
        vars.set_real(
            id::POSITION_ERROR,
            units(self.command.saturating_sub(self.actual)),
        );
        vars.set_real(
            id::ACTUAL_VELOCITY,
            (self.actual_velocity as f64 / 1e6) as f32,
        );
        vars.set_real(id::PHASE_CURRENT, (self.current_ma as f64 / 1e3) as f32);
    }
}

impl Default for Drive {
    fn default() -> Self {
        Self::new()
    }
}

/// The drive and the RAM copy of its variables: what a write of a variable acts on, from
/// System940, an output assembly or a DataLink.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Servo {
    /// The RAM copy of the variables.
    pub vars: Variables,
    /// The simulated drive.
    pub drive: Drive,
}

impl Servo {
    /// The drive at power-up, its variables from the EPM copy (`epm` of a variable's ID)
    /// where it holds one.
    pub fn power_up(epm: impl Fn(u16) -> Option<u32>) -> Self {
        let mut servo = Servo {
            vars: Variables::power_up(epm),
            drive: Drive::new(),
        };
        servo.drive.publish(&mut servo.vars);
        servo
    }

    /// Writes `value` to variable `id`: the RAM copy, and given `epm` the EPM copy as well.
    /// Writes with an action (enable, moves) act at once; the drive's read-only variables
    /// are refreshed.
    pub fn write(&mut self, id: u16, value: Value, epm: Option<&mut EpmCopy>) -> CipResult {
        let (_, var) = params::find(id).ok_or(General::ObjectDoesNotExist)?;
        var.writable(epm.is_some())?;
        let raw = var.encode(value)?;
        self.act(id, raw)?;
        if let Some(epm) = epm {
            epm.store(id, raw)?;
        }
        self.vars.set(id, raw);
        self.drive.publish(&mut self.vars);
        Ok(())
    }

    /// The action a write of `raw` to `id` starts, if any; an error refuses the write.
    fn act(&mut self, id: u16, raw: u32) -> CipResult {
        let settings = Settings::from_vars(&self.vars);
        let amount = f32::from_bits(raw);
        match id {
            id::ENABLE => self.drive.set_enable(raw != 0),
            id::DRIVE_MODE if self.drive.enabled() && raw != self.vars.raw(id) => {
                return Err(General::DeviceStateConflict.into())
            }
            id::MOVED => self
                .drive
                .start_move(MoveKind::Relative, amount, false, &settings)?,
            id::MOVEP => self
                .drive
                .start_move(MoveKind::Absolute, amount, false, &settings)?,
            id::MOVEDS => self
                .drive
                .start_move(MoveKind::Relative, amount, true, &settings)?,
            id::MOVEPS => self
                .drive
                .start_move(MoveKind::Absolute, amount, true, &settings)?,
            _ => {}
        }
        Ok(())
    }

    /// Powers up again from the EPM copy, keeping what the network state says (ownership).
    pub fn restart(&mut self, epm: impl Fn(u16) -> Option<u32>) {
        let owned = self.drive.exstatus() != 0;
        self.vars = Variables::power_up(epm);
        self.drive = Drive::new();
        self.drive.set_owned(owned);
        self.drive.publish(&mut self.vars);
    }
}
