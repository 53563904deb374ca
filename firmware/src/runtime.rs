//! [`run`]: every socket future of the adapter's explicit side, joined into one that never
//! ends (Class 1 I/O is the link task's, [`crate::link`]).

use embassy_futures::join::{join5, join_array};
use embassy_net::Stack;
use enip_stack::{Device, SocketId};

use crate::resources::Resources;
use crate::shared::SharedAdapter;
use crate::{device_tick, multicast, netif, tcp, udp};

/// Runs the adapter on `net` forever: the encapsulation TCP sockets and UDP socket on port
/// 44818, the multicast group membership of Class 1 I/O, tracking of the interface
/// configuration, and the device's own clock ([`Device::poll`], application-triggered
/// production on input changes). Class 1 datagrams themselves are the link task's
/// ([`crate::link::run`], which the board spawns beside).
///
/// `on_reset` is called with the Identity Reset type (0: power cycle, 1: factory defaults)
/// once the reply accepting it has been sent; a board typically restarts there.
///
/// Run it on a single-threaded executor, next to the `embassy_net::Runner` of `net` and the
/// link task.
pub async fn run<D: Device, const S: usize, const C: usize, const F: usize, const L: usize>(
    net: Stack<'_>,
    adapter: &SharedAdapter<D, S, C, F, L>,
    resources: &mut Resources<S, F>,
    on_reset: impl Fn(u8),
) -> ! {
    let on_reset: &dyn Fn(u8) = &on_reset;
    let Resources { tcp, udp } = resources;
    let mut index = 0u8;
    let sockets = tcp.each_mut().map(|bufs| {
        let id = SocketId(index);
        index = index.wrapping_add(1);
        tcp::serve(net, adapter, id, bufs, on_reset)
    });
    // Every joined future loops forever: the join never completes.
    let (_, never, _, _, _) = join5(
        join_array(sockets),
        udp::serve(net, adapter, udp),
        multicast::track(net, adapter),
        netif::track(net, adapter),
        device_tick::serve(adapter),
    )
    .await;
    never
}
