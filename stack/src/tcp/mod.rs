//! The encapsulation port's TCP (RFC 9293), sans-IO: a server of `N` connections on port
//! 44818 that hands each connection's byte stream to the adapter ([`TcpApp`]) and keeps its
//! replies until they are acknowledged. A runtime that owns the Ethernet driver (the
//! firmware's link task) parses each segment for the port into a [`Segment`], calls
//! [`TcpServer::process`], and sends what [`TcpServer::transmit`] hands out; it calls
//! [`TcpServer::poll`] at [`TcpServer::deadline`]. A runtime on a kernel's sockets does not
//! use it: the kernel's TCP feeds the adapter there.
//!
//! What it does, and leaves out, for a server of request and reply:
//! - passive open only; a SYN finds a free connection; with none free, it is answered with a
//!   SYN cookie if one is half-open (RFC 4987 3.6: a SYN flood holds the free connections
//!   half-open, and a client's ACK proving its cookie opens one where a connection is free
//!   again, else in the place of the oldest half-open one) or one has a peer silent for
//!   [`WRITE_TIMEOUT`] (reset for a client that proves its cookie: a SYN alone evicts
//!   nothing), else refused with a RST; every initial sequence number is a cookie, so a
//!   handshake completes even after its half-open connection was dropped;
//! - data is taken in order only (a segment ahead of the next expected byte is answered with
//!   an ACK and dropped, as is one the replies have no room after); no window scaling, SACK
//!   or timestamps; the maximum segment size is announced and honoured;
//! - replies are retransmitted from the oldest unacknowledged byte (RFC 6298 timer, Karn's
//!   rule); a peer that sends nothing for [`GIVE_UP`] while they wait loses its connection
//!   (RFC 1122 4.2.3.5), and so does one that keeps its window closed for
//!   [`WRITE_TIMEOUT`] (a client that stops reading), or one silent for that long when a
//!   new client finds every connection taken;
//! - RST, SYN and ACK checks of RFC 5961 (an in-window RST, any SYN on an open connection,
//!   an ACK older than the peer's largest window before the oldest unacknowledged byte, or
//!   one of what was not sent, gets a challenge ACK, and the segment goes no further),
//!   challenge ACKs and the ACKs of out-of-window segments without data throttled to one per
//!   connection each 500 ms (its section 7); a connection half-open for [`HALF_OPEN`] is
//!   dropped (without a RST);
//! - the adapter closes when the peer does (no CLOSE-WAIT), and a connection is free again
//!   once both FINs are acknowledged (no TIME-WAIT: a late FIN finds no connection and is
//!   answered with a RST); a close the peer does not complete within [`LINGER`] is reset.

mod app;
mod conn;
mod cookie;
#[cfg(test)]
mod flood_tests;
#[cfg(test)]
mod peer_tests;
mod seq;
mod server;
mod siphash;
#[cfg(test)]
mod tests;

use core::net::SocketAddrV4;

use crate::{Duration, Instant, SocketId, TcpOutcome};

pub use server::{closed_port_answer, TcpServer, Transmit};

