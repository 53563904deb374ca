//! The event loop's wait: a fixed set of file descriptors handed to `ppoll(2)` with a
//! timeout to the next deadline, and the clock deadlines are counted on.
//!
//! `ppoll` rather than epoll: the runtime watches at most [`MAX_FDS`] descriptors, so one
//! `ppoll` per wait costs no more than `epoll_wait` and needs no registration calls when the
//! interest changes (a TCP reply waiting for room, the listener closed while every session
//! is taken); its timeout is a `timespec`, so deadlines are kept to the microsecond.

use std::io;
use std::os::fd::RawFd;
use std::time::{Duration, Instant as StdInstant};

use enip_stack::Instant;

/// Descriptors one wait can watch: listener, 3 TCP connections, 2 UDP 44818 sockets, UDP
/// 2222, the interface watch.
pub const MAX_FDS: usize = 8;

/// The monotonic clock, as the stack's microsecond [`Instant`] since the runtime started.
#[derive(Debug, Clone, Copy)]
pub struct Clock {
    start: StdInstant,
}

impl Clock {
    /// A clock whose zero is now.
    pub fn start() -> Self {
        Clock {
            start: StdInstant::now(),
        }
    }

    /// The current instant.
    pub fn now(&self) -> Instant {
        Instant::from_micros(self.start.elapsed().as_micros() as u64)
    }

    /// How long from now until `at` (zero if it has passed).
    pub fn until(&self, at: Instant) -> Duration {
        let at = self.start + Duration::from_micros(at.as_micros());
        at.saturating_duration_since(StdInstant::now())
    }
}

/// The descriptors of one wait and, after it, what each is ready for.
pub struct PollSet {
    fds: [libc::pollfd; MAX_FDS],
    len: usize,
}

/// Where a descriptor sits in the [`PollSet`] of this wait.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Slot(usize);

impl PollSet {
    /// An empty set.
    pub const fn new() -> Self {
        const NONE: libc::pollfd = libc::pollfd {
            fd: -1,
            events: 0,
            revents: 0,
        };
        PollSet {
            fds: [NONE; MAX_FDS],
            len: 0,
        }
    }

    /// Forgets every descriptor (before the next wait's are added).
    pub fn clear(&mut self) {
        self.len = 0;
    }

    /// Watches `fd` for readability (and, with `write`, room to write); `None` when the set
    /// is full, which the runtime's fixed descriptor count rules out.
    pub fn add(&mut self, fd: RawFd, read: bool, write: bool) -> Option<Slot> {
        let entry = self.fds.get_mut(self.len)?;
        let mut events = 0;
        if read {
            events |= libc::POLLIN;
        }
        if write {
            events |= libc::POLLOUT;
        }
        *entry = libc::pollfd {
            fd,
            events,
            revents: 0,
        };
        self.len += 1;
        Some(Slot(self.len - 1))
    }

    /// Waits until a descriptor is ready or `timeout` passes (`None`: no timeout); a signal
    /// ends the wait early, as a timeout does.
    pub fn wait(&mut self, timeout: Option<Duration>) -> io::Result<()> {
        let ts = timeout.map(|t| libc::timespec {
            tv_sec: libc::time_t::try_from(t.as_secs()).unwrap_or(libc::time_t::MAX),
            tv_nsec: t.subsec_nanos() as libc::c_long,
        });
        let ts_ptr = ts.as_ref().map_or(std::ptr::null(), |t| t as *const _);
        let fds = self.fds.get_mut(..self.len).unwrap_or_default();
        // SAFETY: `fds` is a valid, exclusively borrowed array of `fds.len()` pollfd entries
        // and `ts_ptr` is null or points to a timespec that outlives the call; a null signal
        // mask leaves the mask unchanged.
        let n = unsafe {
            libc::ppoll(
                fds.as_mut_ptr(),
                fds.len() as libc::nfds_t,
                ts_ptr,
                std::ptr::null(),
            )
        };
        if n < 0 {
            let e = io::Error::last_os_error();
            if e.kind() != io::ErrorKind::Interrupted {
                return Err(e);
            }
            fds.iter_mut().for_each(|f| f.revents = 0);
        }
        Ok(())
    }

    /// Whether the descriptor at `slot` can be read (or has hung up or failed, which a read
    /// reports).
    pub fn readable(&self, slot: Option<Slot>) -> bool {
        self.revents(slot) & (libc::POLLIN | libc::POLLHUP | libc::POLLERR) != 0
    }

    /// Whether the descriptor at `slot` can be written (or has failed, which a write reports).
    pub fn writable(&self, slot: Option<Slot>) -> bool {
        self.revents(slot) & (libc::POLLOUT | libc::POLLHUP | libc::POLLERR) != 0
    }

    fn revents(&self, slot: Option<Slot>) -> i16 {
        slot.and_then(|Slot(i)| self.fds.get(i))
            .map_or(0, |f| f.revents)
    }
}
