//! Feeding a hardware watchdog only while the firmware makes progress: the link task's future
//! runs inside [`beating`], which counts its polls in a [`Heartbeat`], and [`keep_fed`], a
//! task of its own on the same executor, feeds the watchdog each period in which the link
//! task was polled, then wakes it so an idle link task is polled again in the next period.
//! A stuck executor (a task that never yields, a fault loop) runs neither; a link task that
//! no longer returns to the executor leaves its count still: either way the watchdog is not
//! fed and resets the board. Nothing here runs in an interrupt.

use core::cell::{Cell, RefCell};
use core::future::{poll_fn, Future};
use core::pin::Pin;

use embassy_sync::waitqueue::WakerRegistration;
use embassy_time::{Duration, Timer};

/// The polls of the watched task, and its waker.
pub struct Heartbeat {
    polls: Cell<u32>,
    waker: RefCell<WakerRegistration>,
}

impl Heartbeat {
    /// No poll seen yet.
    pub const fn new() -> Self {
        Heartbeat {
            polls: Cell::new(0),
            waker: RefCell::new(WakerRegistration::new()),
        }
    }
}

impl Default for Heartbeat {
    fn default() -> Self {
        Self::new()
    }
}

/// Runs `task`, counting each of its polls in `heart`. Pass the task pinned where it is
/// (`beating(heart, pin!(future))`), so that its future is not stored twice.
pub async fn beating<F: Future + Unpin>(heart: &Heartbeat, mut task: F) -> F::Output {
    poll_fn(|cx| {
        heart.polls.set(heart.polls.get().wrapping_add(1));
        heart.waker.borrow_mut().register(cx.waker());
        Pin::new(&mut task).poll(cx)
    })
    .await
}

/// Every `period`: calls `feed` if the task in `heart` was polled since the last check, then
/// wakes that task. Spawn it on the executor that runs the watched task; never returns.
pub async fn keep_fed(heart: &Heartbeat, period: Duration, mut feed: impl FnMut()) -> ! {
    let mut seen = heart.polls.get();
    loop {
        Timer::after(period).await;
        let now = heart.polls.get();
        if now != seen {
            feed();
        }
        seen = now;
        heart.waker.borrow_mut().wake();
    }
}
