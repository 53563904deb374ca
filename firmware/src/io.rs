//! Class 1 implicit I/O: the slot where the UDP 2222 socket and the producer timer go.
//!
//! NOT IMPLEMENTED YET. [`serve`] is already joined by [`crate::run`] next to the
//! encapsulation sockets, so adding I/O means filling in this one future: bind UDP
//! [`stack::config::IO_PORT`], feed received O->T datagrams to the adapter, join multicast
//! groups, and produce T->O data at `Timer::at(next production deadline)`. Its socket buffers
//! belong in [`crate::Resources`].

use embassy_net::Stack;
use stack::Device;

use crate::shared::SharedAdapter;

/// Runs Class 1 I/O forever; for now it only waits, as no I/O connection can be opened yet.
pub(crate) async fn serve<D: Device>(_net: Stack<'_>, _adapter: &SharedAdapter<D>) -> ! {
    core::future::pending().await
}
