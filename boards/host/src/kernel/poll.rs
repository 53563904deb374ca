//! The event loop's wait: one `epoll` instance holding every socket of every device, each
//! registered with a key naming its device and its place there, waited on with
//! `epoll_pwait2(2)` until a socket is ready or the next deadline; and the clock deadlines
//! are counted on.
//!
//! `epoll` rather than `ppoll`: a fleet holds 8 descriptors per device (2 048 at 256
//! devices), and a wait must cost what became ready, not what is watched: `ppoll` copies and
//! scans the whole set at every wake-up, `epoll` hands back only the ready ones with their
//! key. Its interest is changed only when a TCP session's changes (a reply waiting for
//! room), and `epoll_pwait2` takes a `timespec`, so deadlines are kept to the microsecond
//! (where it is missing, before Linux 5.11 or under valgrind, `epoll_wait` to the
//! millisecond, rounded up).

use std::io;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd, RawFd};
use std::time::Duration;

use enip_stack::Instant;

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

/// One ready descriptor, as a wait reports it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Ready {
    /// The key it was registered with.
    pub key: u64,
    /// It can be read (or has hung up or failed, which a read reports).
    pub readable: bool,
    /// It can be written (or has failed, which a write reports).
    pub writable: bool,
}

/// An `epoll` instance and the buffer its waits fill.
pub struct Epoll {
    fd: OwnedFd,
    events: Vec<libc::epoll_event>,
    /// `epoll_pwait2` is missing (kernels before 5.11, valgrind): `epoll_wait` with the
    /// timeout rounded up to the millisecond instead.
    whole_ms: bool,
}

impl Epoll {
    /// An instance reporting up to `batch` ready descriptors per wait.
    pub fn new(batch: usize) -> io::Result<Self> {
        // SAFETY: plain epoll_create1(2) call; the result is checked before use.
        let raw = unsafe { libc::epoll_create1(libc::EPOLL_CLOEXEC) };
        if raw < 0 {
            return Err(io::Error::last_os_error());
        }
        // SAFETY: `raw` is a new descriptor nothing else owns.
        let fd = unsafe { OwnedFd::from_raw_fd(raw) };
        let empty = libc::epoll_event { events: 0, u64: 0 };
        Ok(Epoll {
            fd,
            events: vec![empty; batch.max(1)],
            whole_ms: false,
        })
    }

    /// Watches `fd` under `key` for readability (and, with `write`, room to write), whether
    /// it is registered already or not. A descriptor leaves the set by itself when closed.
    pub fn watch(&self, fd: RawFd, key: u64, read: bool, write: bool) -> io::Result<()> {
        let mut events = 0;
        if read {
            events |= libc::EPOLLIN;
        }
        if write {
            events |= libc::EPOLLOUT;
        }
        let mut event = libc::epoll_event {
            events: events as u32,
            u64: key,
        };
        // SAFETY: `event` is a valid epoll_event that outlives the call.
        let ctl = |op, event: &mut libc::epoll_event| unsafe {
            libc::epoll_ctl(self.fd.as_raw_fd(), op, fd, event)
        };
        if ctl(libc::EPOLL_CTL_MOD, &mut event) == 0 {
            return Ok(());
        }
        let e = io::Error::last_os_error();
        if e.raw_os_error() != Some(libc::ENOENT) {
            return Err(e);
        }
        if ctl(libc::EPOLL_CTL_ADD, &mut event) == 0 {
            Ok(())
        } else {
            Err(io::Error::last_os_error())
        }
    }

    /// Waits until a descriptor is ready or `timeout` passes (`None`: no timeout), then
    /// hands each ready one to `ready`; a signal ends the wait early, as a timeout does.
    pub fn wait(
        &mut self,
        timeout: Option<Duration>,
        mut ready: impl FnMut(Ready),
    ) -> io::Result<()> {
        let n = self.wait_raw(timeout);
        let n = match usize::try_from(n) {
            Ok(n) => n,
            Err(_) => {
                let e = io::Error::last_os_error();
                if e.raw_os_error() == Some(libc::ENOSYS) && !self.whole_ms {
                    self.whole_ms = true;
                    return self.wait(timeout, ready);
                }
                return if e.kind() == io::ErrorKind::Interrupted {
                    Ok(())
                } else {
                    Err(e)
                };
            }
        };
        let failed = (libc::EPOLLHUP | libc::EPOLLERR) as u32;
        for e in self.events.iter().take(n) {
            ready(Ready {
                key: e.u64,
                readable: e.events & (libc::EPOLLIN as u32 | failed) != 0,
                writable: e.events & (libc::EPOLLOUT as u32 | failed) != 0,
            });
        }
        Ok(())
    }

    /// One wait into `events`: the count ready, or -1 with `errno` set.
    fn wait_raw(&mut self, timeout: Option<Duration>) -> libc::c_int {
        let max = libc::c_int::try_from(self.events.len()).unwrap_or(libc::c_int::MAX);
        if self.whole_ms {
            // Rounded up: a deadline is never woken for early.
            let ms = timeout.map_or(-1, |t| {
                let ms = t.as_nanos().div_ceil(1_000_000);
                libc::c_int::try_from(ms).unwrap_or(libc::c_int::MAX)
            });
            // SAFETY: `events` holds `max` writable entries.
            return unsafe {
                libc::epoll_wait(self.fd.as_raw_fd(), self.events.as_mut_ptr(), max, ms)
            };
        }
        let ts = timeout.map(|t| libc::timespec {
            tv_sec: libc::time_t::try_from(t.as_secs()).unwrap_or(libc::time_t::MAX),
            tv_nsec: t.subsec_nanos() as libc::c_long,
        });
        let ts_ptr = ts.as_ref().map_or(std::ptr::null(), |t| t as *const _);
        // SAFETY: `events` holds `max` writable entries, `ts_ptr` is null or points to a
        // timespec that outlives the call, and a null signal mask leaves the mask unchanged.
        unsafe {
            libc::epoll_pwait2(
                self.fd.as_raw_fd(),
                self.events.as_mut_ptr(),
                max,
                ts_ptr,
                std::ptr::null(),
            )
        }
    }
}
