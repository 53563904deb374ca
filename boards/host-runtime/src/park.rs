//! [`Parker`]: what a loop does when it has nothing to poll. It wakes the alarms due; unless
//! that (or anything else) made work, it sleeps in `ppoll` on the watched descriptors and its
//! eventfd until the next alarm.

use std::io;
use std::time::Duration;

use crate::clock::now_micros;
use crate::wakeup::Wakeup;
use crate::{reactor, time_driver};

/// Polls in a row that may start at once, without reading the clock, when a task woke
/// another while they ran; the next wait wakes the alarms due first, so a task that keeps
/// waking itself cannot hold them back.
const QUICK_POLLS: u32 = 8;

/// The wait of one loop.
pub(crate) struct Parker<'a> {
    wakeup: &'a Wakeup,
    /// Polls started at once since the clock was last read.
    quick: u32,
}

impl<'a> Parker<'a> {
    /// The wait of the loop that `wakeup` wakes.
    pub(crate) fn new(wakeup: &'a Wakeup) -> Self {
        Parker { wakeup, quick: 0 }
    }

    /// Returns once work is pending; an error only if `ppoll` fails (not for a signal,
    /// which ends the wait early as a timeout does).
    pub(crate) fn park(&mut self) -> io::Result<()> {
        if self.quick < QUICK_POLLS && self.wakeup.take() {
            self.quick = self.quick.saturating_add(1);
            return Ok(());
        }
        self.quick = 0;
        let wakeup = self.wakeup;
        loop {
            let now = now_micros();
            let next = time_driver::expire(now);
            if !wakeup.sleep() {
                return Ok(());
            }
            let timeout =
                (next != u64::MAX).then(|| Duration::from_micros(next.saturating_sub(now)));
            let woken = reactor::wait(wakeup.fd(), timeout);
            // Awake before waking the ready descriptors' wakers: on this thread a wake then
            // writes no eventfd.
            wakeup.awake(matches!(woken, Ok(true)));
            woken?;
            reactor::wake_ready();
        }
    }
}

#[cfg(test)]
mod tests {
    use std::task::Poll;

    use embassy_time::{Duration, Instant, Timer};

    use crate::block_on;

    #[test]
    fn a_task_that_keeps_waking_itself_does_not_hold_back_the_alarms() {
        let start = Instant::now();
        let mut polls = 0u64;
        let spin = std::future::poll_fn(|cx| {
            polls += 1;
            cx.waker().wake_by_ref();
            Poll::<()>::Pending
        });
        let timer = Timer::after(Duration::from_millis(20));
        let first = block_on(async {
            match embassy_futures::select::select(spin, timer).await {
                embassy_futures::select::Either::First(()) => "spin",
                embassy_futures::select::Either::Second(()) => "timer",
            }
        })
        .expect("loop");
        assert_eq!(first, "timer");
        assert!(start.elapsed() >= Duration::from_millis(20));
        assert!(polls > 1);
    }
}
