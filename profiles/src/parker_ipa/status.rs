//! The CIP status parameters P37424-P37439 (Table 2, p.5; the CIP report, p.4-5), kept
//! live from the connection events, the Forward_Open admission and the requests.
//!
//! Semantics where the manual is terse (digest section 7, \[R\]): P37424 is the command
//! stream of an open Class 3 connection ([`CLASS3_STREAM`], 0 without one); P37425 counts
//! Class 1 O->T packets applied, P37426 explicit requests to the controller (A4: "Received"
//! in the report); P37427 is always 0 (requests are handled at once); P37428 counts open
//! connections; P37429 is the Class 1 originator's IPv4, first octet most significant
//! (A11), set at every Class 1 Forward_Open the profile sees while no Class 1 connection
//! runs (a second scanner refused with 0x0106/0x0113 leaves the running connection's
//! client); P37430 counts those attempts (A12); P37431/P37432 are the T->O/O->T intervals in ms; P37433 is Table 3's status;
//! P37434 (groups in use) is stored with the configuration; P37435-P37437 the last
//! configuration entry (R7.3); P37438-P37439 read 0.

use core::net::Ipv4Addr;

use super::ioconfig::{status, Entry};

/// The ACR command stream a Class 3 connection is given: the value of the manual's
/// example 2 (p.5, "Class3 Message Stream = 2" with a Class 3 connection present).
pub const CLASS3_STREAM: i32 = 2;

/// Index of each status parameter from P37424.
pub mod index {
    /// P37424 Class 3 message stream.
    pub const CLASS3_STREAM: usize = 0;
    /// P37425 Class 1 messages (received).
    pub const CLASS1_MESSAGES: usize = 1;
    /// P37426 Class 3 messages (received).
    pub const CLASS3_MESSAGES: usize = 2;
    /// P37427 Class 3 messages queued.
    pub const QUEUED: usize = 3;
    /// P37428 total connections.
    pub const CONNECTIONS: usize = 4;
    /// P37429 client IP address.
    pub const CLIENT_IP: usize = 5;
    /// P37430 Class 1 connection instance.
    pub const INSTANCE: usize = 6;
    /// P37431 producing interval (ms).
    pub const PRODUCING_MS: usize = 7;
    /// P37432 consuming interval (ms).
    pub const CONSUMING_MS: usize = 8;
    /// P37433 Class 1 connection status.
    pub const STATUS: usize = 9;
    /// P37435 last configuration entry group.
    pub const ENTRY_GROUP: usize = 11;
    /// P37436 last configuration entry parameter.
    pub const ENTRY_PARAMETER: usize = 12;
    /// P37437 last configuration entry length.
    pub const ENTRY_LENGTH: usize = 13;
}

/// The live state behind the status parameters.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct CipStatus {
    /// Class 1 O->T packets applied since power-up.
    pub class1_messages: u32,
    /// Explicit requests to the controller since power-up.
    pub class3_messages: u32,
    /// The open Class 1 connection's table slot.
    pub class1_slot: Option<usize>,
    /// Open Class 3 connections.
    pub class3_open: u32,
    /// The last Class 1 originator.
    pub client_ip: u32,
    /// Class 1 Forward_Open attempts seen.
    pub attempts: u32,
    /// T->O interval of the last Class 1 connection, ms.
    pub producing_ms: u32,
    /// O->T interval of the last Class 1 connection, ms.
    pub consuming_ms: u32,
    /// Table 3 status.
    pub status: i32,
    /// The last configuration entry.
    pub entry: Entry,
}

impl CipStatus {
    /// A Class 1 Forward_Open from `originator` reached the profile.
    pub fn attempt(&mut self, originator: Ipv4Addr) {
        self.client_ip = u32::from(originator);
        self.attempts = self.attempts.wrapping_add(1);
    }
    /// The Class 1 connection in `slot` opened with these intervals (µs).
    pub fn opened(&mut self, slot: usize, t_o_us: u32, o_t_us: u32) {
        self.class1_slot = Some(slot);
        self.producing_ms = t_o_us / 1000;
        self.consuming_ms = o_t_us / 1000;
        self.status = status::ACTIVE;
    }
    /// The Class 1 connection in `slot` closed (Forward_Close, timeout...).
    pub fn closed(&mut self, slot: usize) {
        if self.class1_slot == Some(slot) {
            self.class1_slot = None;
            self.status = status::IDLE;
        }
    }
    /// Open connections, Class 1 and Class 3.
    pub fn connections(&self) -> u32 {
        self.class3_open
            .saturating_add(u32::from(self.class1_slot.is_some()))
    }
    /// The value of status parameter P(37424 + `i`) (`groups_in_use` is P37434).
    pub fn param(&self, i: usize, groups_in_use: i32) -> i32 {
        match i {
            index::CLASS3_STREAM if self.class3_open > 0 => CLASS3_STREAM,
            index::CLASS1_MESSAGES => self.class1_messages as i32,
            index::CLASS3_MESSAGES => self.class3_messages as i32,
            index::CONNECTIONS => self.connections() as i32,
            index::CLIENT_IP => self.client_ip as i32,
            index::INSTANCE => self.attempts as i32,
            index::PRODUCING_MS => self.producing_ms as i32,
            index::CONSUMING_MS => self.consuming_ms as i32,
            index::STATUS => self.status,
            super::params::GROUPS_IN_USE_INDEX => groups_in_use,
            index::ENTRY_GROUP => self.entry.group,
            index::ENTRY_PARAMETER => self.entry.parameter,
            index::ENTRY_LENGTH => self.entry.length,
            _ => 0,
        }
    }
}
