//! One encapsulation TCP socket on port 44818: accept, feed the adapter, reply, close, listen
//! again. Each socket is its own future, so a slow or silent peer holds up only its own socket,
//! and a half-open connection holds it at most `tcp_accept::HALF_OPEN`.
//!
//! The session timeouts here ([`WRITE_TIMEOUT`], [`LINGER`]) are every runtime's: the host's
//! kernel-socket runtime (`enip-host --bind`) uses them too.

use core::task::Poll;
use embassy_futures::poll_once;
use embassy_net::tcp::{State, TcpSocket};
use embassy_net::Stack;
use embassy_time::{with_deadline, with_timeout, Duration, Timer};
use enip_stack::device::CloseReason;
use enip_stack::{Device, Instant, SocketId, TcpOutcome};

use crate::clock::{now, to_embassy};
use crate::netif::v4_endpoint;
use crate::resources::TcpBuffers;
use crate::shared::{with_adapter, with_adapter_quiet, SharedAdapter};
use crate::tcp_accept::accept;

/// Longest wait for a reply to fit in the transmit buffer (or be acknowledged before a reset);
/// a peer that takes longer loses its connection.
pub const WRITE_TIMEOUT: Duration = Duration::from_secs(5);
/// Longest wait for the peer to acknowledge our FIN and send its own when closing; then the
/// connection is reset.
pub const LINGER: Duration = Duration::from_secs(2);
/// Longest wait for the RST of an aborted connection to go out.
const ABORT_FLUSH: Duration = Duration::from_millis(100);
/// Pause before listening again after the socket refused to listen.
const RETRY: Duration = Duration::from_millis(100);

/// Serves TCP socket `id` forever, one connection after the other.
pub(crate) async fn serve<
    D: Device,
    const S: usize,
    const C: usize,
    const F: usize,
    const L: usize,
>(
    net: Stack<'_>,
    adapter: &SharedAdapter<D, S, C, F, L>,
    id: SocketId,
    bufs: &mut TcpBuffers<F>,
    on_reset: &dyn Fn(u8),
) -> ! {
    let TcpBuffers { rx, tx, reply } = bufs;
    let (reply, mut socket) = (
        &mut reply.bytes,
        TcpSocket::new(net, &mut rx.bytes, &mut tx.bytes),
    );
    loop {
        if let Err(e) = accept(&mut socket).await {
            warn!("tcp socket {}: listen failed: {:?}", id.0, e);
            socket.abort();
            Timer::after(RETRY).await;
            continue;
        }
        let Some(peer) = socket.remote_endpoint().and_then(v4_endpoint) else {
            // Reset during the handshake: nothing to serve.
            socket.abort();
            continue;
        };
        debug!("tcp socket {}: connection from {}", id.0, peer);
        with_adapter(adapter, |a| a.tcp_accept(id, peer, now()));
        converse(&mut socket, adapter, id, reply, on_reset).await;
        with_adapter(adapter, |a| a.tcp_close(id, now()));
        shut_down(&mut socket).await;
        debug!("tcp socket {}: closed", id.0);
    }
}

/// Exchanges frames on an accepted connection until either side ends it or it idles out.
async fn converse<D: Device, const S: usize, const C: usize, const F: usize, const L: usize>(
    socket: &mut TcpSocket<'_>,
    adapter: &SharedAdapter<D, S, C, F, L>,
    id: SocketId,
    reply: &mut [u8],
    on_reset: &dyn Fn(u8),
) {
    // The inactivity deadline is worked out again only when it passes or the timeout (TCP/IP
    // attribute 13) changes, not per request (it walks the connection table). Traffic since
    // only moves the true deadline later: passing the one kept costs a look, not the session.
    // Read-only: cannot bring the link task's deadline forward, so no watch/notice.
    let (mut timeout, mut deadline) = (inactivity_timeout(adapter), tcp_deadline(adapter, id));
    loop {
        let latest = inactivity_timeout(adapter);
        if latest != timeout {
            (timeout, deadline) = (latest, tcp_deadline(adapter, id));
        }
        // The outcome is written here, not returned through the futures: moved through their
        // `Poll<Result<..>>` layers it cost two 9-byte memcpy calls and the task's own moves
        // of it, about 185 instructions a request on the emulated M4.
        let mut outcome = TcpOutcome::default();
        let read = socket.read_with(|data| {
            let consumed;
            (consumed, outcome) = feed(adapter, id, data, reply);
            (consumed, ())
        });
        let read = match deadline {
            None => read.await,
            Some(at) => match with_deadline(to_embassy(at), read).await {
                Ok(read) => read,
                Err(_) if idle(adapter, id) => {
                    debug!("tcp socket {}: inactivity timeout", id.0);
                    return;
                }
                Err(_) => {
                    deadline = tcp_deadline(adapter, id);
                    continue;
                }
            },
        };
        // An error here is the peer's FIN or RST.
        if read.is_err() {
            return;
        }
        if outcome.reply_len > 0 {
            let out = reply.get(..outcome.reply_len).unwrap_or(&[]);
            if write_all(socket, out).await.is_err() {
                warn!("tcp socket {}: reply not sent in time", id.0);
                return;
            }
        }
        if let Some(kind) = outcome.reset {
            let _ = with_timeout(WRITE_TIMEOUT, socket.flush()).await;
            info!(
                "identity reset type {} requested on tcp socket {}",
                kind, id.0
            );
            with_adapter(adapter, |a| a.close_all(CloseReason::Reset));
            on_reset(kind);
        }
        if outcome.close {
            return;
        }
    }
}

