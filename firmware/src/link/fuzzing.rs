//! What the fuzz targets reach of the link task (cargo feature `fuzzing`, for `fuzz/` only;
//! not an interface for applications): the look at every received frame ([`inspect`]) and
//! the neighbour table its senders go to ([`NeighborTable`]).

use core::net::{Ipv4Addr, SocketAddrV4};
use core::ops::Range;

use enip_stack::Instant;
use smoltcp::phy::ChecksumCapabilities;

use super::frame;
use super::neighbors::Neighbors;

/// Hosts the neighbour table remembers.
pub const NEIGHBORS: usize = super::neighbors::NEIGHBORS;

/// What [`inspect`] found: the sender (IPv4 address and the MAC address its frame came
/// from), and an O->T datagram's source and where its UDP payload lies in the frame.
pub type Found = (
    Option<(Ipv4Addr, [u8; 6])>,
    Option<(SocketAddrV4, Range<usize>)>,
);

/// The link task's look at a received `frame` for an adapter at `me`, every checksum
/// verified in software.
pub fn inspect(frame: &[u8], me: Ipv4Addr) -> Found {
    let seen = frame::inspect(frame, me, &ChecksumCapabilities::default());
    (seen.sender, seen.o_t)
}

/// The link task's neighbour table: IPv4 host -> the MAC address its frames came from.
#[derive(Debug, Default)]
pub struct NeighborTable(Neighbors);

impl NeighborTable {
    /// Notes that `ip`'s frames come from `mac`.
    pub fn learn(&mut self, ip: Ipv4Addr, mac: [u8; 6]) {
        self.0.learn(ip, mac);
    }

    /// The MAC address of `ip`'s frames, if any came.
    pub fn get(&mut self, ip: Ipv4Addr) -> Option<[u8; 6]> {
        self.0.get(ip)
    }

    /// Whether an ARP request may go out at `now` (rate limit).
    pub fn may_ask(&mut self, now: Instant) -> bool {
        self.0.may_ask(now)
    }
}
