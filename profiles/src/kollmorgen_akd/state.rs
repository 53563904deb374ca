//! The drive's state as the network sees it: the simulated drive, the Position Controller
//! settings (units, targets, profile) and the stored parameter values, with the unit
//! conversions between the network's position/profile units and the drive's counts.

use enip_stack::cip::{CipError, CipResult, General};

use super::device::{Drive, Mode, Refusal, COUNTS_PER_REV};
use super::maps::Maps;
use super::motion_tasks::MotionTasks;
use super::params::STORED;

/// EIP.POSUNIT / EIP.PROFUNIT default: 2^16, so 2^16 units per revolution (parameter
/// reference, "EIP.POSUNIT": "The default value is 2^16 = 65536"). Appendix A says
/// "default 1"; the parameter pages are the more specific text (\[R\] item 7).
pub const DEFAULT_UNITS: u32 = 65_536;

/// Position Controller settings (object 0x25 attributes 4-10 and the torque command).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Settings {
    /// Attribute 4 / EIP.POSUNIT: counts per position unit (never 0).
    pub position_units: u32,
    /// Attribute 5 / EIP.PROFUNIT: counts/s (counts/s²) per velocity (acceleration) unit.
    pub profile_units: u32,
    /// Attribute 6: target position, position units.
    pub target_position: i32,
    /// Attribute 7: target velocity, velocity units (magnitude used).
    pub target_velocity: i32,
    /// Attribute 8 / DRV.ACC: acceleration of target-position and target-velocity loads.
    pub acceleration: i32,
    /// Attribute 9 / DRV.DEC: their deceleration.
    pub deceleration: i32,
    /// Attribute 10: 0 absolute, 1 incremental.
    pub incremental: bool,
}

impl Settings {
    /// Power-up values: 2^16 units, 1 rev/s, 10 rev/s².
    pub const fn new() -> Self {
        Settings {
            position_units: DEFAULT_UNITS,
            profile_units: DEFAULT_UNITS,
            target_position: 0,
            target_velocity: 65_536,
            acceleration: 655_360,
            deceleration: 655_360,
            incremental: false,
        }
    }
}

impl Default for Settings {
    fn default() -> Self {
        Self::new()
    }
}

/// Everything but the I/O handshake and the non-volatile copy.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct State {
    /// The simulated drive.
    pub drive: Drive,
    /// The Position Controller settings.
    pub pc: Settings,
    /// Parameters that only hold a value (analog I/O scaling...), by [`STORED`] index.
    pub stored: [i64; STORED],
    /// Load Complete: Status Word 2 bit 7 and Position Controller attribute 58.
    pub load_complete: bool,
    /// The motion task table.
    pub tasks: MotionTasks,
    /// EIP.CMDMAP and EIP.RSPMAP, the dynamic map's lists.
    pub maps: Maps,
}

fn clamp32(v: i64) -> i32 {
    v.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32
}

fn out_of_range() -> CipError {
    CipError::new(General::InvalidAttributeValue)
}

impl State {
    /// Power-up state.
    pub fn new() -> Self {
        State {
            drive: Drive::new(),
            pc: Settings::new(),
            stored: super::params::stored_defaults(),
            load_complete: false,
            tasks: MotionTasks::default(),
            maps: Maps::new(),
        }
    }

    /// Position units to counts.
    pub fn pos_counts(&self, units: i64) -> i64 {
        units.saturating_mul(i64::from(self.pc.position_units))
    }
    /// Counts to position units (floor), saturated to 32 bits.
    pub fn pos_units(&self, counts: i64) -> i32 {
        clamp32(counts.div_euclid(i64::from(self.pc.position_units.max(1))))
    }
    /// Counts to position units, 64 bits.
    pub fn pos_units64(&self, counts: i64) -> i64 {
        counts.div_euclid(i64::from(self.pc.position_units.max(1)))
    }
    /// Velocity (acceleration) units to counts/s (counts/s²).
    pub fn prof_counts(&self, units: i64) -> i64 {
        units.saturating_mul(i64::from(self.pc.profile_units))
    }
    /// Counts/s (counts/s²) to velocity (acceleration) units, 64 bits (towards zero).
    pub fn prof_units64(&self, counts: i64) -> i64 {
        counts
            .checked_div(i64::from(self.pc.profile_units.max(1)))
            .unwrap_or(counts)
    }
    /// Counts/s to velocity units, saturated to 32 bits.
    pub fn prof_units(&self, counts: i64) -> i32 {
        clamp32(self.prof_units64(counts))
    }

    /// A velocity, acceleration or deceleration in profile units: at least 1, at most the
    /// drive's limits (100 rev/s; 10^6 rev/s²); else 0x09.
    pub fn check_profile(&self, units: i64, accel: bool) -> CipResult<i64> {
        let counts = self.prof_counts(units);
        let max = if accel {
            1_000_000 * COUNTS_PER_REV
        } else {
            super::device::MAX_VELOCITY
        };
        if units < 1 || counts > max {
            return Err(out_of_range());
        }
        Ok(counts)
    }

    /// Attribute 3: a new operating mode; refused (0x10) while a trajectory runs.
    pub fn set_mode(&mut self, code: u8) -> CipResult {
        let mode = Mode::from_code(code).ok_or(out_of_range())?;
        if mode != self.drive.config.mode && self.drive.in_motion() {
            return Err(General::DeviceStateConflict.into());
        }
        self.drive.config.mode = mode;
        Ok(())
    }

    /// Attribute 11 (and an I/O load of the target position or target velocity): starts
    /// the profile the attributes describe when the command matches the mode. Position
    /// mode: to attribute 6 (incremental per attribute 10) at attribute 7; velocity mode:
    /// at attribute 7 in the given direction. `Ok(false)` when no motion starts.
    pub fn start_profile(&mut self, positive: bool) -> Result<bool, Refusal> {
        let acc = self.prof_counts(i64::from(self.pc.acceleration));
        let dec = self.prof_counts(i64::from(self.pc.deceleration));
        let v = self.prof_counts(i64::from(self.pc.target_velocity).abs());
        match self.drive.config.mode {
            Mode::Position => {
                let target = self.pos_counts(i64::from(self.pc.target_position));
                let target = if self.pc.incremental {
                    self.drive.target().saturating_add(target)
                } else {
                    target
                };
                self.drive.start_move(target, v, acc, dec)
            }
            Mode::Velocity => {
                let v = if positive { v } else { v.saturating_neg() };
                Ok(self.drive.start_jog(v, acc, dec))
            }
            Mode::Torque => Ok(false),
        }
    }

    /// HOME.MOVE (parameter 205, attribute 101): starts homing; 0x10 unless the drive is
    /// enabled and ready.
    pub fn home(&mut self) -> CipResult {
        self.drive
            .start_homing()
            .map_err(|_| CipError::new(General::DeviceStateConflict))
    }
}

impl Default for State {
    fn default() -> Self {
        Self::new()
    }
}