/// Hands received bytes to the adapter; returns the bytes consumed and what follows. Never
/// inlined: `cargo xtask bench --qemu` counts its calls as the explicit requests served.
#[inline(never)]
fn feed<D: Device, const S: usize, const C: usize, const F: usize, const L: usize>(
    adapter: &SharedAdapter<D, S, C, F, L>,
    id: SocketId,
    data: &mut [u8],
    reply: &mut [u8],
) -> (usize, TcpOutcome) {
    let outcome = with_adapter(adapter, |a| a.tcp_receive(id, data, now(), reply));
    (outcome.consumed.min(data.len()), outcome)
}

/// True if the connection on `id` has been idle past the inactivity timeout.
fn idle<D: Device, const S: usize, const C: usize, const F: usize, const L: usize>(
    adapter: &SharedAdapter<D, S, C, F, L>,
    id: SocketId,
) -> bool {
    tcp_deadline(adapter, id).is_some_and(|at| at <= now())
}

/// When the connection on `id` must close if idle until then (read-only, so without
/// [`with_adapter`]'s wake-ups).
fn tcp_deadline<D: Device, const S: usize, const C: usize, const F: usize, const L: usize>(
    adapter: &SharedAdapter<D, S, C, F, L>,
    id: SocketId,
) -> Option<Instant> {
    with_adapter_quiet(adapter, |a| a.tcp_deadline(id))
}

/// The encapsulation inactivity timeout in seconds (TCP/IP attribute 13; 0 is off).
fn inactivity_timeout<D: Device, const S: usize, const C: usize, const F: usize, const L: usize>(
    adapter: &SharedAdapter<D, S, C, F, L>,
) -> u16 {
    with_adapter_quiet(adapter, |a| a.objects().tcpip.inactivity_timeout_s)
}

/// Queues all of `data` for sending, or fails if the peer does not make room in time.
async fn write_all(socket: &mut TcpSocket<'_>, data: &[u8]) -> Result<(), ()> {
    let mut rest = data;
    // The usual case: the reply fits the free send buffer and is queued in one step, without
    // arming a timer (which reads the clock). Anything left waits under WRITE_TIMEOUT.
    if socket.send_capacity().saturating_sub(socket.send_queue()) >= data.len() {
        match poll_once(socket.write(data)) {
            Poll::Ready(Ok(n)) if n >= data.len() => return Ok(()),
            Poll::Ready(Ok(n)) => rest = data.get(n..).unwrap_or(&[]),
            Poll::Ready(Err(_)) => return Err(()),
            Poll::Pending => {}
        }
    }
    let write = async {
        while !rest.is_empty() {
            match socket.write(rest).await {
                Ok(n) if n > 0 => rest = rest.get(n..).unwrap_or(&[]),
                _ => return Err(()),
            }
        }
        Ok(())
    };
    with_timeout(WRITE_TIMEOUT, write).await.unwrap_or(Err(()))
}

/// Closes gracefully if the peer cooperates within [`LINGER`], otherwise resets; either way
/// the socket is ready to listen again.
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
        let _ = with_timeout(ABORT_FLUSH, socket.flush()).await;
    }
}
