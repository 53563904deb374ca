//! The multicast settings of TCP/IP attributes 8 and 9, as the TCP/IP object and a device
//! that keeps them itself ([`crate::Device::multicast`]) both speak them.

use core::net::Ipv4Addr;

/// Multicast configuration (attribute 9).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MulticastConfig {
    /// 0: default allocation algorithm; 1: the configured range below.
    pub alloc_control: u8,
    /// Number of multicast addresses (alloc control 1).
    pub num_mcast: u16,
    /// First multicast address (alloc control 1).
    pub start: Ipv4Addr,
}

/// TCP/IP attributes 8 and 9 as a device keeps them (see [`crate::Device::multicast`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Multicast {
    /// Attribute 8: TTL of multicast T->O datagrams.
    pub ttl: u8,
    /// Attribute 9: allocation control, number of addresses and the first address in use.
    pub config: MulticastConfig,
}
