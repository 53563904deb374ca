//! Class 1 implicit I/O on UDP 2222: O->T datagrams into the adapter, T->O production at the
//! adapter's exact deadlines (`Timer::at`), multicast group membership and TTL.
//!
//! Two sockets share port 2222: `unicast` sends point-to-point T->O data with the default hop
//! limit, `multicast` sends to the group with the TCP/IP object's TTL. Both receive, since
//! which one smoltcp hands an O->T datagram to is its own business.

use core::net::Ipv4Addr;

use embassy_futures::select::select4;
use embassy_net::udp::{UdpMetadata, UdpSocket};
use embassy_net::Stack;
use embassy_time::{with_timeout, Duration, Timer};
use enip_stack::config::IO_PORT;
use enip_stack::Device;

use crate::clock::{now, to_embassy};
use crate::netif::v4_endpoint;
use crate::resources::{IoBuffers, IoSocketBuffers};
use crate::shared::{io_deadline_moved, with_adapter_quiet as with_adapter, SharedAdapter};

/// Longest wait for transmit buffer room before a T->O datagram is dropped.
const SEND_TIMEOUT: Duration = Duration::from_millis(1);

/// Runs Class 1 I/O forever.
pub(crate) async fn serve<D: Device>(
    net: Stack<'_>,
    adapter: &SharedAdapter<D>,
    bufs: &mut IoBuffers,
) -> ! {
    let IoBuffers {
        unicast,
        multicast,
        out,
    } = bufs;
    let (Some(mut unicast), Some(mut multicast)) = (open(net, unicast), open(net, multicast))
    else {
        loop {
            core::future::pending::<()>().await;
        }
    };
    let mut group: Option<Ipv4Addr> = None;
    let mut ttl = 0u8;
    loop {
        produce(adapter, &unicast, &multicast, out).await;
        track_multicast(net, adapter, &mut multicast, &mut group, &mut ttl);
        let due = with_adapter(adapter, |a| a.io_deadline())
            .map_or(embassy_time::Instant::MAX, to_embassy);
        // Whichever comes first, the loop produces what is due and waits again.
        let _ = select4(
            unicast.recv_from_with(|data, meta| consume(adapter, data, meta)),
            multicast.recv_from_with(|data, meta| consume(adapter, data, meta)),
            Timer::at(due),
            io_deadline_moved(adapter),
        )
        .await;
    }
}

/// A UDP socket bound to port 2222, or `None` if binding failed.
fn open<'a>(net: Stack<'a>, b: &'a mut IoSocketBuffers) -> Option<UdpSocket<'a>> {
    let mut socket = UdpSocket::new(net, &mut b.rx_meta, &mut b.rx, &mut b.tx_meta, &mut b.tx);
    match socket.bind(IO_PORT) {
        Ok(()) => Some(socket),
        Err(e) => {
            error!("udp {}: bind failed: {:?}", IO_PORT, e);
            None
        }
    }
}

/// Hands one O->T datagram to the adapter.
fn consume<D: Device>(adapter: &SharedAdapter<D>, data: &[u8], meta: UdpMetadata) {
    if let Some(from) = v4_endpoint(meta.endpoint) {
        // A discarded datagram is counted by the adapter; nothing to answer.
        let _ = with_adapter(adapter, |a| a.io_receive(from, data, now()));
    }
}

/// Sends every T->O datagram that is due now.
async fn produce<D: Device>(
    adapter: &SharedAdapter<D>,
    unicast: &UdpSocket<'_>,
    multicast: &UdpSocket<'_>,
    out: &mut [u8],
) {
    let at = now();
    // Bounded: each call either produces or returns None, and each producer is due once.
    for _ in 0..enip_stack::config::MAX_CONNECTIONS * 2 {
        let Some((to, len)) = with_adapter(adapter, |a| a.poll_io(at, out)) else {
            return;
        };
        let socket = if to.ip().is_multicast() {
            multicast
        } else {
            unicast
        };
        match with_timeout(
            SEND_TIMEOUT,
            socket.send_to(out.get(..len).unwrap_or(&[]), to),
        )
        .await
        {
            Ok(Ok(())) => {}
            Ok(Err(e)) => warn!("io to {}: {:?}", to, e),
            Err(_) => warn!("io to {}: transmit buffer full", to),
        }
    }
}

/// Joins the T->O multicast group while multicast connections exist, leaves it after, and
/// keeps the multicast socket's hop limit at the TCP/IP object's TTL.
fn track_multicast<D: Device>(
    net: Stack<'_>,
    adapter: &SharedAdapter<D>,
    multicast: &mut UdpSocket<'_>,
    joined: &mut Option<Ipv4Addr>,
    ttl: &mut u8,
) {
    let (want, want_ttl) = with_adapter(adapter, |a| (a.multicast_group(), a.multicast_ttl()));
    if want_ttl != *ttl {
        multicast.set_hop_limit(Some(want_ttl));
        *ttl = want_ttl;
    }
    if want == *joined {
        return;
    }
    if let Some(old) = joined.take() {
        if let Err(e) = net.leave_multicast_group(old) {
            warn!("leave {}: {:?}", old, e);
        }
    }
    if let Some(new) = want {
        match net.join_multicast_group(new) {
            Ok(()) => *joined = Some(new),
            Err(e) => warn!("join {}: {:?}", new, e),
        }
    }
}
