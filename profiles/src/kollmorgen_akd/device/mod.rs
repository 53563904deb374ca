//! The simulated AKD: operating modes, enable, trapezoidal moves and jogs, homing, stops,
//! software limits, faults and actual torque, advanced on a fixed 1 ms control tick.
//!
//! Everything is integer arithmetic in the drive's own feedback counts (2^32 per
//! revolution, as EIP.POSUNIT and EIP.PROFUNIT define them), so the simulation is
//! deterministic: the same commands at the same ticks give the same counts. The profile
//! converts to and from position and profile units. The actual position follows the
//! profile generator exactly (no following error); torque comes from a one-inertia model
//! with viscous friction: `torque_mA = acceleration / TORQUE_A + velocity / TORQUE_V`,
//! reported within the drive's peak current.
//!
//! Stops: Smooth Stop ramps at the motion's own deceleration; Hard Stop, the PLC going to
//! Program mode (run/idle) and losing the owner are controlled stops at DRV.DECSTOP
//! ([`Drive::controlled_stop`]); after a Hard Stop or a lost owner the drive disables at rest.

use enip_stack::{Duration, Instant};

/// The control tick.
pub const TICK: Duration = Duration::from_micros(1_000);
/// Most ticks one poll catches up on (a host that stalled longer loses the rest).
const MAX_CATCH_UP: u32 = 10_000;

mod config;
mod status;
mod trajectory;

pub use config::{
    motionstat, Config, Fault, Mode, Refusal, COUNTS_PER_REV, HOME_TICKS, MAX_TORQUE_MA,
    MAX_VELOCITY, SWLS_NEGATIVE, SWLS_POSITIVE, TICKS_PER_S, TORQUE_A, TORQUE_RATE, TORQUE_V,
};
use trajectory::{Motion, CREEP};

/// The simulated drive.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Drive {
    /// Its settings.
    pub config: Config,
    enabled: bool,
    hard_stop_latched: bool,
    smooth_stop: bool,
    /// Disable once the running stop reaches standstill (a lost owner).
    disable_at_rest: bool,
    fault: Option<Fault>,
    homed: bool,
    position: i64,
    position_rem: i64,
    velocity: i64,
    acceleration: i64,
    target: i64,
    /// The target of the last move (MT.CNTL 3's base), kept when a stop ends it short.
    last_target: i64,
    motion: Motion,
    /// The motion task the running move executes (Start Block), if it is one.
    task: Option<u8>,
    torque_command: i32,
    positive: bool,
    task_completed: bool,
    target_crossed: bool,
    task_invalid: bool,
    moved: bool,
    next_tick: Option<Instant>,
}

impl Default for Drive {
    fn default() -> Self {
        Self::new()
    }
}

impl Drive {
    /// A drive at power-up: disabled, not homed, at position 0.
    pub const fn new() -> Self {
        Drive {
            config: Config::new(),
            enabled: false,
            hard_stop_latched: false,
            smooth_stop: false,
            disable_at_rest: false,
            fault: None,
            homed: false,
            position: 0,
            position_rem: 0,
            velocity: 0,
            acceleration: 0,
            target: 0,
            last_target: 0,
            motion: Motion::Idle,
            task: None,
            torque_command: 0,
            positive: false,
            task_completed: false,
            target_crossed: false,
            task_invalid: false,
            moved: false,
            next_tick: None,
        }
    }

    /// Enables (clearing faults and a hard-stop latch: the enable cycle the manual asks
    /// for) or disables the power stage. Disabling stops at once (the motor coasts; the
    /// simulation has no load to coast).
    pub fn set_enable(&mut self, on: bool) {
        if on {
            self.fault = None;
            self.hard_stop_latched = false;
        }
        self.enabled = on;
        self.disable_at_rest = false;
        self.velocity = 0;
        self.acceleration = 0;
        self.idle();
    }

    /// DRV.CLRFAULTS: clears the faults and the invalid-task flag (the drive stays
    /// disabled until enabled again).
    pub fn clear_faults(&mut self) {
        self.fault = None;
        self.task_invalid = false;
    }

    /// Control word Hard Stop: a controlled stop at DRV.DECSTOP, after which the drive
    /// disables until the Enable bit is cleared and set again.
    pub fn hard_stop(&mut self) {
        if self.enabled && !self.hard_stop_latched {
            self.hard_stop_latched = true;
            self.stop(self.config.decstop, true);
        }
    }

    /// A controlled stop at DRV.DECSTOP of whatever runs (the PLC went to Program mode or
    /// the owner was lost); homing is abandoned. With `disable`, the drive disables once
    /// at rest (at once if it already is). Nothing happens while disabled.
    pub fn controlled_stop(&mut self, disable: bool) {
        if !self.enabled {
            return;
        }
        match self.motion {
            Motion::Idle if self.velocity == 0 => {
                if disable {
                    self.set_enable(false);
                }
                return;
            }
            Motion::Homing { .. } => self.idle(),
            Motion::Stop { dec, .. } if dec >= self.config.decstop => {}
            _ => self.stop(self.config.decstop, false),
        }
        if matches!(self.motion, Motion::Idle) && self.velocity == 0 {
            if disable {
                self.set_enable(false);
            }
            return;
        }
        self.disable_at_rest |= disable;
    }

