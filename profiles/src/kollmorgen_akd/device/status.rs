//! What the simulated drive reports: the status words' bits, DRV.MOTIONSTAT, actual values.

use super::trajectory::Motion;
use super::{motionstat, Drive, Fault, MAX_TORQUE_MA, SWLS_NEGATIVE, SWLS_POSITIVE};
use super::{TORQUE_A, TORQUE_V};

impl Drive {
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
    /// Status Word 1 bit 1 and response byte 1: the motion task whose move runs now.
    pub fn executing_task(&self) -> Option<u8> {
        self.task.filter(|_| self.moving_to_target())
    }
    /// True while a stop ramp (Smooth Stop, Hard Stop, controlled stop, limit) runs.
    pub fn stopping(&self) -> bool {
        matches!(self.motion, Motion::Stop { .. })
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
    /// The target of the last move, counts, also when a stop ended it short.
    pub fn last_target(&self) -> i64 {
        self.last_target
    }
    /// The torque command, mA.
    pub fn torque_command(&self) -> i32 {
        self.torque_command
    }
    /// Actual torque (current), mA: inertia plus viscous friction, within the peak
    /// current.
    pub fn torque(&self) -> i32 {
        if !self.enabled {
            return 0;
        }
        let ma = (self.acceleration / TORQUE_A).saturating_add(self.velocity / TORQUE_V);
        let peak = i64::from(MAX_TORQUE_MA);
        ma.clamp(peak.saturating_neg(), peak) as i32
    }
    /// Status Word 2 bit 3: at or beyond the positive software limit (SWLS.EN bit 1).
    pub fn positive_limit(&self) -> bool {
        self.config.swls & SWLS_POSITIVE != 0 && self.position >= self.config.limit1
    }
    /// Status Word 2 bit 4: at or beyond the negative software limit (SWLS.EN bit 0).
    pub fn negative_limit(&self) -> bool {
        self.config.swls & SWLS_NEGATIVE != 0 && self.position <= self.config.limit0
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
        set(self.task_invalid, TASK_INVALID);
        set(self.moved && self.task_completed, TASK_COMPLETED);
        set(
            matches!(self.motion, Motion::Jog { v, .. } if v == self.velocity),
            VELOCITY_REACHED,
        );
        set(self.fault == Some(Fault::NotHomed), TASK_FAULT);
        set(self.moved && self.target_crossed, TARGET_CROSSED);
        set(self.moved && self.in_window(), TARGET_REACHED);
        s
    }
}
