//! Membership of the T->O multicast group: joined while multicast connections exist, left
//! after (the link task sends to the group; the TCP/IP stack answers IGMP for it).

use core::net::Ipv4Addr;

use embassy_net::Stack;
use enip_stack::Device;

use crate::shared::{membership_changed, with_adapter_quiet, SharedAdapter};

/// Keeps `net`'s group membership on the adapter's multicast group, forever.
pub(crate) async fn track<
    D: Device,
    const S: usize,
    const C: usize,
    const F: usize,
    const L: usize,
>(
    net: Stack<'_>,
    adapter: &SharedAdapter<D, S, C, F, L>,
) -> ! {
    let mut joined: Option<Ipv4Addr> = None;
    loop {
        let want = with_adapter_quiet(adapter, |a| a.multicast_group());
        if want != joined {
            if let Some(old) = joined.take() {
                if let Err(e) = net.leave_multicast_group(old) {
                    warn!("leave {}: {:?}", old, e);
                }
            }
            if let Some(new) = want {
                match net.join_multicast_group(new) {
                    Ok(()) => joined = Some(new),
                    Err(e) => warn!("join {}: {:?}", new, e),
                }
            }
        }
        membership_changed(adapter).await;
    }
}
