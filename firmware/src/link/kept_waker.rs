//! [`KeptWaker`]: the link task's waker, registered once and kept across wake-ups.

use core::cell::RefCell;
use core::task::Waker;

/// The waker of the one task that waits for something (the link task; a board's alarm slot
/// for it keeps one too). Unlike embassy's
/// `WakerRegistration`, waking does not consume it: the task registers once and is woken
/// every time after, so a wake-up of the link task pays no registration.
#[derive(Default)]
pub struct KeptWaker(RefCell<Option<Waker>>);

impl KeptWaker {
    /// No waker yet.
    pub const fn new() -> Self {
        KeptWaker(RefCell::new(None))
    }

    /// Keeps `waker` (instead of any other) for the wake-ups to come.
    pub fn register(&self, waker: &Waker) {
        let mut kept = self.0.borrow_mut();
        if !kept.as_ref().is_some_and(|w| w.will_wake(waker)) {
            *kept = Some(waker.clone());
        }
    }

    /// Wakes the waker kept, if any, and keeps it.
    pub fn wake(&self) {
        if let Some(waker) = self.0.borrow().as_ref() {
            waker.wake_by_ref();
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::KeptWaker;
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Arc;
    use std::task::{Wake, Waker};

    struct Count(AtomicUsize);

    impl Wake for Count {
        fn wake(self: Arc<Self>) {
            self.0.fetch_add(1, Ordering::SeqCst);
        }
    }

    #[test]
    fn wakes_the_kept_waker_every_time_until_another_registers() {
        let (a, b) = (
            Arc::new(Count(AtomicUsize::new(0))),
            Arc::new(Count(AtomicUsize::new(0))),
        );
        let kept = KeptWaker::new();
        kept.wake(); // none yet: nothing happens
        kept.register(&Waker::from(a.clone()));
        kept.wake();
        kept.wake();
        assert_eq!(a.0.load(Ordering::SeqCst), 2);
        kept.register(&Waker::from(b.clone()));
        kept.wake();
        assert_eq!(
            (a.0.load(Ordering::SeqCst), b.0.load(Ordering::SeqCst)),
            (2, 1)
        );
    }
}
