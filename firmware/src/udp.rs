//! The encapsulation UDP socket on port 44818: ListIdentity and friends, immediate or delayed.

use core::net::{IpAddr, Ipv4Addr, SocketAddrV4};

use embassy_futures::select::{select, Either};
use embassy_net::udp::{UdpMetadata, UdpSocket};
use embassy_net::Stack;
use embassy_time::{with_timeout, Duration, Timer};
use enip_stack::config::ENCAP_PORT;
use enip_stack::Device;

use crate::clock::{now, to_embassy};
use crate::netif::v4_endpoint;
use crate::resources::UdpBuffers;
use crate::shared::{with_adapter, SharedAdapter};

/// Longest wait for room in the transmit buffer before a reply is dropped.
const SEND_TIMEOUT: Duration = Duration::from_millis(500);

/// Serves UDP 44818 forever: answers datagrams and sends delayed replies when they come due.
pub(crate) async fn serve<
    D: Device,
    const S: usize,
    const C: usize,
    const F: usize,
    const L: usize,
>(
    net: Stack<'_>,
    adapter: &SharedAdapter<D, S, C, F, L>,
    bufs: &mut UdpBuffers<F>,
) -> ! {
    let UdpBuffers {
        rx_meta,
        rx,
        tx_meta,
        tx,
        reply,
    } = bufs;
    let mut socket = UdpSocket::new(net, rx_meta, rx, tx_meta, tx);
    if let Err(e) = socket.bind(ENCAP_PORT) {
        error!("udp {}: bind failed: {:?}", ENCAP_PORT, e);
        // Nothing else can use the port: keep the other futures running.
        loop {
            core::future::pending::<()>().await;
        }
    }
    loop {
        let due = with_adapter(adapter, |a| a.udp_deadline());
        // No timer at all while no reply is delayed: a timer in the queue costs every poll.
        let timer = async {
            match due {
                Some(at) => Timer::at(to_embassy(at)).await,
                None => core::future::pending().await,
            }
        };
        let event = select(
            socket.recv_from_with(|data, meta| answer(adapter, data, meta, reply)),
            timer,
        )
        .await;
        match event {
            Either::First(Some((to, len))) => {
                send(&socket, reply.get(..len).unwrap_or(&[]), to).await
            }
            Either::First(None) => {}
            Either::Second(()) => send_due(&socket, adapter, reply).await,
        }
    }
}

/// Feeds one datagram to the adapter; returns where to send the reply written to `reply`.
fn answer<D: Device, const S: usize, const C: usize, const F: usize, const L: usize>(
    adapter: &SharedAdapter<D, S, C, F, L>,
    data: &[u8],
    meta: UdpMetadata,
    reply: &mut [u8],
) -> Option<(SocketAddrV4, usize)> {
    let from = v4_endpoint(meta.endpoint)?;
    let to = match meta.local_address.map(IpAddr::from) {
        Some(IpAddr::V4(a)) => a,
        _ => Ipv4Addr::UNSPECIFIED,
    };
    let len = with_adapter(adapter, |a| a.udp_receive(from, to, data, now(), reply));
    (len > 0).then_some((from, len))
}

/// Sends every delayed reply that is due.
async fn send_due<D: Device, const S: usize, const C: usize, const F: usize, const L: usize>(
    socket: &UdpSocket<'_>,
    adapter: &SharedAdapter<D, S, C, F, L>,
    out: &mut [u8],
) {
    while let Some((to, len)) = with_adapter(adapter, |a| a.poll_udp(now(), out)) {
        send(socket, out.get(..len).unwrap_or(&[]), to).await;
    }
}

/// Sends one datagram, dropping it if the socket cannot take it in time.
async fn send(socket: &UdpSocket<'_>, data: &[u8], to: SocketAddrV4) {
    match with_timeout(SEND_TIMEOUT, socket.send_to(data, to)).await {
        Ok(Ok(())) => {}
        Ok(Err(e)) => warn!("udp reply to {}: {:?}", to, e),
        Err(_) => warn!("udp reply to {}: transmit buffer full", to),
    }
}
