//! Address Conflict Detection (RFC 5227 with the EtherNet/IP adaptation of CIP Volume 2):
//! the ARP probe and announcement frames ([`arp`]), the sans-IO state machine of one
//! address ([`Acd`]), and what the TCP/IP Interface object reports of it ([`AcdState`]:
//! capability bit 7, status bits 6 and 7, attributes 10 and 11, the last two saved in the
//! non-volatile store).
//!
//! The runtime that owns the Ethernet driver runs [`Acd`] (the firmware's link task); a
//! runtime on a kernel's sockets leaves ARP to the kernel and reports no capability.

pub mod arp;
mod machine;
mod record;

pub use arp::{Arp, ArpFrame, ARP_FRAME_LEN};
pub use machine::{
    Acd, Phase, Verdict, ANNOUNCE_INTERVAL, ANNOUNCE_NUM, ANNOUNCE_WAIT, DEFEND_INTERVAL,
    PROBE_MAX, PROBE_MIN, PROBE_NUM, PROBE_WAIT,
};
pub use record::{AcdSettings, Activity, LastConflict, LAST_CONFLICT_LEN};

/// What the TCP/IP Interface object shows of Address Conflict Detection.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AcdState {
    /// The runtime detects conflicts (capability bit 7); false on a kernel's sockets.
    pub capable: bool,
    /// Attributes 10 and 11 (10 as set: it applies at the next start).
    pub settings: AcdSettings,
    /// A conflict was detected since start (status bit 6, AcdStatus).
    pub conflict: bool,
    /// The address is not used because of a conflict (status bit 7, AcdFault).
    pub fault: bool,
    /// The runtime was told to skip detection in this run ([`crate::Adapter::skip_acd`]).
    pub(crate) skipped: bool,
    /// Attribute 11 as last saved, to save it only when it says something new.
    pub(crate) saved: LastConflict,
}

impl AcdState {
    /// At power-up: not capable until the runtime says so, factory settings.
    pub const fn new() -> Self {
        AcdState {
            capable: false,
            settings: AcdSettings::DEFAULT,
            conflict: false,
            fault: false,
            skipped: false,
            saved: LastConflict::NONE,
        }
    }
}

impl Default for AcdState {
    fn default() -> Self {
        Self::new()
    }
}
