//! [`run`]: embassy's raw executor on the calling thread, parked in `ppoll` while no task is
//! ready.

use std::convert::Infallible;
use std::io;

use embassy_executor::{raw, Spawner};

use crate::park::Parker;
use crate::wakeup::Wakeup;

/// Runs an executor on this thread for ever: `init` spawns its first tasks; then it polls
/// the tasks woken and waits for the next wake (an alarm of this thread, a descriptor its
/// tasks watch with [`crate::Readable`], a wake from any thread). Returns only an error: no
/// eventfd for the loop, or a failed `ppoll`.
pub fn run(init: impl FnOnce(Spawner)) -> io::Result<Infallible> {
    let wakeup: &'static Wakeup = Box::leak(Box::new(Wakeup::new()?));
    let context = std::ptr::from_ref(wakeup).cast_mut().cast::<()>();
    let executor: &'static raw::Executor = Box::leak(Box::new(raw::Executor::new(context)));
    init(executor.spawner());
    let mut parker = Parker::new(wakeup);
    loop {
        // SAFETY: only this loop polls the executor, never from the pender (which only sets
        // the flag the parker reads), so never re-entrantly.
        unsafe { executor.poll() };
        parker.park()?;
    }
}

#[cfg(test)]
mod tests {
    use std::time::Instant as StdInstant;

    use embassy_time::{Duration, Timer};

    /// Sleeps `ms`, then logs `id`.
    #[embassy_executor::task(pool_size = 2)]
    async fn sleeper(id: u32, ms: u64, log: &'static std::sync::Mutex<Vec<u32>>) {
        Timer::after(Duration::from_millis(ms)).await;
        log.lock().expect("log").push(id);
    }

    #[test]
    fn tasks_sleep_on_the_alarms_and_run_in_deadline_order() {
        let log: &'static std::sync::Mutex<Vec<u32>> = Box::leak(Box::default());
        let start = StdInstant::now();
        // The executor never returns: it runs on a thread of its own, left running.
        std::thread::spawn(move || {
            super::run(|spawner| {
                spawner.spawn(sleeper(1, 40, log).expect("task"));
                spawner.spawn(sleeper(2, 20, log).expect("task"));
            })
        });
        while log.lock().expect("log").len() < 2 {
            assert!(start.elapsed().as_secs() < 10, "tasks did not finish");
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        assert_eq!(*log.lock().expect("log"), [2, 1]);
        assert!(start.elapsed() >= std::time::Duration::from_millis(40));
    }
}
