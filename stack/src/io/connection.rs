//! One entry of the connection table and its per-direction state. Its timing (watchdog,
//! last activity, production deadline, waiting trigger) is not here: the table keeps it
//! ([`super::table::ConnectionTable`]), changed only through the table's intents.

use core::net::{Ipv4Addr, SocketAddrV4};

use crate::device::{ConnectionInfo, ConnectionPoints, Kind, Trigger};
use crate::time::Duration;
use crate::wire::forward_open::Triad;

/// O->T (consuming) state of a Class 1 connection.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Consumer {
    /// Assembly instance the data goes to (a heartbeat point for input/listen only).
    pub instance: u16,
    /// Application data bytes expected.
    pub size: u16,
    /// True if the data carries the 32-bit run/idle header.
    pub run_idle: bool,
    /// Last 16-bit sequence count applied.
    pub last_sequence: Option<u16>,
    /// Last 32-bit encapsulation sequence number seen.
    pub last_encap_sequence: Option<u32>,
    /// Last run/idle state reported to the device.
    pub run: bool,
}

/// T->O (producing) state of a Class 1 connection.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Producer {
    /// Assembly instance produced.
    pub instance: u16,
    /// Application data bytes produced.
    pub size: u16,
    /// Where the datagrams go (originator or multicast group, port 2222).
    pub destination: SocketAddrV4,
    /// Production inhibit time: the least time between a production that carried a trigger
    /// and the next triggered one.
    pub inhibit: Duration,
    /// What makes it produce.
    pub trigger: Trigger,
    /// 32-bit encapsulation sequence number of the last datagram.
    pub encap_sequence: u32,
    /// 16-bit CIP sequence count of the last new data.
    pub sequence: u16,
    /// DSCP of its packets, chosen at the open from the T->O priority (QoS object).
    pub dscp: u8,
    /// The T->O priority it was opened with (a connection joining its multicast must match).
    pub priority: u8,
    /// True if it was opened with a variable T->O size (a joining connection must match).
    pub variable: bool,
}

/// Direction-specific state.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Transport {
    /// Class 1 implicit I/O. A connection without a producer of its own follows another's
    /// multicast production (same T->O ID): a listen-only one always, another kind when it
    /// joined a production already going to the group.
    Class1 {
        /// O->T state.
        consumer: Consumer,
        /// T->O state, unless it follows another connection's producer.
        producer: Option<Producer>,
    },
    /// Class 3 connected explicit messaging on the session that opened it.
    Class3 {
        /// Sequence count of the last request executed (its reply is cached in the table).
        last_sequence: Option<u16>,
    },
}

/// One open connection.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Connection {
    /// Application relationship.
    pub kind: Kind,
    /// The originator's triad.
    pub triad: Triad,
    /// The originator's IP address.
    pub originator: Ipv4Addr,
    /// The assembly instances of its path.
    pub points: ConnectionPoints,
    /// Socket index of the encapsulation session whose Forward_Open opened it.
    pub socket: u8,
    /// O->T connection ID (chosen here).
    pub o_t_id: u32,
    /// T->O connection ID.
    pub t_o_id: u32,
    /// O->T packet interval, microseconds.
    pub o_t_rpi: u32,
    /// T->O packet interval, microseconds.
    pub t_o_rpi: u32,
    /// Inactivity timeout: O->T RPI x multiplier.
    pub timeout: Duration,
    /// Direction-specific state.
    pub transport: Transport,
}

impl Connection {
    /// The Class 1 producer, if it has its own.
    pub fn producer(&self) -> Option<&Producer> {
        match &self.transport {
            Transport::Class1 { producer, .. } => producer.as_ref(),
            Transport::Class3 { .. } => None,
        }
    }
    /// The Class 1 consumer.
    pub fn consumer(&self) -> Option<&Consumer> {
        match &self.transport {
            Transport::Class1 { consumer, .. } => Some(consumer),
            Transport::Class3 { .. } => None,
        }
    }
    /// True if its T->O data goes to a multicast group.
    pub fn produces_multicast(&self) -> bool {
        self.producer()
            .is_some_and(|p| p.destination.ip().is_multicast())
    }
    /// True if it receives another connection's multicast production (same T->O ID) instead
    /// of producing its own.
    pub fn follows(&self) -> bool {
        matches!(self.transport, Transport::Class1 { producer: None, .. })
    }
}

impl Connection {
    /// The device's description of this connection, in table slot `slot`.
    pub fn info(&self, slot: usize) -> ConnectionInfo {
        ConnectionInfo {
            slot,
            kind: self.kind,
            triad: self.triad,
            originator: self.originator,
            points: self.points,
            o_t_id: self.o_t_id,
            t_o_id: self.t_o_id,
            o_t_rpi_us: self.o_t_rpi,
            t_o_rpi_us: self.t_o_rpi,
            multicast: self.produces_multicast() || self.follows(),
        }
    }
}
