//! Motion tasks: the table the control word's Start Block bit runs from (manual p.12: "a
//! stored motion task whose number is in byte 1", on its 0 -> 1 transition with Load/Start
//! 0), edited like the AKD does: MT.NUM selects a task, MT.P / MT.V / MT.ACC / MT.DEC /
//! MT.CNTL hold its values, MT.SET stores them as task MT.NUM and MT.LOAD reads task MT.NUM
//! back. The parameter instances are the project's (not in any retrieved Appendix B).

use super::device::Refusal;

/// Number of motion tasks (0 to 15).
pub const TASKS: usize = 16;
/// MT.CNTL bit 0: the position is relative to the last target.
pub const CNTL_RELATIVE: i64 = 1;

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
    /// MT.CNTL: bit 0 relative.
    pub control: i64,
}

/// The table, the task being edited and the task running.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct MotionTasks {
    /// The stored tasks (`None`: not defined).
    pub table: [Option<Task>; TASKS],
    /// MT.NUM.
    pub number: u8,
    /// The MT.P ... MT.CNTL values being edited.
    pub edit: Task,
    /// The task started last, while its move runs.
    pub running: Option<u8>,
}

impl MotionTasks {
    /// MT.SET: stores the edited values as task MT.NUM.
    pub fn set(&mut self) {
        if let Some(slot) = self.table.get_mut(usize::from(self.number)) {
            *slot = Some(self.edit);
        }
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
