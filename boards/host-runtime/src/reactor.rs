//! Readable file descriptors: a future asks to be woken when a descriptor can be read
//! ([`Readable::poll_readable`]); the loop's wait watches the descriptors asked for in one
//! `ppoll` ([`wait`]) and wakes the wakers of those found ready ([`wake_ready`]).
//! Level-triggered and per thread: a descriptor is watched by the loop of the thread that
//! made its [`Readable`], and only while a waker waits for it, so nothing is registered or
//! removed per wait, and a poll touches only its own descriptor's state.

use std::cell::{Cell, RefCell};
use std::io;
use std::os::fd::RawFd;
use std::rc::Rc;
use std::task::{Context, Poll, Waker};
use std::time::Duration;

/// A descriptor watched for reading by the loop of the thread that made this (which is
/// why it is not `Send`); the owner of the descriptor keeps it open while this lives.
#[derive(Debug)]
pub struct Readable {
    source: Rc<Source>,
}

impl Readable {
    /// Watches `fd` on this thread's loop.
    pub fn new(fd: RawFd) -> Self {
        let source = Rc::new(Source {
            fd,
            ready: Cell::new(false),
            waker: RefCell::new(None),
        });
        REACTOR.with_borrow_mut(|r| r.sources.push(Rc::clone(&source)));
        Readable { source }
    }

    /// Ready when the loop's last wait found the descriptor readable (or failed: the read
    /// reports it), once per report, so a read follows only a report; else the waker is
    /// kept and woken by the wait that finds it readable.
    pub fn poll_readable(&self, cx: &mut Context<'_>) -> Poll<()> {
        if self.source.ready.replace(false) {
            return Poll::Ready(());
        }
        let mut waker = self.source.waker.borrow_mut();
        match &mut *waker {
            Some(w) if w.will_wake(cx.waker()) => {}
            w => *w = Some(cx.waker().clone()),
        }
        Poll::Pending
    }
}

impl Drop for Readable {
    fn drop(&mut self) {
        // On a thread whose state is gone (it is exiting) there is nothing to remove.
        let _ = REACTOR.try_with(|r| {
            if let Ok(mut r) = r.try_borrow_mut() {
                r.sources.retain(|s| !Rc::ptr_eq(s, &self.source));
            }
        });
    }
}

/// A watched descriptor.
#[derive(Debug)]
struct Source {
    fd: RawFd,
    /// A wait found it readable and no poll has taken that yet.
    ready: Cell<bool>,
    /// Who waits for it to be readable (`None`: not watched).
    waker: RefCell<Option<Waker>>,
}

impl Source {
    fn watched(&self) -> bool {
        self.waker.borrow().is_some()
    }
}

/// A thread's watched descriptors, and the `ppoll` array reused by every wait.
struct Reactor {
    sources: Vec<Rc<Source>>,
    fds: Vec<libc::pollfd>,
}

thread_local! {
    static REACTOR: RefCell<Reactor> = const {
        RefCell::new(Reactor {
            sources: Vec::new(),
            fds: Vec::new(),
        })
    };
}

/// Waits until `wakeup` or a descriptor a waker waits for is readable, or `timeout` passes
/// (`None`: no timeout); a signal ends the wait early, as a timeout does. Returns whether
/// `wakeup` is readable; [`wake_ready`] then wakes the wakers of the descriptors found ready.
pub(crate) fn wait(wakeup: RawFd, timeout: Option<Duration>) -> io::Result<bool> {
    REACTOR.with_borrow_mut(|r| r.wait(wakeup, timeout))
}

/// Wakes the wakers of the descriptors the last [`wait`] found ready.
pub(crate) fn wake_ready() {
    // Woken outside the borrow: a waker may make or drop a `Readable` (an executor's does
    // not).
    while let Some(waker) = REACTOR.with_borrow(Reactor::take_woken) {
        waker.wake();
    }
}

impl Reactor {
    fn wait(&mut self, wakeup: RawFd, timeout: Option<Duration>) -> io::Result<bool> {
        let watch = |fd| libc::pollfd {
            fd,
            events: libc::POLLIN,
            revents: 0,
        };
        self.fds.clear();
        self.fds.push(watch(wakeup));
        let watched = self.sources.iter().filter(|s| s.watched());
        self.fds.extend(watched.map(|s| watch(s.fd)));
        if crate::ppoll(&mut self.fds, timeout)? == 0 {
            return Ok(false);
        }
        let mut fds = self.fds.iter();
        let woken = fds.next().is_some_and(|p| p.revents != 0);
        let watched = self.sources.iter().filter(|s| s.watched());
        for (source, p) in watched.zip(fds) {
            if p.revents != 0 {
                source.ready.set(true);
            }
        }
        Ok(woken)
    }

    /// The waker of a descriptor found ready, no longer watched until polled again.
    fn take_woken(&self) -> Option<Waker> {
        self.sources
            .iter()
            .filter(|s| s.ready.get())
            .find_map(|s| s.waker.borrow_mut().take())
    }
}

#[cfg(test)]
mod tests {
    use std::io::Write;
    use std::os::fd::AsRawFd;
    use std::os::unix::net::UnixStream;
    use std::task::{Context, Poll, Waker};
    use std::time::{Duration, Instant};

    use super::Readable;
    use crate::block_on;

    #[test]
    fn a_descriptor_is_ready_once_per_wait_that_finds_it_readable() {
        let (reader, mut writer) = UnixStream::pair().expect("pair");
        let readable = Readable::new(reader.as_raw_fd());
        let start = Instant::now();
        let writer_thread = std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(20));
            writer.write_all(b"x").expect("write");
            writer
        });
        block_on(std::future::poll_fn(|cx| readable.poll_readable(cx))).expect("loop");
        assert!(start.elapsed() >= Duration::from_millis(20));
        let mut cx = Context::from_waker(Waker::noop());
        // The report is taken; the byte, still unread, is reported by the next wait.
        assert_eq!(readable.poll_readable(&mut cx), Poll::Pending);
        block_on(std::future::poll_fn(|cx| readable.poll_readable(cx))).expect("loop");
        drop(writer_thread.join().expect("writer"));
    }
}