    /// A new owner connected: a stop begun for the lost one no longer disables.
    pub fn keep_enabled(&mut self) {
        self.disable_at_rest = false;
    }

    /// Control word Smooth Stop (a level): while set, motion ramps down with its own
    /// deceleration and no new motion starts.
    pub fn set_smooth_stop(&mut self, on: bool) {
        if on && !self.smooth_stop {
            let dec = match self.motion {
                Motion::Move { dec, .. } | Motion::Jog { dec, .. } => Some(dec),
                Motion::Torque => Some(self.config.decstop),
                _ => None,
            };
            if let Some(dec) = dec {
                self.stop(dec, false);
            }
        }
        self.smooth_stop = on;
    }

    /// Starts a ramp to standstill at `dec`; a move it interrupts keeps its target watched,
    /// so running past it sets "target crossed".
    fn stop(&mut self, dec: i64, emergency: bool) {
        let watch = match self.motion {
            Motion::Move { target, .. } => Some(target),
            Motion::Stop { watch, .. } => watch,
            _ => None,
        };
        self.motion = Motion::Stop {
            dec,
            emergency,
            watch,
        };
    }

    /// True if a new motion may start now.
    pub fn ready(&self) -> bool {
        self.enabled && !self.hard_stop_latched && !self.smooth_stop && self.fault.is_none()
    }

    /// A motion starts: the previous one (and the task it ran) is replaced.
    fn begin(&mut self, motion: Motion) {
        self.motion = motion;
        self.task = None;
        self.task_invalid = false;
        self.disable_at_rest = false;
    }

    /// The manual's p.11 rule: motion in position mode before homing faults the drive.
    fn refuse_unhomed(&mut self) -> Result<(), Refusal> {
        if self.config.mode != Mode::Position || self.homed {
            return Ok(());
        }
        self.fault = Some(Fault::NotHomed);
        self.enabled = false;
        self.velocity = 0;
        self.idle();
        Err(Refusal::NotHomed)
    }

    /// Starts a move to `target` counts at `v` counts/s with `acc`/`dec` counts/s².
    /// `Ok(false)` if the drive cannot move now (the data is kept, no motion starts); a
    /// move before homing faults the drive; a velocity, acceleration or deceleration of 0
    /// is an invalid motion (DRV.MOTIONSTAT bit 10).
    pub fn start_move(&mut self, target: i64, v: i64, acc: i64, dec: i64) -> Result<bool, Refusal> {
        if !self.ready() {
            return Ok(false);
        }
        if v == 0 || acc <= 0 || dec <= 0 {
            self.task_invalid = true;
            return Err(Refusal::Invalid);
        }
        self.refuse_unhomed()?;
        self.begin(Motion::Move {
            target,
            v: v.abs().clamp(CREEP, MAX_VELOCITY),
            acc,
            dec,
        });
        self.target = target;
        self.last_target = target;
        self.task_completed = false;
        self.target_crossed = false;
        self.moved = true;
        Ok(true)
    }

    /// Starts motion task `task`'s move (as [`Drive::start_move`]); Status Word 1 bit 1
    /// and response byte 1 follow it until the move ends or another motion replaces it.
    pub fn start_task_move(
        &mut self,
        task: u8,
        target: i64,
        v: i64,
        acc: i64,
        dec: i64,
    ) -> Result<bool, Refusal> {
        let started = self.start_move(target, v, acc, dec)?;
        if started {
            self.task = Some(task);
        }
        Ok(started)
    }

    /// A motion task could not be activated (undefined or invalid): DRV.MOTIONSTAT bit 10
    /// until the next motion starts or DRV.CLRFAULTS.
    pub fn task_rejected(&mut self) {
        self.task_invalid = true;
    }

    /// Starts a jog towards the signed velocity `v` counts/s; a jog to 0 ramps down and
    /// ends. In position mode the drive must be homed first (p.11), like a move.
    pub fn start_jog(&mut self, v: i64, acc: i64, dec: i64) -> Result<bool, Refusal> {
        if !self.ready() {
            return Ok(false);
        }
        self.refuse_unhomed()?;
        self.begin(Motion::Jog {
            v: v.clamp(-MAX_VELOCITY, MAX_VELOCITY),
            acc: acc.max(1),
            dec: dec.max(1),
        });
        self.moved = false;
        self.task_completed = false;
        Ok(true)
    }

    /// Sets the torque command (mA); in torque mode the motor follows it.
    pub fn set_torque(&mut self, milliamps: i32) -> bool {
        self.torque_command = milliamps.clamp(-MAX_TORQUE_MA, MAX_TORQUE_MA);
        if self.config.mode == Mode::Torque && self.ready() {
            if self.motion != Motion::Torque {
                self.begin(Motion::Torque);
            }
            self.moved = false;
            return true;
        }
        false
    }

