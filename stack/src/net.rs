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

    /// True if `addr` is the limited broadcast or this subnet's directed broadcast (a /31
    /// or /32 subnet has none: on a /31 link both addresses are hosts, RFC 3021).
    pub fn is_broadcast(&self, addr: Ipv4Addr) -> bool {
        addr == Ipv4Addr::BROADCAST || self.host_part(addr) == Some(!u32::from(self.netmask))
    }

    /// True if `addr` is this subnet's network address, its host part zero (a /31 or /32
    /// subnet has none).
    pub fn is_network_address(&self, addr: Ipv4Addr) -> bool {
        self.host_part(addr) == Some(0)
    }

    /// The host part of `addr` if it is in this subnet and the subnet has a network and a
    /// broadcast address (a prefix of 30 bits or less).
    fn host_part(&self, addr: Ipv4Addr) -> Option<u32> {
        let mask = u32::from(self.netmask);
        let addr = u32::from(addr);
        (mask < 0xFFFF_FFFE && addr & mask == u32::from(self.ip) & mask).then_some(addr & !mask)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn on(ip: [u8; 4], prefix: u32) -> NetworkConfig {
        let mask = u32::MAX.checked_shl(32 - prefix).unwrap_or(0);
        NetworkConfig::new_static(Ipv4Addr::from(ip), Ipv4Addr::from(mask), [0; 6])
    }

    #[test]
    fn a_subnets_broadcast_and_network_addresses() {
        let net = on([198, 18, 0, 2], 24);
        assert!(net.is_broadcast(Ipv4Addr::new(198, 18, 0, 255)));
        assert!(net.is_broadcast(Ipv4Addr::BROADCAST));
        assert!(net.is_network_address(Ipv4Addr::new(198, 18, 0, 0)));
        for host in [
            [198, 18, 0, 1],
            [198, 18, 0, 2],
            [198, 18, 1, 255],
            [10, 1, 5, 0],
        ] {
            let host = Ipv4Addr::from(host);
            assert!(
                !net.is_broadcast(host) && !net.is_network_address(host),
                "{host}"
            );
        }
        // A /31 link has two hosts and neither address; a /32 has only the host.
        for (me, other) in [
            ([198, 18, 0, 1], [198, 18, 0, 0]),
            ([198, 18, 0, 0], [198, 18, 0, 1]),
        ] {
            let net = on(me, 31);
            for addr in [me, other].map(Ipv4Addr::from) {
                assert!(
                    !net.is_broadcast(addr) && !net.is_network_address(addr),
                    "{addr}"
                );
            }
        }
        let single = on([198, 18, 0, 7], 32);
        assert!(!single.is_broadcast(Ipv4Addr::new(198, 18, 0, 7)));
    }
}
