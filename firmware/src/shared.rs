//! The adapter shared between the runtime's futures on one single-threaded executor.

use core::cell::RefCell;

use embassy_sync::blocking_mutex::raw::NoopRawMutex;
use embassy_sync::blocking_mutex::Mutex;
use stack::{Adapter, Device};

/// An [`Adapter`] shared by the socket futures; never borrowed across an `.await`.
pub type SharedAdapter<D> = Mutex<NoopRawMutex, RefCell<Adapter<D>>>;

/// Wraps `adapter` for [`crate::run`].
pub const fn share<D: Device>(adapter: Adapter<D>) -> SharedAdapter<D> {
    Mutex::new(RefCell::new(adapter))
}

/// Runs `f` with exclusive access to the shared adapter.
///
/// The borrow cannot be taken twice: every caller returns before its next `.await`, and the
/// executor runs one future at a time.
pub fn with_adapter<D: Device, R>(
    shared: &SharedAdapter<D>,
    f: impl FnOnce(&mut Adapter<D>) -> R,
) -> R {
    shared.lock(|cell| f(&mut cell.borrow_mut()))
}