    /// HOME.MOVE: starts homing; refused unless the drive is ready.
    pub fn start_homing(&mut self) -> Result<(), Refusal> {
        if !self.ready() {
            return Err(Refusal::NotReady);
        }
        self.begin(Motion::Homing {
            ticks_left: HOME_TICKS,
        });
        Ok(())
    }

    /// Advances the drive to `now`, tick by tick; returns when the next tick is due.
    pub fn poll(&mut self, now: Instant) -> Instant {
        let mut next = self.next_tick.unwrap_or(now);
        let mut ticks = 0;
        while next <= now && ticks < MAX_CATCH_UP {
            self.tick();
            next = next.add(TICK);
            ticks = ticks.saturating_add(1);
        }
        if next <= now {
            next = now.add(TICK);
        }
        self.next_tick = Some(next);
        next
    }

    fn idle(&mut self) {
        self.motion = Motion::Idle;
        self.target = self.position;
    }

    /// One control tick.
    pub fn tick(&mut self) {
        let before = self.velocity;
        if self.enabled {
            self.motion_step();
            self.advance();
            self.limit_check();
            self.watch_target();
        }
        self.acceleration = self
            .velocity
            .saturating_sub(before)
            .saturating_mul(TICKS_PER_S);
        if self.velocity != 0 {
            self.positive = self.velocity > 0;
        }
    }

    fn advance(&mut self) {
        let total = self.velocity.saturating_add(self.position_rem);
        self.position = self.position.saturating_add(total / TICKS_PER_S);
        self.position_rem = total % TICKS_PER_S;
    }

    fn motion_step(&mut self) {
        match self.motion {
            Motion::Idle => self.velocity = 0,
            Motion::Move {
                target,
                v,
                acc,
                dec,
            } => self.move_step(target, v, acc, dec),
            Motion::Jog { v, acc, dec } => {
                self.ramp(v, acc, dec);
                if v == 0 && self.velocity == 0 {
                    self.idle();
                }
            }
            Motion::Stop { dec, emergency, .. } => {
                self.ramp(0, dec, dec);
                if self.velocity == 0 {
                    self.idle();
                    if emergency || self.disable_at_rest {
                        self.enabled = false;
                        self.disable_at_rest = false;
                    }
                }
            }
            Motion::Homing { ticks_left } => {
                self.velocity = 0;
                if ticks_left <= 1 {
                    self.position = self.config.home_position;
                    self.position_rem = 0;
                    self.homed = true;
                    self.idle();
                } else {
                    self.motion = Motion::Homing {
                        ticks_left: ticks_left.saturating_sub(1),
                    };
                }
            }
            Motion::Torque => {
                let error = i64::from(self.torque_command)
                    .saturating_mul(TORQUE_V)
                    .saturating_sub(self.velocity);
                let step = error.saturating_mul(TORQUE_RATE) / TICKS_PER_S;
                self.velocity = self
                    .velocity
                    .saturating_add(step)
                    .clamp(-MAX_VELOCITY, MAX_VELOCITY);
            }
        }
    }

    /// Ramps the velocity towards `v` with `acc` (speeding up) or `dec` (slowing down).
    fn ramp(&mut self, v: i64, acc: i64, dec: i64) {
        self.velocity = trajectory::ramp(self.velocity, v, acc, dec);
    }

    /// One tick of a trapezoidal move: the speed the remaining distance allows at `dec`,
    /// reached with `acc`; the last tick lands exactly on the target.
    fn move_step(&mut self, target: i64, v: i64, acc: i64, dec: i64) {
        let remaining = target.saturating_sub(self.position);
        let dir = remaining.signum();
        if remaining == 0 {
            self.finish_move();
            return;
        }
        let next = trajectory::move_speed(remaining, self.velocity, v, acc, dec);
        self.velocity = next.saturating_mul(dir);
        let travel = next.saturating_add(self.position_rem.saturating_mul(dir)) / TICKS_PER_S;
        if next > 0 && i128::from(travel) >= i128::from(remaining).abs() {
            self.position = target;
            self.position_rem = 0;
            self.velocity = 0;
            self.finish_move();
            // Position already placed: advance() must not move it again.
            self.position_rem = 0;
        }
    }

    fn finish_move(&mut self) {
        self.motion = Motion::Idle;
        self.velocity = 0;
        self.task = None;
        self.task_completed = self.in_window();
    }

    /// A stop that interrupted a move and runs past its target: "target crossed".
    fn watch_target(&mut self) {
        if let Motion::Stop {
            watch: Some(target),
            ..
        } = self.motion
        {
            let past = (self.velocity > 0 && self.position > target)
                || (self.velocity < 0 && self.position < target);
            self.target_crossed |= past;
        }
    }

    /// Software limits: a motion heading beyond an enabled limit stops at DRV.DECSTOP.
    fn limit_check(&mut self) {
        let beyond = (self.positive_limit() && self.velocity > 0)
            || (self.negative_limit() && self.velocity < 0);
        if beyond && !matches!(self.motion, Motion::Stop { .. }) {
            self.stop(self.config.decstop, false);
        }
    }

    fn in_window(&self) -> bool {
        self.position.abs_diff(self.target) <= self.config.window.unsigned_abs()
    }
}
