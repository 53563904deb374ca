//! What the stack tells a device about its connections: opened, closed and why, ownership
//! of the outputs, and run/idle.

use core::net::Ipv4Addr;

use super::Kind;
use crate::wire::forward_open::Triad;

/// How a connection ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CloseReason {
    /// Forward_Close from the originator.
    ForwardClose,
    /// The inactivity watchdog expired (no O->T data for multiplier x RPI).
    Timeout,
    /// The multicast production it received stopped: the last connection producing it that
    /// was not listen-only went away (a listen-only one), or that production was reconfigured
    /// away.
    Dependency,
    /// Its encapsulation session ended (Class 3).
    SessionClosed,
    /// The Identity object was reset: every connection ends.
    Reset,
    /// The size of an assembly it carries changed under it (a device reconfigured).
    Reconfigured,
}

impl CloseReason {
    /// The reason in words, for logs.
    pub const fn describe(self) -> &'static str {
        match self {
            CloseReason::ForwardClose => "Forward_Close",
            CloseReason::Timeout => "timeout (no data for multiplier x RPI)",
            CloseReason::Dependency => "its owner connection closed",
            CloseReason::SessionClosed => "its session closed",
            CloseReason::Reset => "Identity Reset",
            CloseReason::Reconfigured => "an assembly size changed",
        }
    }
}

/// The assembly instances a connection names in its path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ConnectionPoints {
    /// Configuration assembly.
    pub config: Option<u16>,
    /// Consumed (O->T) assembly or heartbeat point.
    pub consumed: Option<u16>,
    /// Produced (T->O) assembly.
    pub produced: Option<u16>,
}

/// One connection as a device sees it in its events.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ConnectionInfo {
    /// Its slot in the connection table (0..[`crate::config::MAX_CONNECTIONS`]); the same in
    /// its closed event and in [`crate::cip::context::Via::Connected`].
    pub slot: usize,
    /// Exclusive owner, input only, listen only or Class 3.
    pub kind: Kind,
    /// The originator's triad: vendor ID, originator serial and connection serial.
    pub triad: Triad,
    /// The originator's IP address.
    pub originator: Ipv4Addr,
    /// The assembly instances of its path (none for Class 3).
    pub points: ConnectionPoints,
    /// O->T connection ID.
    pub o_t_id: u32,
    /// T->O connection ID.
    pub t_o_id: u32,
    /// O->T packet interval, microseconds.
    pub o_t_rpi_us: u32,
    /// T->O packet interval, microseconds.
    pub t_o_rpi_us: u32,
    /// True if its T->O data goes to a multicast group.
    pub multicast: bool,
}

/// Connection life-cycle events the stack reports to the device.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConnectionEvent {
    /// A connection was opened (after [`crate::Device::admit`] accepted it).
    Opened(ConnectionInfo),
    /// A connection was closed, and why.
    Closed(ConnectionInfo, CloseReason),
    /// An exclusive-owner connection now owns the device's outputs.
    OwnershipGained,
    /// The last exclusive-owner connection ended.
    OwnershipLost(CloseReason),
    /// O->T data switched between Run (true) and Idle (false).
    RunIdle(bool),
}
