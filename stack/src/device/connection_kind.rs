//! What a connection is to the device: its application relationship ([`Kind`]) and what
//! makes its producer send ([`Trigger`]), as a Forward_Open asks and the events report.

/// The application relationship of a connection.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Kind {
    /// Class 1, owns the output assembly it consumes.
    ExclusiveOwner,
    /// Class 1, consumes only a heartbeat.
    InputOnly,
    /// Class 1, heartbeat only, follows another connection's multicast production.
    ListenOnly,
    /// Class 3 connected explicit messaging.
    Explicit,
}

/// What makes a Class 1 producer send.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Trigger {
    /// Every RPI.
    Cyclic,
    /// On data change (reported by the device), not faster than the inhibit time; RPI otherwise.
    ChangeOfState,
    /// When the application says so, not faster than the inhibit time; RPI otherwise.
    Application,
}
