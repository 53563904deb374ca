//! The drive's state as the network sees it: the simulated drive, the Position Controller
//! settings (units, targets, profile) and the stored parameter values, with the unit
//! conversions between the network's position/profile units and the drive's counts.

use enip_stack::cip::{CipError, CipResult, General};

use super::device::{Drive, Mode, Refusal, COUNTS_PER_REV};
use super::maps::Maps;
use super::motion_tasks::{self, cntl, MotionTasks, StartError, Task, TASKS};
use super::params::{self, id, Param, STORED};

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
    /// Attribute 22: jog velocity, velocity units (signed: its sign is the direction); the
    /// velocity of a velocity-mode start through attribute 11 (section 7).
    pub jog_velocity: i32,
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
            jog_velocity: 65_536,
        }
    }
}

impl Default for Settings {
    fn default() -> Self {
        Self::new()
    }
}

/// The settings a command can change before it is refused (the command dynamic map's
/// parameters and the command's own data): kept to undo a refused load.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Snapshot {
    pc: Settings,
    config: super::device::Config,
    stored: [i64; STORED],
    number: u8,
    edit: Task,
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
            stored: params::stored_defaults(),
            load_complete: false,
            tasks: MotionTasks::default(),
            maps: Maps::new(),
        }
    }

    /// The settings a refused load must leave as they were.
    pub fn snapshot(&self) -> Snapshot {
        Snapshot {
            pc: self.pc,
            config: self.drive.config,
            stored: self.stored,
            number: self.tasks.number,
            edit: self.tasks.edit,
        }
    }

    /// Puts back the settings of `snapshot` (a refused load changes nothing).
    pub fn restore(&mut self, snapshot: &Snapshot) {
        self.pc = snapshot.pc;
        self.drive.config = snapshot.config;
        self.stored = snapshot.stored;
        self.tasks.number = snapshot.number;
        self.tasks.edit = snapshot.edit;
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
    /// mode: to attribute 6 (incremental per attribute 10) at attribute 7 (a velocity of 0
    /// is an invalid motion); velocity mode: at `velocity` units/s in the given direction
    /// (0 ramps down and ends). `Ok(false)` when no motion starts.
    pub fn start_profile(&mut self, velocity: i32, positive: bool) -> Result<bool, Refusal> {
        let acc = self.prof_counts(i64::from(self.pc.acceleration));
        let dec = self.prof_counts(i64::from(self.pc.deceleration));
        let v = self.prof_counts(i64::from(velocity).abs());
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
                self.drive.start_jog(v, acc, dec)
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

    /// The value of `param` in network scaling.
    pub fn param(&self, param: &Param) -> i64 {
        let d = &self.drive;
        let pc = &self.pc;
        match param.instance {
            id::EIP_POSUNIT => i64::from(pc.position_units),
            id::EIP_PROFUNIT => i64::from(pc.profile_units),
            id::DRV_ACC => i64::from(pc.acceleration),
            id::DRV_DEC => i64::from(pc.deceleration),
            id::DRV_DECSTOP => self.prof_units64(d.config.decstop),
            id::DRV_MOTIONSTAT => i64::from(d.motionstat()),
            id::HOME_MODE => i64::from(d.config.home_mode),
            id::HOME_P => self.pos_units64(d.config.home_position),
            id::MT_TPOSWND => self.pos_units64(d.config.window),
            id::PL_FB => self.pos_units64(d.position()),
            id::VL_FB => self.prof_units64(d.velocity()),
            // IL.FB is in amperes: x1000 gives milliamps.
            id::IL_FB => i64::from(d.torque()),
            id::SWLS_EN => i64::from(d.config.swls),
            id::SWLS_LIMIT0 => self.pos_units64(d.config.limit0),
            id::SWLS_LIMIT1 => self.pos_units64(d.config.limit1),
            id::MT_NUM => i64::from(self.tasks.number),
            id::MT_P => self.tasks.edit.position,
            id::MT_V => self.tasks.edit.velocity,
            id::MT_ACC => self.tasks.edit.acceleration,
            id::MT_DEC => self.tasks.edit.deceleration,
            id::MT_CNTL => self.tasks.edit.control,
            other => params::stored_index(other)
                .and_then(|i| self.stored.get(i).copied())
                .unwrap_or(0),
        }
    }

    /// Writes `value` (network scaling) to `param`, or refuses it with 0x09 and changes
    /// nothing. Commands are the caller's (they reach the drive and the NV copy).
    pub fn set_param(&mut self, param: &Param, value: i64) -> CipResult {
        let positive = |v: i64| {
            u32::try_from(v)
                .ok()
                .filter(|&v| v > 0)
                .ok_or(out_of_range())
        };
        let profile32 = |s: &State, v: i64| {
            s.check_profile(v, true)?;
            i32::try_from(v).map_err(|_| out_of_range())
        };
        match param.instance {
            id::EIP_POSUNIT => self.pc.position_units = positive(value)?,
            id::EIP_PROFUNIT => self.pc.profile_units = positive(value)?,
            id::DRV_ACC => self.pc.acceleration = profile32(self, value)?,
            id::DRV_DEC => self.pc.deceleration = profile32(self, value)?,
            id::DRV_DECSTOP => self.drive.config.decstop = self.check_profile(value, true)?,
            id::HOME_MODE => self.drive.config.home_mode = params::home_mode(value)?,
            id::HOME_P => self.drive.config.home_position = self.pos_counts(value),
            id::MT_TPOSWND if value >= 0 => self.drive.config.window = self.pos_counts(value),
            id::SWLS_EN if (0..=3).contains(&value) => self.drive.config.swls = value as u8,
            id::SWLS_LIMIT0 => self.drive.config.limit0 = self.pos_counts(value),
            id::SWLS_LIMIT1 => self.drive.config.limit1 = self.pos_counts(value),
            id::MT_NUM => {
                self.tasks.number = u8::try_from(value)
                    .ok()
                    .filter(|&n| usize::from(n) < TASKS)
                    .ok_or(out_of_range())?
            }
            id::MT_P => self.tasks.edit.position = value,
            id::MT_V if value >= 0 => self.tasks.edit.velocity = value,
            id::MT_ACC if value >= 0 => self.tasks.edit.acceleration = value,
            id::MT_DEC if value >= 0 => self.tasks.edit.deceleration = value,
            id::MT_CNTL if motion_tasks::valid_control(value) => self.tasks.edit.control = value,
            other => {
                let fits = match param.len {
                    1 | 2 | 4 if param.signed => {
                        let bits = u32::from(param.len).saturating_mul(8).saturating_sub(1);
                        ((1i64 << bits).saturating_neg()..(1i64 << bits)).contains(&value)
                    }
                    1 | 2 | 4 => (0..(1i64 << (8 * u32::from(param.len)))).contains(&value),
                    _ => true,
                };
                let slot = params::stored_index(other)
                    .filter(|_| fits)
                    .and_then(|i| self.stored.get_mut(i))
                    .ok_or(out_of_range())?;
                *slot = value;
            }
        }
        Ok(())
    }

    /// Starts motion task `n` (a position move); `Ok(false)` if the drive is not ready.
    /// An undefined task, or one whose profile the drive cannot run, sets DRV.MOTIONSTAT
    /// bit 10 (invalid motion task).
    pub fn start_task(&mut self, n: u8) -> Result<bool, StartError> {
        let result = self.try_start_task(n);
        if matches!(
            result,
            Err(StartError::Undefined) | Err(StartError::Drive(Refusal::Invalid))
        ) {
            self.drive.task_rejected();
        }
        result
    }

    fn try_start_task(&mut self, n: u8) -> Result<bool, StartError> {
        let task = self
            .tasks
            .table
            .get(usize::from(n))
            .copied()
            .flatten()
            .ok_or(StartError::Undefined)?;
        let v = self
            .check_profile(task.velocity, false)
            .map_err(|_| StartError::Undefined)?;
        let acc = self
            .check_profile(task.acceleration, true)
            .map_err(|_| StartError::Undefined)?;
        let dec = self
            .check_profile(task.deceleration, true)
            .map_err(|_| StartError::Undefined)?;
        let distance = self.pos_counts(task.position);
        let base = match task.control {
            cntl::RELATIVE_TARGET => self.drive.last_target(),
            cntl::RELATIVE_COMMAND => self.drive.commanded_position(),
            cntl::RELATIVE_FEEDBACK => self.drive.position(),
            _ => 0,
        };
        self.drive
            .start_task_move(n, base.saturating_add(distance), v, acc, dec)
            .map_err(StartError::Drive)
    }

    /// The task whose move runs now (response byte 1 and Status Word 1 bit 1).
    pub fn executing_task(&self) -> Option<u8> {
        self.drive.executing_task()
    }
}

impl Default for State {
    fn default() -> Self {
        Self::new()
    }
}
