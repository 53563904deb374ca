//! The link task's part of TCP: each segment for port 44818 goes to the adapter's TCP server
//! ([`IoPort::tcp_segment`], which hands its data to the sessions), a segment for a port
//! nothing listens on is answered with a RST, and each segment the server owes goes out
//! behind its headers, marked with the DSCP of explicit messaging. One wake-up of the link
//! task takes a request and sends its reply.

use core::net::Ipv4Addr;
use core::task::Context;

use embassy_net_driver::{Driver, TxToken};
use enip_stack::config::ENCAP_PORT;
use enip_stack::tcp::{closed_port_answer, Outgoing};
use enip_stack::{Instant, NetworkConfig};
use smoltcp::phy::ChecksumCapabilities;

use super::frame::{self, send_copy, ARP_REQUEST_LEN};
use super::io_port::IoPort;
use super::neighbors::{next_hop, Neighbors};
use super::tcp_frames::{self, Hop};

/// Segments sent in one pass at most: every connection's reply and its FIN, and the answer to
/// a segment of no connection.
const SEGMENTS_PER_PASS: usize = 2 * enip_stack::config::MAX_SESSIONS + 1;

/// What the link task keeps of TCP between passes.
#[derive(Debug, Default)]
pub(crate) struct TcpLink {
    /// When the server's timers run next, as last asked.
    next: Option<Instant>,
    /// The server took a segment or had no room to send: it is asked again at the next pass.
    stale: bool,
    /// The answer to a segment of no connection (a RST, or a SYN cookie's SYN-ACK), to send
    /// from our port.
    answer: Option<(Outgoing, u16)>,
}

/// Where the segments go from: our MAC address, the interface, and whether its address may
/// be used (Address Conflict Detection).
pub(crate) struct LocalEnd<'a> {
    /// Our MAC address.
    pub mac: [u8; 6],
    /// The interface configuration.
    pub me: &'a NetworkConfig,
    /// The address may be used.
    pub usable: bool,
}

impl TcpLink {
    /// The TCP segment `segment` (an IPv4 payload) from `src` to the interface `me`, its
    /// checksum checked if `verify`: to the server, at `at`; true if it was well formed and
    /// its checksum held.
    pub(crate) fn take(
        &mut self,
        segment: &[u8],
        (src, me): (Ipv4Addr, Ipv4Addr),
        verify: bool,
        io: &dyn IoPort,
        at: Instant,
    ) -> bool {
        let Some(segment) = tcp_frames::parse(segment, src, me, verify) else {
            return false;
        };
        if let Some(answer) = io.tcp_segment(&segment, at) {
            self.answer = Some((answer, ENCAP_PORT));
        }
        self.stale = true;
        true
    }

    /// The TCP segment `segment` (an IPv4 payload) from `src` to `port` of the interface
    /// `me`, a port nothing listens on, its checksum checked if `verify`: a RST answers it
    /// (RFC 9293 3.10.7.1), so a scanner finds the port closed; true if it was well formed
    /// and its checksum held.
    pub(crate) fn refuse(
        &mut self,
        segment: &[u8],
        (src, me, port): (Ipv4Addr, Ipv4Addr, u16),
        verify: bool,
    ) -> bool {
        let Some(segment) = tcp_frames::parse(segment, src, me, verify) else {
            return false;
        };
        // An answer owed on the encapsulation port (a SYN cookie's SYN-ACK) is not given up
        // for a closed port's: SYNs to other ports pass no flood guard.
        if let Some(answer) = closed_port_answer(&segment).filter(|_| self.answer.is_none()) {
            self.answer = Some((answer, port));
            self.stale = true;
        }
        true
    }

    /// True if the pass at `at` has TCP work: a segment came, or a timer is due.
    pub(crate) fn due(&self, at: Instant) -> bool {
        self.stale || self.next.is_some_and(|next| next <= at)
    }

    /// When the server's timers run next.
    pub(crate) fn deadline(&self) -> Option<Instant> {
        self.next
    }

    /// Runs the server's timers if due at `at` and sends what it owes from `from`; false if
    /// the driver had no room (the rest goes when it has: the driver wakes the task).
    pub(crate) fn serve<D: Driver>(
        &mut self,
        (cx, driver): (&mut Context<'_>, &mut D),
        io: &dyn IoPort,
        from: &LocalEnd<'_>,
        (neighbors, sums): (&mut Neighbors, &ChecksumCapabilities),
        at: Instant,
    ) -> bool {
        if self.next.is_some_and(|next| next <= at) {
            io.tcp_poll(at);
        }
        let dscp = io.explicit_dscp();
        let mut sent_all = false;
        let mut room = true;
        for _ in 0..SEGMENTS_PER_PASS {
            let answer = self.answer.take();
            if answer.is_none() && !io.tcp_owes() {
                sent_all = true;
                break;
            }
            let Some(tx) = driver.transmit(cx) else {
                self.answer = answer;
                room = false;
                break;
            };
            let mut tx = Some(tx);
            // The server's segments go from the encapsulation port, an answer from the port
            // its segment came to.
            let port = answer.as_ref().map_or(ENCAP_PORT, |&(_, port)| port);
            let mut send = |out: &Outgoing, payload: &[u8]| {
                if let Some(tx) = tx.take() {
                    send_segment(tx, (from, dscp, port), out, payload, (neighbors, sums), at);
                }
            };
            match answer {
                Some((answer, _)) => send(&answer, &[]),
                None => {
                    io.tcp_transmit(at, &mut send);
                }
            }
        }
        if !sent_all && room {
            // More than a pass sends: the next pass goes on at once.
            cx.waker().wake_by_ref();
        }
        self.stale = !sent_all;
        self.next = io.tcp_deadline();
        room
    }
}

/// Sends `out` with `payload` through `tx` from `from` (with the explicit `dscp` and our TCP
/// `port`) to the peer's next hop, if a frame came from it; else the segment is dropped (TCP
/// sends it again) and the next hop asked for by ARP. Nothing goes out while the address
/// may not be used.
fn send_segment(
    tx: impl TxToken,
    (from, dscp, port): (&LocalEnd<'_>, u8, u16),
    out: &Outgoing,
    payload: &[u8],
    (neighbors, sums): (&mut Neighbors, &ChecksumCapabilities),
    at: Instant,
) {
    if !from.usable {
        return;
    }
    let me = from.me;
    let peer = *out.peer.ip();
    let hop = next_hop(peer, me.ip, me.netmask, me.gateway);
    // A connection's segments keep its peer's entry as T->O's do; a SYN's answer or a RST
    // (to whatever address a segment claimed) does not.
    let keep = !out.flags.syn && !out.flags.rst;
    let mut lookup = |ip| {
        if keep {
            neighbors.get(ip)
        } else {
            neighbors.peek(ip)
        }
    };
    let Some(to) = lookup(peer).or_else(|| lookup(hop)) else {
        if neighbors.may_ask(at) {
            let mut request = [0u8; ARP_REQUEST_LEN];
            frame::write_arp_request(&mut request, (from.mac, me.ip), hop);
            send_copy(tx, &request);
        }
        return;
    };
    let hop = Hop {
        from: (from.mac, me.ip),
        to,
        dscp,
        port,
    };
    let len = tcp_frames::frame_len(out, payload.len());
    tx.consume(len, |buf| tcp_frames::write(buf, &hop, out, payload, sums));
}
