//! Class codes of the objects the stack implements.

/// Identity object.
pub const IDENTITY: u16 = 0x01;
/// Message Router object.
pub const MESSAGE_ROUTER: u16 = 0x02;
/// Assembly object.
pub const ASSEMBLY: u16 = 0x04;
/// Connection Manager object.
pub const CONNECTION_MANAGER: u16 = 0x06;
/// QoS object.
pub const QOS: u16 = 0x48;
/// TCP/IP Interface object.
pub const TCP_IP_INTERFACE: u16 = 0xF5;
/// Ethernet Link object.
pub const ETHERNET_LINK: u16 = 0xF6;
/// LLDP Management object.
pub const LLDP_MANAGEMENT: u16 = 0x109;
/// LLDP Data Table object.
pub const LLDP_DATA_TABLE: u16 = 0x10A;
