//! Where a request came from: what a vendor service or attribute handler may ask of it.

use core::net::SocketAddrV4;

use crate::time::Instant;

/// How a request reached the Message Router.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Via {
    /// Unconnected (UCMM): SendRRData, or a datagram on UDP 44818.
    Unconnected,
    /// Over the Class 3 connection in this table slot (SendUnitData).
    Connected {
        /// The connection's table slot (as in [`crate::device::ConnectionInfo::slot`]).
        slot: usize,
    },
}

/// The context of one explicit request.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RequestContext {
    /// Unconnected or over which Class 3 connection.
    pub via: Via,
    /// The encapsulation session's peer (IP address and TCP port), when it came over TCP.
    pub peer: Option<SocketAddrV4>,
    /// The time the request is handled.
    pub now: Instant,
}

impl RequestContext {
    /// A request that came unconnected from `peer` at `now`.
    pub const fn unconnected(peer: Option<SocketAddrV4>, now: Instant) -> Self {
        RequestContext {
            via: Via::Unconnected,
            peer,
            now,
        }
    }
    /// True if the request came over a Class 3 connection.
    pub const fn is_connected(&self) -> bool {
        matches!(self.via, Via::Connected { .. })
    }
}
