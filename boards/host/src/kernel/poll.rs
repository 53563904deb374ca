//! The event loop's wait: a fixed set of file descriptors handed to `ppoll(2)` with a
//! timeout to the next deadline, and the clock deadlines are counted on.
//!
//! `ppoll` rather than epoll: the runtime watches at most [`MAX_FDS`] descriptors, so one
//! `ppoll` per wait costs no more than `epoll_wait` and needs no registration calls when the
//! interest changes (a TCP reply waiting for room, the listener closed while every session
//! is taken); its timeout is a `timespec`, so deadlines are kept to the microsecond.

use std::io;
use std::os::fd::RawFd;
use std::time::Duration;

use enip_stack::Instant;

/// Descriptors the loop watches: UDP 2222, 2 UDP 44818 sockets, the interface watch, the
/// listener and 3 TCP connections.
pub const MAX_FDS: usize = 8;

/// The monotonic clock (`CLOCK_MONOTONIC`, [`enip_host_runtime::now_micros`], the clock of
/// embassy-time on the host too), as the stack's microsecond [`Instant`].
#[derive(Debug, Clone, Copy)]
pub struct Clock;

impl Clock {
    /// The current instant.
    pub fn now(&self) -> Instant {
        Instant::from_micros(enip_host_runtime::now_micros())
    }
}

/// How long from `now` until `at` (zero if it has passed).
pub fn until(now: Instant, at: Instant) -> Duration {
    Duration::from_micros(at.as_micros().saturating_sub(now.as_micros()))
}

/// The descriptors the loop waits on, each at a fixed index, and after a wait what each is
/// ready for. An entry without a descriptor (-1) is ignored by `ppoll`.
pub struct PollSet {
    fds: [libc::pollfd; MAX_FDS],
}

impl PollSet {
    /// A set watching nothing.
    pub const fn new() -> Self {
        const NONE: libc::pollfd = libc::pollfd {
            fd: -1,
            events: 0,
            revents: 0,
        };
        PollSet {
            fds: [NONE; MAX_FDS],
        }
    }

    /// Watches `fd` at `index` for readability (and, with `write`, room to write); `None`
    /// watches nothing there.
    pub fn set(&mut self, index: usize, fd: Option<RawFd>, read: bool, write: bool) {
        let Some(entry) = self.fds.get_mut(index) else {
            return;
        };
        let mut events = 0;
        if read {
            events |= libc::POLLIN;
        }
        if write {
            events |= libc::POLLOUT;
        }
        *entry = libc::pollfd {
            fd: fd.unwrap_or(-1),
            events,
            revents: 0,
        };
    }

    /// Waits until a descriptor is ready or `timeout` passes (`None`: no timeout); a signal
    /// ends the wait early, as a timeout does.
    pub fn wait(&mut self, timeout: Option<Duration>) -> io::Result<()> {
        enip_host_runtime::ppoll(&mut self.fds, timeout).map(|_| ())
    }

    /// Whether the descriptor at `index` can be read (or has hung up or failed, which a read
    /// reports).
    pub fn readable(&self, index: usize) -> bool {
        self.revents(index) & (libc::POLLIN | libc::POLLHUP | libc::POLLERR) != 0
    }

    /// Whether the descriptor at `index` can be written (or has failed, which a write
    /// reports).
    pub fn writable(&self, index: usize) -> bool {
        self.revents(index) & (libc::POLLOUT | libc::POLLHUP | libc::POLLERR) != 0
    }

    fn revents(&self, index: usize) -> i16 {
        self.fds.get(index).map_or(0, |f| f.revents)
    }
}
