//! The device's own clock: calls [`enip_stack::Device::poll`] (through
//! [`enip_stack::Adapter::poll_device`], which also produces the inputs the device says changed)
//! at the instant it asks for, e.g. a simulated drive's control tick.

use embassy_time::Timer;
use enip_stack::Device;

use crate::clock::{now, to_embassy};
use crate::shared::{with_adapter, SharedAdapter};

/// Runs the device's clock forever; a device that never asks to be polled again is left
/// alone (its input changes still go out after each request or O->T datagram).
pub(crate) async fn serve<
    D: Device,
    const S: usize,
    const C: usize,
    const F: usize,
    const L: usize,
>(
    adapter: &SharedAdapter<D, S, C, F, L>,
) -> ! {
    loop {
        match with_adapter(adapter, |a| a.poll_device(now())) {
            Some(at) => Timer::at(to_embassy(at)).await,
            None => core::future::pending::<()>().await,
        }
    }
}
