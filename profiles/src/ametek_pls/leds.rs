//! The module's MS and NS LEDs (Introduction, Figure 1) as states the profile keeps and
//! logs at each transition (host and QEMU boards have no LEDs; the Nucleo board's
//! indicators follow the identity status and the connection table).

use enip_stack::device::Kind;
use enip_stack::device::{CloseReason, ConnectionEvent};

/// Module Status (Figure 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModuleStatus {
    /// Green: operating correctly (a program was written or loaded).
    Operating,
    /// Green flashing: standby, not configured.
    Standby,
    /// Red flashing: a recoverable fault (here: the resolver fault).
    RecoverableFault,
}

/// Network Status (Figure 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NetworkStatus {
    /// Green: at least one EtherNet/IP connection.
    Connected,
    /// Green flashing: no connection.
    NoConnection,
    /// Red flashing: a connection with the module as target timed out; left when a
    /// connection is established again or on reset.
    TimedOut,
}

/// The two LEDs and what they are computed from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Leds {
    connections: u32,
    timed_out: bool,
    ms: ModuleStatus,
    ns: NetworkStatus,
}

impl Default for Leds {
    fn default() -> Self {
        Self::new()
    }
}

impl Leds {
    /// At power-up: standby, no connection.
    pub const fn new() -> Self {
        Leds {
            connections: 0,
            timed_out: false,
            ms: ModuleStatus::Standby,
            ns: NetworkStatus::NoConnection,
        }
    }

    /// Module Status now.
    pub fn module_status(&self) -> ModuleStatus {
        self.ms
    }

    /// Network Status now.
    pub fn network_status(&self) -> NetworkStatus {
        self.ns
    }

    /// Follows the connections.
    pub fn connection_event(&mut self, event: &ConnectionEvent) {
        match event {
            ConnectionEvent::Opened(_) => {
                self.connections = self.connections.saturating_add(1);
                self.timed_out = false;
            }
            ConnectionEvent::Closed(c, reason) => {
                self.connections = self.connections.saturating_sub(1);
                if *reason == CloseReason::Timeout && c.kind != Kind::Explicit {
                    self.timed_out = true;
                }
            }
            _ => {}
        }
        let ns = match (self.connections, self.timed_out) {
            (_, true) => NetworkStatus::TimedOut,
            (0, false) => NetworkStatus::NoConnection,
            _ => NetworkStatus::Connected,
        };
        if ns != self.ns {
            info!("PLS: NS LED {}", describe_ns(ns));
            self.ns = ns;
        }
    }

    /// Follows the module's state: configured, resolver fault.
    pub fn module(&mut self, configured: bool, fault: bool) {
        let ms = match (fault, configured) {
            (true, _) => ModuleStatus::RecoverableFault,
            (false, true) => ModuleStatus::Operating,
            (false, false) => ModuleStatus::Standby,
        };
        if ms != self.ms {
            info!("PLS: MS LED {}", describe_ms(ms));
            self.ms = ms;
        }
    }
}

fn describe_ms(ms: ModuleStatus) -> &'static str {
    match ms {
        ModuleStatus::Operating => "green (operating)",
        ModuleStatus::Standby => "flashing green (standby, not configured)",
        ModuleStatus::RecoverableFault => "flashing red (resolver fault)",
    }
}

fn describe_ns(ns: NetworkStatus) -> &'static str {
    match ns {
        NetworkStatus::Connected => "green (connection established)",
        NetworkStatus::NoConnection => "flashing green (no connection)",
        NetworkStatus::TimedOut => "flashing red (a connection timed out)",
    }
}
