//! [`run`]: every future of the adapter's explicit side that is not the link task's, joined
//! into one that never ends (Class 1 I/O and the encapsulation TCP are the link task's,
//! [`crate::link`]).

use embassy_futures::join::join5;
use embassy_net::Stack;
use enip_stack::Device;

use crate::resources::Resources;
use crate::shared::SharedAdapter;
use crate::{device_tick, multicast, netif, udp};

/// Runs the adapter on `net` forever: the UDP socket on port 44818, the multicast group
/// membership of Class 1 I/O, tracking of the interface configuration, the device's own
/// clock ([`Device::poll`], application-triggered production on input changes), and the
/// Identity Resets the encapsulation TCP accepted. Class 1 datagrams and the encapsulation
/// TCP connections themselves are the link task's ([`crate::link::run`], which the board
/// spawns beside).
///
/// `on_reset` is called with the Identity Reset type (0: power cycle, 1: factory defaults)
/// once the reply accepting it has been acknowledged; a board typically restarts there.
///
/// Run it on a single-threaded executor, next to the `embassy_net::Runner` of `net` and the
/// link task.
pub async fn run<D: Device, const S: usize, const C: usize, const F: usize, const L: usize>(
    net: Stack<'_>,
    adapter: &SharedAdapter<D, S, C, F, L>,
    resources: &mut Resources<F>,
    on_reset: impl Fn(u8),
) -> ! {
    let resets = async {
        loop {
            on_reset(adapter.reset_requested().await);
        }
    };
    // Every joined future loops forever: the join never completes.
    let (never, ..) = join5(
        resets,
        udp::serve(net, adapter, &mut resources.udp),
        multicast::track(net, adapter),
        netif::track(net, adapter),
        device_tick::serve(adapter),
    )
    .await;
    never
}
