//! The link task's wake-up at its next deadline (a production, a watchdog expiry, an LLDPDU,
//! a probe): asked of a [`LinkAlarm`] at every pass that sleeps.
//!
//! [`TimeQueue`] asks embassy-time, whose queue keeps one expiry per task, shared with the
//! timers the driver arms on the same task. A board whose time driver keeps the link task
//! an alarm slot of its own (the emulated board's) skips the queue: no entry to find or
//! walk at each deadline, and a deadline no driver timer of the task can take with it.

use core::task::Waker;

/// Wakes the link task at a deadline.
pub trait LinkAlarm {
    /// Wakes `waker` at embassy-time tick `at`, or at once if it has passed. The task asks
    /// again at every pass that sleeps, with its earliest deadline: an alarm may keep only
    /// the last deadline asked (embassy-time keeps the earliest asked since it last fired).
    fn wake_at(&self, at: u64, waker: &Waker);

    /// True if a deadline asked stays asked until it fires or another is asked: nothing
    /// else can take it (a slot of its own). The task then asks only when its deadline
    /// changed.
    fn keeps_deadline(&self) -> bool {
        false
    }
}

/// embassy-time's timer queue: the link task's alarm on a board without one of its own.
#[derive(Debug, Clone, Copy, Default)]
pub struct TimeQueue;

impl LinkAlarm for TimeQueue {
    fn wake_at(&self, at: u64, waker: &Waker) {
        embassy_time_driver::schedule_wake(at, waker);
    }
}
