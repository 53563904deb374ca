//! The interface configuration the runtime reports to the stack (TCP/IP and Ethernet Link).

use core::net::Ipv4Addr;

/// Addresses of the network interface, as configured statically or by DHCP.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NetworkConfig {
    /// The interface's IPv4 address.
    pub ip: Ipv4Addr,
    /// Network mask.
    pub netmask: Ipv4Addr,
    /// Default gateway (0.0.0.0 when none).
    pub gateway: Ipv4Addr,
    /// Primary and secondary name servers (0.0.0.0 when none).
    pub dns: [Ipv4Addr; 2],
    /// The Ethernet MAC address.
    pub mac: [u8; 6],
    /// True when the address came from DHCP.
    pub dhcp: bool,
    /// Link speed in Mbit/s (Ethernet Link attribute 1).
    pub link_speed_mbps: u32,
    /// Whether the link is up.
    pub link_up: bool,
}

impl NetworkConfig {
    /// A static configuration with no gateway or DNS, a 100 Mbit/s link that is up.
    pub const fn new_static(ip: Ipv4Addr, netmask: Ipv4Addr, mac: [u8; 6]) -> Self {
        NetworkConfig {
            ip,
            netmask,
            gateway: Ipv4Addr::UNSPECIFIED,
            dns: [Ipv4Addr::UNSPECIFIED, Ipv4Addr::UNSPECIFIED],
            mac,
            dhcp: false,
            link_speed_mbps: 100,
            link_up: true,
        }
    }

    /// True if `addr` is the limited broadcast or this subnet's directed broadcast.
    pub fn is_broadcast(&self, addr: Ipv4Addr) -> bool {
        let mask = u32::from(self.netmask);
        addr == Ipv4Addr::BROADCAST
            || (mask != u32::MAX && u32::from(addr) == (u32::from(self.ip) & mask) | !mask)
    }
}
