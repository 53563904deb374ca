//! [`serve`]: the TLS listener on 2221 feeding one encapsulation session slot of the adapter
//! with decrypted bytes, as the plaintext socket on 44818 feeds its own, and encrypting the
//! replies.

use embassy_net::tcp::{State, TcpSocket};
use embassy_net::{IpAddress, IpEndpoint, Stack};
use embassy_time::{with_timeout, Duration, Timer};
use enip_firmware::{with_adapter, SharedAdapter};
use enip_stack::device::CloseReason;
use enip_stack::{Device, Instant, SocketId};

use crate::session::TlsSession;

/// EtherNet/IP over TLS: TCP port 2221 (the stack's, which the link task passes on).
pub use enip_stack::config::TLS_PORT;
/// Longest handshake; a client that takes longer is dropped.
const HANDSHAKE_TIMEOUT: Duration = Duration::from_secs(10);
/// Longest wait for a reply to be taken by the peer (the plaintext sockets' bound).
const WRITE_TIMEOUT: Duration = Duration::from_micros(enip_stack::tcp::WRITE_TIMEOUT.as_micros());
/// Longest wait for the peer's FIN when closing (the plaintext sockets' bound).
const LINGER: Duration = Duration::from_micros(enip_stack::tcp::LINGER.as_micros());
/// Pause before listening again after the socket refused to listen.
const RETRY: Duration = Duration::from_millis(100);
/// Decrypted bytes handed to the adapter per read.
const PLAIN_LEN: usize = 600;

/// The buffers of one TLS session: the TCP socket's, and the adapter's reply.
pub struct TlsBuffers<const F: usize> {
    rx: [u8; 1024],
    tx: [u8; 1024],
    reply: [u8; F],
}

impl<const F: usize> TlsBuffers<F> {
    /// Zeroed buffers (for a static).
    pub const fn new() -> Self {
        Self {
            rx: [0; 1024],
            tx: [0; 1024],
            reply: [0; F],
        }
    }
}

impl<const F: usize> Default for TlsBuffers<F> {
    fn default() -> Self {
        Self::new()
    }
}

/// Serves TLS on 2221 forever, one connection after the other, as the adapter's session
/// `id` over the shim's TLS slot `slot`; [`crate::setup`] must have succeeded.
pub async fn serve<D: Device, const S: usize, const C: usize, const F: usize, const L: usize>(
    net: Stack<'_>,
    adapter: &SharedAdapter<D, S, C, F, L>,
    id: SocketId,
    slot: usize,
    bufs: &mut TlsBuffers<F>,
    on_reset: &dyn Fn(u8),
) -> ! {
    let TlsBuffers { rx, tx, reply } = bufs;
    let mut socket = TcpSocket::new(net, rx, tx);
    loop {
        if socket.accept(TLS_PORT).await.is_err() {
            socket.abort();
            Timer::after(RETRY).await;
            continue;
        }
        let Some(peer) = socket.remote_endpoint().and_then(v4) else {
            socket.abort();
            continue;
        };
        // The session slot may be shared with a plaintext socket (the board's choice): a TLS
        // client is refused while the slot serves one (seen by its inactivity deadline, so
        // not when the timeout is off).
        if with_adapter(adapter, |a| a.tcp_deadline(id)).is_some() {
            socket.abort();
            let _ = with_timeout(Duration::from_millis(100), socket.flush()).await;
            continue;
        }
        // The suites EtherNet/IP Security allows now (a configuration applies to the next
        // session).
        let allowed = with_adapter(adapter, |a| a.security(now()).active.allowed.clone());
        crate::offer(&allowed);
        if let Ok(mut tls) = TlsSession::new(slot, &mut socket) {
            if let Ok(Ok(())) = with_timeout(HANDSHAKE_TIMEOUT, tls.handshake()).await {
                with_adapter(adapter, |a| {
                    a.tcp_accept(id, peer, now());
                    a.set_session_secure(id, true);
                });
                let peer_listens = converse(&mut tls, adapter, id, reply, on_reset).await;
                with_adapter(adapter, |a| a.tcp_close(id, now()));
                if peer_listens {
                    let _ = with_timeout(WRITE_TIMEOUT, tls.close_notify()).await;
                }
            }
        }
        shut_down(&mut socket).await;
    }
}

/// Closes gracefully if the peer cooperates within [`LINGER`] (as the plaintext sockets do),
/// otherwise resets; either way the socket is ready to listen again.
async fn shut_down(socket: &mut TcpSocket<'_>) {
    socket.close();
    let linger = async {
        let _ = socket.flush().await;
        // Discard anything still arriving until the peer's FIN (or RST) ends the stream.
        while socket.read_with(|data| (data.len(), ())).await.is_ok() {}
    };
    let _ = with_timeout(LINGER, linger).await;
    if !matches!(socket.state(), State::Closed | State::TimeWait) {
        socket.abort();
        let _ = with_timeout(Duration::from_millis(100), socket.flush()).await;
    }
}

/// Feeds decrypted bytes to the adapter and encrypts its replies until either side ends;
/// true if this side ended it on its own (inactivity, a reset), when the peer may still take
/// a close_notify. A peer that unregistered its session closes the connection itself, and a
/// close_notify racing its FIN would only draw a reset.
async fn converse<D: Device, const S: usize, const C: usize, const F: usize, const L: usize>(
    tls: &mut TlsSession<'_, '_>,
    adapter: &SharedAdapter<D, S, C, F, L>,
    id: SocketId,
    reply: &mut [u8],
    on_reset: &dyn Fn(u8),
) -> bool {
    let mut plain = [0u8; PLAIN_LEN];
    loop {
        let read = match with_adapter(adapter, |a| a.tcp_deadline(id)) {
            None => tls.read(&mut plain).await,
            Some(at) => {
                let at = embassy_time::Instant::from_micros(at.as_micros());
                match embassy_time::with_deadline(at, tls.read(&mut plain)).await {
                    Ok(read) => read,
                    Err(_) => return true,
                }
            }
        };
        // An error or a close_notify: the peer is gone.
        let Ok(len) = read else { return false };
        if len == 0 {
            return false;
        }
        let mut rest = plain.get(..len).unwrap_or(&[]);
        while !rest.is_empty() {
            let outcome = with_adapter(adapter, |a| a.tcp_receive(id, rest, now(), reply));
            rest = rest.get(outcome.consumed..).unwrap_or(&[]);
            if outcome.reply_len > 0 {
                let out = reply.get(..outcome.reply_len).unwrap_or(&[]);
                if !matches!(
                    with_timeout(WRITE_TIMEOUT, tls.write_all(out)).await,
                    Ok(Ok(()))
                ) {
                    return false;
                }
            }
            if let Some(kind) = outcome.reset {
                with_adapter(adapter, |a| a.close_all(CloseReason::Reset));
                on_reset(kind);
            }
            if outcome.close || outcome.consumed == 0 {
                return outcome.reset.is_some();
            }
        }
    }
}

/// The current time as the stack counts it.
fn now() -> Instant {
    Instant::from_micros(embassy_time::Instant::now().as_micros())
}

/// An IPv4 endpoint as the stack's address.
fn v4(ep: IpEndpoint) -> Option<core::net::SocketAddrV4> {
    match ep.addr {
        IpAddress::Ipv4(ip) => Some(core::net::SocketAddrV4::new(ip, ep.port)),
        #[allow(unreachable_patterns)]
        _ => None,
    }
}
