//! [`StackHold`]: how long the link task waits for the network stack to take a frame from its
//! full receive queue before it reads the driver on.
//!
//! The queue between the link task and the stack is short (`RX_FRAMES`). While it is full the
//! link task stops reading the driver, so a burst waits in the driver for the stack instead
//! of being dropped. But the O->T data of the Class 1 connections waits there too, behind the
//! burst: under a flood the stack stays behind, and the connections would time out with
//! their data unread. So the link task waits at most [`STACK_HOLD_US`]; after that it reads
//! on, hands O->T data to the adapter and drops the stack's frames while the queue has no
//! room, until the stack has emptied its queue. A frame the stack takes does not earn it
//! another wait: under a flood it takes one well within each wait, and a wait renewed at each
//! would hold the driver to the stack's pace, the O->T data behind it, until the driver's own
//! buffer overflowed and dropped them.

use enip_stack::Instant;

/// Longest wait for the stack to take a frame from its full queue, in microseconds: well
/// within the shortest Class 1 watchdog a scanner asks for (4 x a 1 ms RPI).
pub(crate) const STACK_HOLD_US: u64 = 1_000;

/// Since when the stack has been behind: from when the link task found its queue full until
/// it finds it empty.
#[derive(Debug, Default)]
pub(crate) struct StackHold {
    /// `None`: the queue has not been full since it was last empty.
    since: Option<Instant>,
}

impl StackHold {
    /// Whether the driver is read at `at`, the stack's queue `full` or `empty` (or neither):
    /// yes while it has room, and once [`STACK_HOLD_US`] have passed since it was first found
    /// full after it was last empty.
    pub(crate) fn may_read(&mut self, full: bool, empty: bool, at: Instant) -> bool {
        if empty {
            self.since = None;
        }
        if !full {
            return true;
        }
        let since = *self.since.get_or_insert(at);
        at.as_micros().saturating_sub(since.as_micros()) >= STACK_HOLD_US
    }

    /// When the wait ends, while the queue is `full` and the end is still ahead of `at` (once
    /// it has passed, the driver's own wake-up serves).
    pub(crate) fn until(&self, full: bool, at: Instant) -> Option<Instant> {
        let since = self.since.filter(|_| full)?;
        let until = since.as_micros().saturating_add(STACK_HOLD_US);
        (until > at.as_micros()).then(|| Instant::from_micros(until))
    }
}

#[cfg(test)]
mod tests {
    use super::{StackHold, STACK_HOLD_US};
    use enip_stack::Instant;

    #[test]
    fn reads_while_the_queue_has_room() {
        let mut hold = StackHold::default();
        assert!(hold.may_read(false, true, Instant(5)));
        assert!(hold.may_read(false, false, Instant(6)));
        assert_eq!(hold.until(false, Instant(6)), None);
    }

    #[test]
    fn waits_for_the_stack_then_reads_on_until_it_has_caught_up() {
        let mut hold = StackHold::default();
        // Found full at 1 000: wait, and wake at the end of the wait.
        assert!(!hold.may_read(true, false, Instant(1_000)));
        assert_eq!(
            hold.until(true, Instant(1_000)),
            Some(Instant(1_000 + STACK_HOLD_US))
        );
        assert!(!hold.may_read(true, false, Instant(1_999)));
        // The stack stayed behind: read on, with no wake-up of the wait's own.
        assert!(hold.may_read(true, false, Instant(2_000)));
        assert_eq!(hold.until(true, Instant(2_000)), None);
        assert!(hold.may_read(true, false, Instant(9_000)));
        // It took a frame, and the queue filled again (a flood): no new wait.
        assert!(hold.may_read(false, false, Instant(9_100)));
        assert!(hold.may_read(true, false, Instant(9_200)));
        assert_eq!(hold.until(true, Instant(9_200)), None);
        // It emptied its queue: a full queue later waits anew.
        assert!(hold.may_read(false, true, Instant(9_300)));
        assert!(!hold.may_read(true, false, Instant(9_400)));
        assert_eq!(
            hold.until(true, Instant(9_400)),
            Some(Instant(9_400 + STACK_HOLD_US))
        );
    }

    #[test]
    fn a_burst_the_stack_keeps_up_with_waits_once() {
        let mut hold = StackHold::default();
        // Full at 0, the stack takes a frame at 400 and the burst fills the slot at 500.
        assert!(!hold.may_read(true, false, Instant(0)));
        assert!(hold.may_read(false, false, Instant(400)));
        assert!(!hold.may_read(true, false, Instant(500)));
        // The wait is the one begun at 0, not one begun at 500.
        assert_eq!(hold.until(true, Instant(500)), Some(Instant(STACK_HOLD_US)));
        assert!(hold.may_read(true, false, Instant(STACK_HOLD_US)));
    }
}
