//! [`Wakeup`]: how a loop learns that it has work. Every wake sets a flag; only a wake while
//! the loop sleeps (necessarily from another thread) also writes an eventfd the loop's
//! `ppoll` watches, so a wake on the loop's own thread, nearly all of them, costs one atomic
//! store and no system call.

use std::io;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd, RawFd};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::task::Wake;

/// A loop's pending-work flag and its eventfd.
pub(crate) struct Wakeup {
    /// Something was woken since the loop last looked.
    pending: AtomicBool,
    /// The loop is in (or about to enter) its wait.
    sleeping: AtomicBool,
    eventfd: OwnedFd,
}

impl Wakeup {
    /// A flag with a new eventfd.
    pub(crate) fn new() -> io::Result<Self> {
        // SAFETY: eventfd(2) with constant arguments; the result is checked before use.
        let fd = unsafe { libc::eventfd(0, libc::EFD_NONBLOCK | libc::EFD_CLOEXEC) };
        if fd < 0 {
            return Err(io::Error::last_os_error());
        }
        Ok(Wakeup {
            pending: AtomicBool::new(false),
            sleeping: AtomicBool::new(false),
            // SAFETY: `fd` is an eventfd this function just opened and nothing else owns.
            eventfd: unsafe { OwnedFd::from_raw_fd(fd) },
        })
    }

    /// Marks work pending; ends the loop's wait if it sleeps.
    pub(crate) fn signal(&self) {
        self.pending.store(true, Ordering::SeqCst);
        if self.sleeping.load(Ordering::SeqCst) {
            let one = 1u64.to_ne_bytes();
            // SAFETY: writes 8 bytes from a live 8-byte array to the eventfd this owns. A
            // full counter (EAGAIN) already wakes the loop, so the result is not needed.
            let _ = unsafe { libc::write(self.fd(), one.as_ptr().cast(), one.len()) };
        }
    }

    /// Whether work was pending; clears it.
    pub(crate) fn take(&self) -> bool {
        self.pending.load(Ordering::SeqCst) && self.pending.swap(false, Ordering::SeqCst)
    }

    /// Enters the wait: from here a wake writes the eventfd. Returns false, staying awake, if
    /// work is pending (and clears it).
    pub(crate) fn sleep(&self) -> bool {
        self.sleeping.store(true, Ordering::SeqCst);
        if self.take() {
            self.sleeping.store(false, Ordering::SeqCst);
            return false;
        }
        true
    }

    /// Leaves the wait; empties the eventfd if `written` (it was found readable).
    pub(crate) fn awake(&self, written: bool) {
        self.sleeping.store(false, Ordering::SeqCst);
        if written {
            let mut count = [0u8; 8];
            // SAFETY: reads at most 8 bytes into a live 8-byte array from the eventfd this
            // owns; a read that finds it empty (EAGAIN) changes nothing.
            let _ = unsafe { libc::read(self.fd(), count.as_mut_ptr().cast(), count.len()) };
        }
    }

    /// The eventfd, for the wait to watch.
    pub(crate) fn fd(&self) -> RawFd {
        self.eventfd.as_raw_fd()
    }
}

/// A [`Wakeup`] as a waker, for [`crate::block_on`].
impl Wake for Wakeup {
    fn wake(self: Arc<Self>) {
        self.signal();
    }

    fn wake_by_ref(self: &Arc<Self>) {
        self.signal();
    }
}

/// The pender of every embassy executor in the program, which are [`crate::run`]'s: its
/// context is the executor's [`Wakeup`].
#[unsafe(export_name = "__pender")]
fn pender(context: *mut ()) {
    // SAFETY: `run` creates its executor with a pointer to a leaked (so never freed)
    // `Wakeup` as the context, and no other executor exists in a program that links this
    // crate (it owns the `__pender` symbol).
    let wakeup = unsafe { &*context.cast_const().cast::<Wakeup>() };
    wakeup.signal();
}