/// Longest wait for a peer that sends nothing while replies or our FIN wait for it (RFC 1122
/// 4.2.3.5's R2 for data, at least 100 s: a link down for a switch's restart or a spanning
/// tree's reconvergence ends no session, unless a new client needs its place after
/// [`WRITE_TIMEOUT`]): then the connection is reset.
pub const GIVE_UP: Duration = Duration::from_secs(100);
/// Longest wait for a peer to open its closed window for replies that wait (a client that
/// stops reading; answering the window probes does not count): then the connection is
/// reset; and how long a silent peer keeps its connection when a new client finds every
/// one taken. The boards on a kernel's TCP close a session whose replies find no room in
/// its socket for as long.
pub const WRITE_TIMEOUT: Duration = Duration::from_secs(5);
/// Longest wait for the peer to complete a close: then the connection is reset.
pub const LINGER: Duration = Duration::from_secs(2);
/// Longest a connection may stay half-open (SYN received, waiting for the handshake's ACK).
pub const HALF_OPEN: Duration = Duration::from_millis(300);
/// The maximum segment size announced: an Ethernet frame's 1500-byte IPv4 payload less the
/// 20-byte IPv4 and TCP headers.
pub const MSS: u16 = 1460;
/// The smallest maximum segment size taken from a peer (a smaller one is raised to it, as
/// Linux does: a tiny one would make a reply a flood of segments).
const MIN_MSS: u16 = 48;
/// The peer's maximum segment size when its SYN names none (RFC 9293 3.7.1).
pub const DEFAULT_MSS: u16 = 536;
/// The first retransmission timeout, before any round trip was measured (RFC 6298 2.1).
pub const INITIAL_RTO: Duration = Duration::from_secs(1);
/// The shortest retransmission timeout (a LAN's round trip is far shorter; a peer's delayed
/// ACK is not).
pub const MIN_RTO: Duration = Duration::from_millis(200);

/// Control flags of a segment.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Flags {
    /// SYN.
    pub syn: bool,
    /// ACK: the acknowledgment number is valid.
    pub ack: bool,
    /// FIN.
    pub fin: bool,
    /// RST.
    pub rst: bool,
    /// PSH.
    pub psh: bool,
}

/// A segment received for the port, its headers parsed and its checksum verified.
#[derive(Clone, Copy, Debug)]
pub struct Segment<'a> {
    /// The sender's address and port.
    pub peer: SocketAddrV4,
    /// Sequence number.
    pub seq: u32,
    /// Acknowledgment number (meaningful with [`Flags::ack`]).
    pub ack: u32,
    /// Control flags.
    pub flags: Flags,
    /// The window the sender offers.
    pub window: u16,
    /// The maximum segment size option, if the segment carries one.
    pub mss: Option<u16>,
    /// The data.
    pub payload: &'a [u8],
}

impl Segment<'_> {
    /// Sequence space the segment takes: its data, and one each for SYN and FIN.
    fn len(&self) -> u32 {
        let data = u32::try_from(self.payload.len()).unwrap_or(u32::MAX);
        data.saturating_add(u32::from(self.flags.syn))
            .saturating_add(u32::from(self.flags.fin))
    }

    /// The segment size the sender takes (its SYN's option, else RFC 9293's default), within
    /// [`MIN_MSS`] and our own.
    fn peer_mss(&self) -> u16 {
        self.mss.unwrap_or(DEFAULT_MSS).clamp(MIN_MSS, MSS)
    }
}

/// A segment to send from the port to [`Self::peer`]; its data is handed beside it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Outgoing {
    /// The receiver's address and port.
    pub peer: SocketAddrV4,
    /// Sequence number.
    pub seq: u32,
    /// Acknowledgment number (sent with [`Flags::ack`]).
    pub ack: u32,
    /// Control flags.
    pub flags: Flags,
    /// The window offered.
    pub window: u16,
    /// The maximum segment size option (on a SYN).
    pub mss: Option<u16>,
}

/// What the server hands a connection's byte stream to: the adapter ([`crate::Adapter`]
/// implements it), or a test's stand-in.
pub trait TcpApp {
    /// Connection `id` from `peer` is established.
    fn accepted(&mut self, id: SocketId, peer: SocketAddrV4, now: Instant);
    /// Bytes `data` arrived on `id`, in order; a reply goes into `reply` (as
    /// [`crate::Adapter::tcp_receive`]).
    fn receive(&mut self, id: SocketId, data: &[u8], now: Instant, reply: &mut [u8]) -> TcpOutcome;
    /// Connection `id` ended, by either side or a timeout.
    fn closed(&mut self, id: SocketId, now: Instant);
    /// When connection `id` closes if nothing arrives until then (the encapsulation
    /// inactivity timeout).
    fn idle_deadline(&self, id: SocketId) -> Option<Instant>;
}
