//! The module's MS and NS LEDs (Introduction, Figure 1) as states the profile keeps and
//! logs at each transition (host and QEMU boards have no LEDs; the Nucleo board's
//! indicators follow the identity status and the connection table).

use core::net::Ipv4Addr;

use enip_stack::config::MAX_CONNECTIONS;
use enip_stack::device::{CloseReason, ConnectionEvent, ConnectionInfo, ConnectionPoints, Kind};

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
    /// Red flashing: a connection with the module as target timed out; left when every
    /// timed-out connection is established again or on reset.
    TimedOut,
}

/// A connection as the NS LED tells it apart: "re-established" is a new connection from
/// the same originator, of the same kind, to the same connection points.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Lost {
    originator: Ipv4Addr,
    kind: Kind,
    points: ConnectionPoints,
}

impl Lost {
    fn of(c: &ConnectionInfo) -> Self {
        Lost {
            originator: c.originator,
            kind: c.kind,
            points: c.points,
        }
    }
}

/// The two LEDs and what they are computed from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Leds {
    connections: u32,
    /// The I/O connections that timed out and are not re-established yet.
    timed_out: [Option<Lost>; MAX_CONNECTIONS],
    /// More timed out than the list holds: only a reset leaves red flashing.
    overflow: bool,
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
            timed_out: [None; MAX_CONNECTIONS],
            overflow: false,
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

    /// Follows the connections: an I/O connection that timed out keeps NS red flashing
    /// until the same originator opens the same kind of connection to the same points.
    pub fn connection_event(&mut self, event: &ConnectionEvent) {
        match event {
            ConnectionEvent::Opened(c) => {
                self.connections = self.connections.saturating_add(1);
                let back = Lost::of(c);
                for slot in self.timed_out.iter_mut() {
                    if *slot == Some(back) {
                        *slot = None;
                    }
                }
            }
            ConnectionEvent::Closed(c, reason) => {
                self.connections = self.connections.saturating_sub(1);
                if *reason == CloseReason::Timeout && c.kind != Kind::Explicit {
                    self.lost(Lost::of(c));
                }
            }
            _ => {}
        }
        self.show_network();
    }

    /// The module was reset (Identity Reset): the timed-out connections are forgotten.
    pub fn reset(&mut self) {
        self.timed_out = [None; MAX_CONNECTIONS];
        self.overflow = false;
        self.show_network();
    }

    /// Notes a timed-out connection (once).
    fn lost(&mut self, lost: Lost) {
        if self.timed_out.contains(&Some(lost)) {
            return;
        }
        match self.timed_out.iter_mut().find(|s| s.is_none()) {
            Some(slot) => *slot = Some(lost),
            None => self.overflow = true,
        }
    }

    /// Recomputes NS and logs a change.
    fn show_network(&mut self) {
        let timed_out = self.overflow || self.timed_out.iter().any(Option::is_some);
        let ns = match (self.connections, timed_out) {
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
