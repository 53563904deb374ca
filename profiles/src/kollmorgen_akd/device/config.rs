//! The simulated drive's vocabulary: its constants, operating modes, faults and refusals,
//! DRV.MOTIONSTAT bits, and the settings it keeps as parameters.

/// Control ticks per second.
pub const TICKS_PER_S: i64 = 1_000;
/// Feedback counts per revolution (EIP.POSUNIT: "actual position feedback counts (at 32
/// bits per revolution)").
pub const COUNTS_PER_REV: i64 = 1 << 32;
/// Velocity (counts/s) one milliamp holds against the simulated load's viscous friction:
/// 100 mA per revolution per second, so the velocity limit needs 10 A.
pub const TORQUE_V: i64 = COUNTS_PER_REV / 100;
/// Inverse of the torque-mode time constant (1/s): the motor reaches a new torque's
/// velocity with a 20 ms time constant.
pub const TORQUE_RATE: i64 = 50;
/// Acceleration (counts/s²) one milliamp gives the simulated motor's inertia: 0.5 rev/s²
/// per mA (2 A for DRV.DECSTOP's 1000 rev/s²).
pub const TORQUE_A: i64 = TORQUE_V * TORQUE_RATE;
/// Velocity limit (counts/s): 100 revolutions per second.
pub const MAX_VELOCITY: i64 = 100 * COUNTS_PER_REV;
/// Torque command limit and reported torque limit, mA (the simulated drive's peak current,
/// 20 A: a drive never reports more current than its power stage delivers).
pub const MAX_TORQUE_MA: i32 = 20_000;
/// Ticks a home move of mode 0 takes (MOTIONSTAT bit 3 "homing active" meanwhile).
pub const HOME_TICKS: u32 = 20;

/// DRV.MOTIONSTAT bits (AKD parameter reference).
pub mod motionstat {
    /// Motion task active.
    pub const TASK_ACTIVE: u32 = 1 << 0;
    /// Home position found.
    pub const HOME_FOUND: u32 = 1 << 1;
    /// Home routine finished.
    pub const HOME_FINISHED: u32 = 1 << 2;
    /// Homing active.
    pub const HOMING: u32 = 1 << 3;
    /// Emergency stop procedure in progress.
    pub const ESTOP: u32 = 1 << 7;
    /// A motion task could not be activated (invalid motion task).
    pub const TASK_INVALID: u32 = 1 << 10;
    /// Motion task completed: trajectory finished and inside MT.TPOSWND.
    pub const TASK_COMPLETED: u32 = 1 << 11;
    /// Motion task target velocity reached.
    pub const VELOCITY_REACHED: u32 = 1 << 12;
    /// Motion task fault.
    pub const TASK_FAULT: u32 = 1 << 13;
    /// Target position crossed: a stop interrupted the move and its ramp ran past the
    /// target (the overshoot flag; never set by a move that ends normally).
    pub const TARGET_CROSSED: u32 = 1 << 14;
    /// Target position reached: inside MT.TPOSWND, without waiting for the trajectory to
    /// end (bit 11 waits).
    pub const TARGET_REACHED: u32 = 1 << 15;
}

/// SWLS.EN bit 0: the negative software limit (SWLS.LIMIT0) is on.
pub const SWLS_NEGATIVE: u8 = 1;
/// SWLS.EN bit 1: the positive software limit (SWLS.LIMIT1) is on.
pub const SWLS_POSITIVE: u8 = 2;

/// Operating mode (Position Controller attribute 3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// 0: position mode (the default).
    Position,
    /// 1: velocity mode.
    Velocity,
    /// 2: torque mode.
    Torque,
}

impl Mode {
    /// The mode of attribute value `code`.
    pub const fn from_code(code: u8) -> Option<Mode> {
        match code {
            0 => Some(Mode::Position),
            1 => Some(Mode::Velocity),
            2 => Some(Mode::Torque),
            _ => None,
        }
    }
    /// The attribute value of the mode.
    pub const fn code(self) -> u8 {
        match self {
            Mode::Position => 0,
            Mode::Velocity => 1,
            Mode::Torque => 2,
        }
    }
}

/// A drive fault (Status Word 1 bit 3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fault {
    /// A position-mode move was begun before the drive was homed (manual p.11).
    NotHomed,
}

/// Why the drive refused to start something.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refusal {
    /// A position-mode move before homing: the drive faulted.
    NotHomed,
    /// The drive is disabled, stopping or faulted.
    NotReady,
    /// The motion's data cannot make a motion (a velocity of 0 for a move): DRV.MOTIONSTAT
    /// bit 10, "invalid motion task".
    Invalid,
}

/// Settings the drive keeps as parameters (all in counts, counts/s or counts/s²).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// Operating mode.
    pub mode: Mode,
    /// MT.TPOSWND: the in-position window.
    pub window: i64,
    /// SWLS.EN: bit 0 enables the negative limit (SWLS.LIMIT0), bit 1 the positive one
    /// (SWLS.LIMIT1).
    pub swls: u8,
    /// SWLS.LIMIT0: the negative software limit.
    pub limit0: i64,
    /// SWLS.LIMIT1: the positive software limit.
    pub limit1: i64,
    /// DRV.DECSTOP: deceleration of a hard stop and of a software-limit stop.
    pub decstop: i64,
    /// HOME.P: the position homing sets.
    pub home_position: i64,
    /// HOME.MODE.
    pub home_mode: i16,
}

impl Config {
    /// Power-up settings: position mode, a half-revolution window (MT.TPOSWND's default
    /// 0.5 rev), limits off at
    /// +-1000 revolutions, hard stop at 1000 rev/s².
    pub const fn new() -> Self {
        Config {
            mode: Mode::Position,
            window: COUNTS_PER_REV / 2,
            swls: 0,
            limit0: -1_000 * COUNTS_PER_REV,
            limit1: 1_000 * COUNTS_PER_REV,
            decstop: 1_000 * COUNTS_PER_REV,
            home_position: 0,
            home_mode: 0,
        }
    }
}

impl Default for Config {
    fn default() -> Self {
        Self::new()
    }
}
