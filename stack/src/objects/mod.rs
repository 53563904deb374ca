//! The standard objects the stack serves: Identity, Message Router, Assembly, Connection
//! Manager, TCP/IP Interface, Ethernet Link, QoS, LLDP Management and LLDP Data Table, the device's declared vendor classes, and the
//! dispatcher (`router`) that sends each request to its object. They sit above the
//! connections ([`crate::io`]): the Connection Manager opens and closes them, and Identity
//! and Assembly look at them (status bits, output ownership).

pub(crate) mod assembly;
pub(crate) mod connection_manager;
pub(crate) mod ethernet_link;
pub(crate) mod identity;
pub mod link_counters;
pub(crate) mod lldp_data_table;
pub(crate) mod lldp_management;
pub(crate) mod message_router;
pub(crate) mod qos;
pub(crate) mod router;
#[cfg(feature = "cip-security")]
pub mod security;
pub(crate) mod serve;
pub(crate) mod tcpip;
pub(crate) mod tcpip_nv;
pub(crate) mod vendor;

pub use connection_manager::Counters as ConnectionManagerCounters;
pub use ethernet_link::LinkState;
pub use link_counters::{InterfaceCounters, LinkCounters, MediaCounters};
pub use lldp_data_table::{Neighbor, NeighborTable};
pub use lldp_management::{LldpConfig, LldpDue, LldpState};
pub use qos::{Dscp, QosState};
pub use tcpip::TcpIpState;
pub use tcpip_nv::InterfaceConfig;

use crate::cip::context::RequestContext;
use crate::device::Device;
use crate::io::open::Origin;
use crate::io::ConnectionTable;
use crate::net::NetworkConfig;
use crate::nv::NvStore;
use crate::wire::cpf::SockAddrRepr;

/// State the stack's own objects keep between requests.
#[derive(Debug, Clone)]
pub struct ObjectState {
    /// TCP/IP Interface object settings.
    pub tcpip: tcpip::TcpIpState,
    /// Address Conflict Detection as the TCP/IP object reports it.
    pub acd: crate::acd::AcdState,
    /// Ethernet Link object counters and settings.
    pub link: ethernet_link::LinkState,
    /// Connection Manager request and reject counters.
    pub connection_manager: connection_manager::Counters,
    /// LLDP Management and LLDP Data Table objects: the LLDP agent.
    pub lldp: lldp_management::LldpState,
    /// QoS object: the DSCP values set and those in use.
    pub qos: qos::QosState,
    /// A Reset service was accepted: its type, for the runtime to act on once replied.
    pub pending_reset: Option<u8>,
    /// CIP Security objects (feature `cip-security`).
    #[cfg(feature = "cip-security")]
    pub security: security::SecurityState,
}

impl ObjectState {
    /// Defaults at power-up.
    pub fn new() -> Self {
        ObjectState {
            tcpip: tcpip::TcpIpState::new(),
            acd: crate::acd::AcdState::new(),
            link: ethernet_link::LinkState::new(),
            connection_manager: connection_manager::Counters::default(),
            lldp: lldp_management::LldpState::new(),
            qos: qos::QosState::new(),
            pending_reset: None,
            #[cfg(feature = "cip-security")]
            security: security::SecurityState::new(),
        }
    }
}

impl Default for ObjectState {
    fn default() -> Self {
        Self::new()
    }
}

/// Everything a service handler may look at or change.
pub(crate) struct Ctx<'a, D: Device, const C: usize> {
    pub device: &'a mut D,
    pub state: &'a mut ObjectState,
    pub net: &'a NetworkConfig,
    /// The connection table (Forward_Open, ownership, identity status).
    pub connections: &'a mut ConnectionTable<C>,
    /// Who sent the request, when it came over TCP.
    pub origin: Option<Origin>,
    /// Set by a Forward_Open whose T->O data is multicast: the reply's T->O socket address.
    pub reply_t_o_sockaddr: Option<SockAddrRepr>,
    /// Unconnected or connected, the session's peer, the time.
    pub request: RequestContext,
    /// Where settings that survive a power cycle go (none: they last until power-off).
    pub store: Option<&'a mut (dyn NvStore + 'static)>,
    /// Makes CSRs with the device key (Create_CSR), if the runtime gave one.
    #[cfg(feature = "cip-security")]
    pub csr: Option<&'a mut (dyn security::CsrSigner + 'static)>,
}

impl<D: Device, const C: usize> Ctx<'_, D, C> {
    /// Identity attribute 5: the device's bits plus what the connections contribute.
    pub(crate) fn identity_status(&self) -> u16 {
        identity::status(
            self.device.status_bits(),
            self.connections.identity_status(),
        )
    }
    /// The time the request is handled.
    pub(crate) fn now(&self) -> crate::time::Instant {
        self.request.now
    }
}
