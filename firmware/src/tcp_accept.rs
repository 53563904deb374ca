//! Listening on TCP 44818 with half-open connections bounded: a connection whose SYN came
//! but whose handshake's ACK did not within [`HALF_OPEN`] is dropped and its socket listens
//! again. smoltcp has no SYN cookies and one connection per socket, so without the bound a
//! SYN flood (or a single SYN from a forged address nobody answers for) holds the adapter's
//! three sockets for as long as smoltcp keeps retrying the SYN-ACK, and every new client is
//! refused. The link task's SYN guard (`link/flood_guard.rs`) keeps a flooding source from
//! taking them again meanwhile.

use core::future::{poll_fn, Future};
use core::pin::pin;
use core::task::Poll;

use embassy_futures::poll_once;
use embassy_net::tcp::{AcceptError, State, TcpSocket};
use embassy_net::IpEndpoint;
use embassy_time::{with_timeout, Duration, Instant};
use enip_stack::config::ENCAP_PORT;

use crate::clock::instant_now;

/// Longest a connection may stay half-open (SYN received, waiting for the handshake's ACK)
/// before its socket listens again. A peer on the LAN answers in well under a millisecond.
pub const HALF_OPEN: Duration = Duration::from_millis(300);

/// Listens on [`ENCAP_PORT`] until a connection is established (or the socket is left in a
/// state past the handshake, e.g. a peer that sent its FIN at once), dropping each
/// half-open one after [`HALF_OPEN`].
pub(crate) async fn accept(socket: &mut TcpSocket<'_>) -> Result<(), AcceptError> {
    // The half-open connection being timed, and since when.
    let mut half_open: Option<(Option<IpEndpoint>, Instant)> = None;
    loop {
        match socket.state() {
            State::Closed | State::TimeWait => {
                // The first poll of `accept` listens; what follows is waited for below.
                if let Poll::Ready(Err(e)) = poll_once(socket.accept(ENCAP_PORT)) {
                    return Err(e);
                }
            }
            State::Listen => {
                half_open = None;
                next_event(socket).await;
            }
            State::SynReceived | State::SynSent => {
                let peer = socket.remote_endpoint();
                let since = match half_open {
                    Some((p, at)) if p == peer => at,
                    _ => instant_now(),
                };
                half_open = Some((peer, since));
                let left = since
                    .checked_add(HALF_OPEN)
                    .and_then(|end| end.checked_duration_since(instant_now()));
                match left.filter(|l| *l > Duration::from_ticks(0)) {
                    Some(left) => {
                        let _ = with_timeout(left, next_event(socket)).await;
                    }
                    None => {
                        debug!(
                            "tcp: half-open connection dropped after {} ms",
                            HALF_OPEN.as_millis()
                        );
                        socket.abort();
                        half_open = None;
                    }
                }
            }
            _ => return Ok(()),
        }
    }
}

/// Completes at the socket's next wake-up: a change of state (smoltcp wakes its waiters on
/// every one), or anything else that wakes the task (the caller looks again either way).
async fn next_event(socket: &TcpSocket<'_>) {
    let mut ready = pin!(socket.wait_write_ready());
    let mut waited = false;
    poll_fn(|cx| {
        if waited {
            return Poll::Ready(());
        }
        waited = true;
        // Registers the task with the socket; ready at once only when it could send.
        ready.as_mut().poll(cx)
    })
    .await;
}
