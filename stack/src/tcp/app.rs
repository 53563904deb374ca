//! The adapter as the server's [`TcpApp`]: its sessions take the byte streams.

use core::net::SocketAddrV4;

use super::TcpApp;
use crate::{Adapter, Device, Instant, SocketId, TcpOutcome};

impl<D: Device, const S: usize, const C: usize, const F: usize, const L: usize> TcpApp
    for Adapter<D, S, C, F, L>
{
    fn accepted(&mut self, id: SocketId, peer: SocketAddrV4, now: Instant) {
        self.tcp_accept(id, peer, now);
    }

    /// Never inlined: `cargo xtask bench --qemu` counts its calls as the explicit requests
    /// served.
    #[inline(never)]
    fn receive(&mut self, id: SocketId, data: &[u8], now: Instant, reply: &mut [u8]) -> TcpOutcome {
        self.tcp_receive(id, data, now, reply)
    }

    fn closed(&mut self, id: SocketId, now: Instant) {
        self.tcp_close(id, now);
    }

    fn idle_deadline(&self, id: SocketId) -> Option<Instant> {
        self.tcp_deadline(id)
    }
}
