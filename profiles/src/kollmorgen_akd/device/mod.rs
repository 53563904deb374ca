//! The simulated AKD: operating modes, enable, trapezoidal moves and jogs, homing, stops,
//! software limits, faults and actual torque, advanced on a fixed 1 ms control tick.
//!
//! Everything is integer arithmetic in the drive's own feedback counts (2^32 per
//! revolution, as EIP.POSUNIT and EIP.PROFUNIT define them), so the simulation is
//! deterministic: the same commands at the same ticks give the same counts. The profile
//! converts to and from position and profile units. The actual position follows the
//! profile generator exactly (no following error); torque comes from a one-inertia model
//! with viscous friction: `torque_mA = (acceleration + velocity / 1 s) / TORQUE_K`.

use enip_stack::{Duration, Instant};

/// The control tick.
pub const TICK: Duration = Duration::from_micros(1_000);
/// Most ticks one poll catches up on (a host that stalled longer loses the rest).
const MAX_CATCH_UP: u32 = 10_000;

mod config;
mod trajectory;

pub use config::{
    motionstat, Config, Fault, Mode, Refusal, COUNTS_PER_REV, HOME_TICKS, MAX_TORQUE_MA,
    MAX_VELOCITY, TICKS_PER_S, TORQUE_K,
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
    fault: Option<Fault>,
    homed: bool,
    position: i64,
    position_rem: i64,
    velocity: i64,
    acceleration: i64,
    target: i64,
    motion: Motion,
    torque_command: i32,
    positive: bool,
    task_completed: bool,
    target_crossed: bool,
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
            fault: None,
            homed: false,
            position: 0,
            position_rem: 0,
            velocity: 0,
            acceleration: 0,
            target: 0,
            motion: Motion::Idle,
            torque_command: 0,
            positive: false,
            task_completed: false,
            target_crossed: false,
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
        self.velocity = 0;
        self.acceleration = 0;
        self.idle();
    }

    /// DRV.CLRFAULTS: clears the faults (the drive stays disabled until enabled again).
    pub fn clear_faults(&mut self) {
        self.fault = None;
    }

    /// Control word Hard Stop: a controlled stop at DRV.DECSTOP, after which the drive
    /// disables until the Enable bit is cleared and set again.
    pub fn hard_stop(&mut self) {
        if self.enabled && !self.hard_stop_latched {
            self.hard_stop_latched = true;
            self.motion = Motion::Stop {
                dec: self.config.decstop,
                emergency: true,
            };
        }
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
                self.motion = Motion::Stop {
                    dec,
                    emergency: false,
                };
            }
        }
        self.smooth_stop = on;
    }

    /// True if a new motion may start now.
    pub fn ready(&self) -> bool {
        self.enabled && !self.hard_stop_latched && !self.smooth_stop && self.fault.is_none()
    }

    /// Starts a move to `target` counts at `v` counts/s with `acc`/`dec` counts/s².
    /// `Ok(false)` if the drive cannot move now (the data is kept, no motion starts); a
    /// move before homing faults the drive.
    pub fn start_move(&mut self, target: i64, v: i64, acc: i64, dec: i64) -> Result<bool, Refusal> {
        if !self.ready() {
            return Ok(false);
        }
        if !self.homed {
            self.fault = Some(Fault::NotHomed);
            self.enabled = false;
            self.velocity = 0;
            self.idle();
            return Err(Refusal::NotHomed);
        }
        self.target = target;
        self.task_completed = false;
        self.target_crossed = false;
        self.moved = true;
        self.motion = Motion::Move {
            target,
            v: v.abs().clamp(CREEP, MAX_VELOCITY),
            acc: acc.max(1),
            dec: dec.max(1),
        };
        Ok(true)
    }

    /// Starts a jog towards the signed velocity `v` counts/s.
    pub fn start_jog(&mut self, v: i64, acc: i64, dec: i64) -> bool {
        if !self.ready() {
            return false;
        }
        self.moved = false;
        self.task_completed = false;
        self.motion = Motion::Jog {
            v: v.clamp(-MAX_VELOCITY, MAX_VELOCITY),
            acc: acc.max(1),
            dec: dec.max(1),
        };
        true
    }

    /// Sets the torque command (mA); in torque mode the motor follows it.
    pub fn set_torque(&mut self, milliamps: i32) -> bool {
        self.torque_command = milliamps.clamp(-MAX_TORQUE_MA, MAX_TORQUE_MA);
        if self.config.mode == Mode::Torque && self.ready() {
            self.moved = false;
            self.motion = Motion::Torque;
            return true;
        }
        false
    }

    /// HOME.MOVE: starts homing; refused unless the drive is ready.
    pub fn start_homing(&mut self) -> Result<(), Refusal> {
        if !self.ready() {
            return Err(Refusal::NotReady);
        }
        self.motion = Motion::Homing {
            ticks_left: HOME_TICKS,
        };
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
            Motion::Jog { v, acc, dec } => self.ramp(v, acc, dec),
            Motion::Stop { dec, emergency } => {
                self.ramp(0, dec, dec);
                if self.velocity == 0 {
                    self.idle();
                    if emergency {
                        self.enabled = false;
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
                let acc = i64::from(self.torque_command)
                    .saturating_mul(TORQUE_K)
                    .saturating_sub(self.velocity);
                self.velocity = self
                    .velocity
                    .saturating_add(acc / TICKS_PER_S)
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
            self.target_crossed = true;
            self.finish_move();
            // Position already placed: advance() must not move it again.
            self.position_rem = 0;
        }
    }

    fn finish_move(&mut self) {
        self.motion = Motion::Idle;
        self.velocity = 0;
        self.task_completed = self.in_window();
    }

    /// Software limits: a motion heading beyond an enabled limit stops at DRV.DECSTOP.
    fn limit_check(&mut self) {
        if !self.config.swls_enabled {
            return;
        }
        let beyond = (self.position >= self.config.limit1 && self.velocity > 0)
            || (self.position <= self.config.limit0 && self.velocity < 0);
        if beyond && !matches!(self.motion, Motion::Stop { .. }) {
            self.motion = Motion::Stop {
                dec: self.config.decstop,
                emergency: false,
            };
        }
    }

    fn in_window(&self) -> bool {
        self.position.abs_diff(self.target) <= self.config.window.unsigned_abs()
    }

    /// Status Word 1 bit 7: the power stage is enabled.
    pub fn enabled(&self) -> bool {
        self.enabled
    }
    /// Status Word 1 bit 5: homed.
    pub fn homed(&self) -> bool {
        self.homed
    }
    /// Status Word 1 bit 4: the direction of the last motion (1 positive; 0 negative or
    /// no motion since power-up).
    pub fn positive(&self) -> bool {
        self.positive
    }
    /// Status Word 1 bit 3: the fault present, if any.
    pub fn fault(&self) -> Option<Fault> {
        self.fault
    }
    /// Status Word 1 bit 2: no trajectory and the motor inside the window of the last
    /// target position.
    pub fn in_position(&self) -> bool {
        !self.in_motion() && self.in_window()
    }
    /// Status Word 1 bit 0: a trajectory is in progress (moving, stopping or homing).
    pub fn in_motion(&self) -> bool {
        self.enabled && (self.motion != Motion::Idle || self.velocity != 0)
    }
    /// True while a profile move (Position Controller attribute 11) is in progress.
    pub fn moving_to_target(&self) -> bool {
        matches!(self.motion, Motion::Move { .. })
    }
    /// True while the hard stop latch waits for an enable cycle.
    pub fn hard_stopped(&self) -> bool {
        self.hard_stop_latched
    }
    /// True while the Smooth Stop level is set.
    pub fn smooth_stopped(&self) -> bool {
        self.smooth_stop
    }
    /// Actual position, counts.
    pub fn position(&self) -> i64 {
        self.position
    }
    /// Actual velocity, counts/s.
    pub fn velocity(&self) -> i64 {
        self.velocity
    }
    /// The commanded (trajectory) position, counts: the profile generator's, which the
    /// simulated motor follows exactly.
    pub fn commanded_position(&self) -> i64 {
        self.position
    }
    /// The commanded velocity, counts/s: the velocity the motion aims for.
    pub fn commanded_velocity(&self) -> i64 {
        match self.motion {
            Motion::Move { target, v, .. } => {
                v.saturating_mul(target.saturating_sub(self.position).signum())
            }
            Motion::Jog { v, .. } => v,
            Motion::Torque => self.velocity,
            _ => 0,
        }
    }
    /// The last target position, counts.
    pub fn target(&self) -> i64 {
        self.target
    }
    /// The torque command, mA.
    pub fn torque_command(&self) -> i32 {
        self.torque_command
    }
    /// Actual torque (current), mA.
    pub fn torque(&self) -> i32 {
        if !self.enabled {
            return 0;
        }
        let ma = self.acceleration.saturating_add(self.velocity) / TORQUE_K;
        ma.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32
    }
    /// Status Word 2 bit 3: at or beyond the positive software limit (limits enabled).
    pub fn positive_limit(&self) -> bool {
        self.config.swls_enabled && self.position >= self.config.limit1
    }
    /// Status Word 2 bit 4: at or beyond the negative software limit (limits enabled).
    pub fn negative_limit(&self) -> bool {
        self.config.swls_enabled && self.position <= self.config.limit0
    }
    /// DRV.MOTIONSTAT.
    pub fn motionstat(&self) -> u32 {
        use motionstat::*;
        let mut s = 0;
        let mut set = |on: bool, bit: u32| {
            if on {
                s |= bit;
            }
        };
        set(matches!(self.motion, Motion::Move { .. }), TASK_ACTIVE);
        set(self.homed, HOME_FOUND | HOME_FINISHED);
        set(matches!(self.motion, Motion::Homing { .. }), HOMING);
        set(
            matches!(
                self.motion,
                Motion::Stop {
                    emergency: true,
                    ..
                }
            ),
            ESTOP,
        );
        set(self.moved && self.task_completed, TASK_COMPLETED);
        set(
            matches!(self.motion, Motion::Jog { v, .. } if v == self.velocity),
            VELOCITY_REACHED,
        );
        set(self.fault == Some(Fault::NotHomed), TASK_FAULT);
        set(self.moved && self.target_crossed, TARGET_CROSSED);
        set(self.moved && self.in_position(), TARGET_REACHED);
        s
    }
}
