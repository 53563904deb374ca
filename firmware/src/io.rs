//! Class 1 implicit I/O on UDP 2222: O->T datagrams into the adapter, T->O production at the
//! adapter's exact deadlines (`Timer::at`), multicast group membership and TTL.
//!
//! Two sockets share port 2222: `unicast` sends point-to-point T->O data with the default hop
//! limit and receives every O->T datagram (smoltcp hands a datagram to the first socket bound
//! to its port), `multicast` sends to the group with the TCP/IP object's TTL.

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
use crate::shared::{
    io_deadline_moved, take_explicit_change, with_adapter_quiet as with_adapter, SharedAdapter,
};

/// Longest wait for transmit buffer room before a T->O datagram is dropped.
const SEND_TIMEOUT: Duration = Duration::from_millis(1);

/// Runs Class 1 I/O forever.
pub(crate) async fn serve<D: Device>(
    net: Stack<'_>,
    adapter: &SharedAdapter<D>,
    bufs: &mut IoBuffers,
) -> ! {
    let IoBuffers { unicast, multicast } = bufs;
    let (Some(mut unicast), Some(mut multicast)) = (open(net, unicast), open(net, multicast))
    else {
        loop {
            core::future::pending::<()>().await;
        }
    };
    let mut group: Option<Ipv4Addr> = None;
    let mut ttl = 0u8;
    let mut timeouts = None;
    loop {
        produce(adapter, &mut unicast, &mut multicast).await;
        // Membership and TTL change only when a connection opens or closes or the TCP/IP
        // object changes: after explicit traffic or a watchdog expiry.
        let (due, now_timeouts) =
            with_adapter(adapter, |a| (a.io_deadline(), a.connections().timeouts()));
        if take_explicit_change(adapter) || timeouts != Some(now_timeouts) {
            timeouts = Some(now_timeouts);
            track_multicast(net, adapter, &mut multicast, &mut group, &mut ttl);
        }
        let timer = async {
            match due {
                Some(at) => Timer::at(to_embassy(at)).await,
                None => core::future::pending().await,
            }
        };
        // Whichever comes first, the loop produces what is due and waits again.
        let _ = select4(
            unicast.recv_from_with(|data, meta| consume(adapter, data, meta)),
            multicast.recv_from_with(|data, meta| consume(adapter, data, meta)),
            timer,
            io_deadline_moved(adapter),
        )
        .await;
    }
}

/// A UDP socket bound to port 2222, or `None` if binding failed.
fn open<'a, const P: usize, const L: usize>(
    net: Stack<'a>,
    b: &'a mut IoSocketBuffers<P, L>,
) -> Option<UdpSocket<'a>> {
    let mut socket = UdpSocket::new(net, &mut b.rx_meta, &mut b.rx, &mut b.tx_meta, &mut b.tx);
    match socket.bind(IO_PORT) {
        Ok(()) => Some(socket),
        Err(e) => {
            error!("udp {}: bind failed: {:?}", IO_PORT, e);
            None
        }
    }
}

/// Hands one O->T datagram to the adapter. Never inlined: `cargo xtask bench` counts its
/// calls as the Class 1 cycles of the emulated board.
#[inline(never)]
fn consume<D: Device>(adapter: &SharedAdapter<D>, data: &[u8], meta: UdpMetadata) {
    if let Some(from) = v4_endpoint(meta.endpoint) {
        // A discarded datagram is counted by the adapter; nothing to answer.
        let _ = with_adapter(adapter, |a| a.io_receive(from, data, now()));
    }
}

/// Sends every T->O datagram that is due now, each built by the adapter straight into its
/// socket's transmit buffer.
async fn produce<'a, D: Device>(
    adapter: &SharedAdapter<D>,
    unicast: &mut UdpSocket<'a>,
    multicast: &mut UdpSocket<'a>,
) {
    let at = now();
    // Bounded: each round sends or drops one datagram, and each producer is due once.
    for _ in 0..enip_stack::config::MAX_CONNECTIONS * 2 {
        let Some(due) = with_adapter(adapter, |a| a.io_due(at)) else {
            return;
        };
        let socket = if due.to.ip().is_multicast() {
            &mut *multicast
        } else {
            &mut *unicast
        };
        // With room in the buffer (the usual case) the datagram is written in the first
        // poll, right after `io_due`. After a wait for room, a connection closed meanwhile
        // leaves an empty datagram.
        let send = socket.send_to_with(due.max_len, due.to, |buf| {
            (
                with_adapter(adapter, |a| a.write_io(due, at, Some(buf))),
                (),
            )
        });
        match with_timeout(SEND_TIMEOUT, send).await {
            Ok(Ok(())) => continue,
            Ok(Err(e)) => warn!("io to {}: {:?}", due.to, e),
            Err(_) => warn!("io to {}: transmit buffer full", due.to),
        }
        // Not sent: the connection moves on to its next production all the same.
        with_adapter(adapter, |a| a.write_io(due, at, None));
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
