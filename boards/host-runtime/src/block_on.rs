//! [`block_on`]: one future run to completion on the calling thread, with the executor's
//! wait between polls, for programs and tests that have no tasks.

use std::future::Future;
use std::io;
use std::pin::pin;
use std::sync::Arc;
use std::task::{Context, Poll, Waker};

use crate::park::Parker;
use crate::wakeup::Wakeup;

/// Polls `future` until it completes, waiting between polls as [`crate::run`] does (this
/// thread's alarms, the descriptors it watches, wakes from any thread). An error only if
/// no eventfd can be made or `ppoll` fails.
pub fn block_on<F: Future>(future: F) -> io::Result<F::Output> {
    let wakeup = Arc::new(Wakeup::new()?);
    let waker = Waker::from(Arc::clone(&wakeup));
    let mut cx = Context::from_waker(&waker);
    let mut future = pin!(future);
    let mut parker = Parker::new(&wakeup);
    loop {
        if let Poll::Ready(out) = future.as_mut().poll(&mut cx) {
            return Ok(out);
        }
        parker.park()?;
    }
}

#[cfg(test)]
mod tests {
    use std::task::{Poll, Waker};
    use std::time::Instant as StdInstant;

    use embassy_time::{Duration, Instant, Timer};

    use super::block_on;

    #[test]
    fn a_timer_fires_at_its_deadline_and_not_before() {
        let start = Instant::now();
        let woke = block_on(async {
            Timer::after(Duration::from_millis(30)).await;
            Instant::now()
        })
        .expect("loop");
        let slept = woke.duration_since(start);
        assert!(slept >= Duration::from_millis(30), "{slept:?}");
        assert!(slept < Duration::from_secs(5), "{slept:?}");
    }

    #[test]
    fn a_wake_from_another_thread_ends_the_wait() {
        let start = StdInstant::now();
        let (tx, rx) = std::sync::mpsc::channel::<Waker>();
        let waker_thread = std::thread::spawn(move || {
            let waker = rx.recv().expect("waker");
            std::thread::sleep(std::time::Duration::from_millis(20));
            waker.wake();
        });
        let mut sent = Some(tx);
        // Pending once (handing its waker to the other thread), ready when polled again.
        block_on(std::future::poll_fn(|cx| match sent.take() {
            Some(tx) => {
                tx.send(cx.waker().clone()).expect("send");
                Poll::Pending
            }
            None => Poll::Ready(()),
        }))
        .expect("loop");
        waker_thread.join().expect("waker thread");
        let waited = start.elapsed();
        assert!(waited >= std::time::Duration::from_millis(20), "{waited:?}");
        assert!(waited < std::time::Duration::from_secs(5), "{waited:?}");
    }
}
