//! The adapter shared between the runtime's futures on one single-threaded executor, the
//! wake-up that tells the I/O future its deadline moved, and the note that explicit traffic
//! may have changed its connections.

use core::cell::RefCell;
use core::sync::atomic::{AtomicBool, Ordering};

use embassy_sync::blocking_mutex::raw::NoopRawMutex;
use embassy_sync::blocking_mutex::Mutex;
use embassy_sync::signal::Signal;
use enip_stack::{Adapter, Device, Instant};

/// An [`Adapter`] shared by the socket futures; never borrowed across an `.await`.
pub struct SharedAdapter<D: Device> {
    adapter: Mutex<NoopRawMutex, RefCell<Adapter<D>>>,
    io_wake: Signal<NoopRawMutex, ()>,
    /// Set by every [`with_adapter`]: connections or the TCP/IP object may have changed.
    explicit: AtomicBool,
}

/// Wraps `adapter` for [`crate::run`].
pub const fn share<D: Device>(adapter: Adapter<D>) -> SharedAdapter<D> {
    SharedAdapter {
        adapter: Mutex::new(RefCell::new(adapter)),
        io_wake: Signal::new(),
        explicit: AtomicBool::new(false),
    }
}

/// Runs `f` with exclusive access to the shared adapter. If `f` brought the I/O deadline
/// forward (a Forward_Open, a trigger), the I/O future is woken to honour it.
///
/// The borrow cannot be taken twice: every caller returns before its next `.await`, and the
/// executor runs one future at a time.
pub fn with_adapter<D: Device, R>(
    shared: &SharedAdapter<D>,
    f: impl FnOnce(&mut Adapter<D>) -> R,
) -> R {
    let (r, before, after) = shared.adapter.lock(|cell| {
        let mut a = cell.borrow_mut();
        let before = a.io_deadline();
        let r = f(&mut a);
        (r, before, a.io_deadline())
    });
    shared.explicit.store(true, Ordering::Relaxed);
    if earlier(after, before) {
        shared.io_wake.signal(());
    }
    r
}

/// True (once) if [`with_adapter`] ran since the last call: the I/O future then checks what
/// only explicit traffic changes (multicast group and TTL).
pub(crate) fn take_explicit_change<D: Device>(shared: &SharedAdapter<D>) -> bool {
    shared.explicit.swap(false, Ordering::Relaxed)
}

/// Like [`with_adapter`] without the wake-up: for the I/O future itself.
pub(crate) fn with_adapter_quiet<D: Device, R>(
    shared: &SharedAdapter<D>,
    f: impl FnOnce(&mut Adapter<D>) -> R,
) -> R {
    shared.adapter.lock(|cell| f(&mut cell.borrow_mut()))
}

/// Waits until another future brought the I/O deadline forward.
pub(crate) async fn io_deadline_moved<D: Device>(shared: &SharedAdapter<D>) {
    shared.io_wake.wait().await
}

/// True if deadline `a` comes before `b` (`None` is never).
fn earlier(a: Option<Instant>, b: Option<Instant>) -> bool {
    match (a, b) {
        (Some(a), Some(b)) => a < b,
        (Some(_), None) => true,
        (None, _) => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn earlier_treats_none_as_never() {
        assert!(earlier(Some(Instant(1)), None));
        assert!(earlier(Some(Instant(1)), Some(Instant(2))));
        assert!(!earlier(Some(Instant(2)), Some(Instant(2))));
        assert!(!earlier(None, Some(Instant(2))));
    }
}
