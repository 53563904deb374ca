//! Motion tasks: the table the control word's Start Block bit runs from (manual p.12: "a
//! stored motion task whose number is in byte 1", on its 0 -> 1 transition with Load/Start
//! 0), edited like the AKD does: MT.NUM selects a task (0-128, the drive's range), MT.P /
//! MT.V / MT.ACC / MT.DEC / MT.CNTL hold its values, MT.SET stores them as task MT.NUM and
//! MT.LOAD reads task MT.NUM back. The parameter instances are the project's (not in any
//! retrieved Appendix B).
//!
//! MT.CNTL bits 0-3 are the task type of the AKD parameter reference: 0 absolute, 1
//! relative to the command position (PL.CMD), 3 relative to the previous target, 7
//! relative to the feedback position (PL.FB); 5 and 8 (an external start position or
//! target) and the other bits (chaining, blending) are not modelled and refused.

use enip_stack::cip::{CipError, CipResult, General};

use super::device::Refusal;

/// Number of motion tasks (MT.NUM 0 to 128).
pub const TASKS: usize = 129;

/// MT.CNTL task types the simulation runs.
pub mod cntl {
    /// Absolute: the target is MT.P.
    pub const ABSOLUTE: i64 = 0;
    /// Relative to the command position: PL.CMD + MT.P.
    pub const RELATIVE_COMMAND: i64 = 1;
    /// Relative to the previous target: the last target + MT.P.
    pub const RELATIVE_TARGET: i64 = 3;
    /// Relative to the feedback position: PL.FB + MT.P.
    pub const RELATIVE_FEEDBACK: i64 = 7;
}

/// True if `value` is an MT.CNTL the simulation runs.
pub fn valid_control(value: i64) -> bool {
    matches!(
        value,
        cntl::ABSOLUTE | cntl::RELATIVE_COMMAND | cntl::RELATIVE_TARGET | cntl::RELATIVE_FEEDBACK
    )
}

/// One motion task, in network units (scaled when it starts).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Task {
    /// MT.P: target position (absolute) or distance (relative), position units.
    pub position: i64,
    /// MT.V: velocity, profile units.
    pub velocity: i64,
    /// MT.ACC: acceleration, profile units.
    pub acceleration: i64,
    /// MT.DEC: deceleration, profile units.
    pub deceleration: i64,
    /// MT.CNTL: the task type.
    pub control: i64,
}

/// The table and the task being edited.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MotionTasks {
    /// The stored tasks (`None`: not defined).
    pub table: [Option<Task>; TASKS],
    /// MT.NUM.
    pub number: u8,
    /// The MT.P ... MT.CNTL values being edited.
    pub edit: Task,
}

impl Default for MotionTasks {
    fn default() -> Self {
        MotionTasks {
            table: [None; TASKS],
            number: 0,
            edit: Task::default(),
        }
    }
}

impl MotionTasks {
    /// MT.SET: stores the edited values as task MT.NUM. A task that cannot move (MT.V,
    /// MT.ACC or MT.DEC 0: the power-up values) is refused with 0x09 and nothing changes.
    pub fn set(&mut self) -> CipResult {
        let e = &self.edit;
        if e.velocity <= 0 || e.acceleration <= 0 || e.deceleration <= 0 {
            return Err(CipError::new(General::InvalidAttributeValue));
        }
        if let Some(slot) = self.table.get_mut(usize::from(self.number)) {
            *slot = Some(self.edit);
        }
        Ok(())
    }
    /// MT.LOAD: reads task MT.NUM into the edited values (an undefined task reads zeros).
    pub fn load(&mut self) {
        self.edit = self
            .table
            .get(usize::from(self.number))
            .copied()
            .flatten()
            .unwrap_or_default();
    }
}

/// Why a task did not start.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StartError {
    /// No such task, or an invalid profile in it.
    Undefined,
    /// The drive refused (not homed: it faulted).
    Drive(Refusal),
}
