//! The embassy-time driver: `now` is [`now_micros`]; an alarm goes into a list of the thread
//! that schedules it, which that thread's loop expires before it waits ([`expire`]), so no
//! lock is taken and no timer thread runs.

use std::cell::RefCell;
use std::task::Waker;

use embassy_time_driver::Driver;

use crate::clock::now_micros;

/// The driver; its state is per thread ([`ALARMS`]).
struct HostTime;

embassy_time_driver::time_driver_impl!(static DRIVER: HostTime = HostTime);

impl Driver for HostTime {
    fn now(&self) -> u64 {
        now_micros()
    }

    fn schedule_wake(&self, at: u64, waker: &Waker) {
        ALARMS.with_borrow_mut(|alarms| alarms.schedule(at, waker));
    }
}

thread_local! {
    /// The alarms scheduled on this thread.
    static ALARMS: RefCell<Alarms> = const { RefCell::new(Alarms::new()) };
}

/// One waker to wake at `at` (microseconds).
struct Alarm {
    at: u64,
    waker: Waker,
}

/// A thread's alarms: at most one per waker (the earliest asked for), and the earliest of
/// all, so that a wait with nothing due looks at one number.
struct Alarms {
    list: Vec<Alarm>,
    /// The earliest `at` in `list` (`u64::MAX`: none).
    earliest: u64,
}

impl Alarms {
    const fn new() -> Self {
        Alarms {
            list: Vec::new(),
            earliest: u64::MAX,
        }
    }

    /// Wakes `waker` at `at`, or earlier if it is already to be woken earlier (it then asks
    /// again when polled).
    fn schedule(&mut self, at: u64, waker: &Waker) {
        match self.list.iter_mut().find(|a| a.waker.will_wake(waker)) {
            Some(alarm) => alarm.at = alarm.at.min(at),
            None => self.list.push(Alarm {
                at,
                waker: waker.clone(),
            }),
        }
        self.earliest = self.earliest.min(at);
    }

    /// Removes an alarm due at `now` and gives its waker; `None` once none is due.
    fn take_due(&mut self, now: u64) -> Option<Waker> {
        if now < self.earliest {
            return None;
        }
        if let Some(i) = self.list.iter().position(|a| a.at <= now) {
            return Some(self.list.swap_remove(i).waker);
        }
        self.earliest = self.list.iter().map(|a| a.at).min().unwrap_or(u64::MAX);
        None
    }
}

/// Wakes every alarm of this thread due at `now`; returns when the next is due (`u64::MAX`:
/// none).
pub(crate) fn expire(now: u64) -> u64 {
    // Each waker is woken outside the borrow: waking may schedule again.
    while let Some(waker) = ALARMS.with_borrow_mut(|alarms| alarms.take_due(now)) {
        waker.wake();
    }
    ALARMS.with_borrow(|alarms| alarms.earliest)
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Arc;
    use std::task::Wake;

    use super::*;

    struct Count(AtomicUsize);

    impl Wake for Count {
        fn wake(self: Arc<Self>) {
            self.0.fetch_add(1, Ordering::SeqCst);
        }
    }

    fn counter() -> (Arc<Count>, Waker) {
        let count = Arc::new(Count(AtomicUsize::new(0)));
        (count.clone(), Waker::from(count))
    }

    #[test]
    fn one_alarm_per_waker_at_the_earliest_time_asked() {
        let (a, wa) = counter();
        let (b, wb) = counter();
        let mut alarms = Alarms::new();
        alarms.schedule(300, &wa);
        alarms.schedule(100, &wa);
        alarms.schedule(200, &wa);
        alarms.schedule(150, &wb);
        assert_eq!(alarms.list.len(), 2);
        assert_eq!(alarms.earliest, 100);
        assert!(alarms.take_due(99).is_none());
        alarms.take_due(100).expect("due").wake();
        assert_eq!(a.0.load(Ordering::SeqCst), 1);
        assert!(alarms.take_due(100).is_none());
        assert_eq!(alarms.earliest, 150);
        alarms.take_due(1_000).expect("due").wake();
        assert_eq!(b.0.load(Ordering::SeqCst), 1);
        assert!(alarms.take_due(1_000).is_none());
        assert_eq!(alarms.earliest, u64::MAX);
    }

    #[test]
    fn expire_wakes_what_is_due_on_this_thread_only() {
        let (a, wa) = counter();
        let (b, wb) = counter();
        let now = now_micros();
        embassy_time_driver::schedule_wake(now, &wa);
        embassy_time_driver::schedule_wake(now + 60_000_000, &wb);
        std::thread::spawn(move || assert_eq!(expire(u64::MAX - 1), u64::MAX))
            .join()
            .expect("other thread");
        assert_eq!(expire(now), now + 60_000_000);
        assert_eq!(a.0.load(Ordering::SeqCst), 1);
        assert_eq!(b.0.load(Ordering::SeqCst), 0);
    }
}
