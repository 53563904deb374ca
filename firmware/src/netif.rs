//! The interface configuration: read from the embassy-net stack and kept current in the adapter.

use core::net::{IpAddr, Ipv4Addr, SocketAddrV4};

use embassy_futures::select::select;
use embassy_net::{HardwareAddress, IpEndpoint, Stack};
use enip_stack::{Device, NetworkConfig};

use crate::shared::{with_adapter, SharedAdapter};

/// The interface configuration of `net` now: addresses (unspecified while it has none), MAC
/// and link state, with a 100 Mbit/s link speed and `dhcp` false.
pub fn network_config(net: Stack<'_>) -> NetworkConfig {
    let mut config =
        NetworkConfig::new_static(Ipv4Addr::UNSPECIFIED, Ipv4Addr::UNSPECIFIED, mac(net));
    if let Some(v4) = net.config_v4() {
        config.ip = v4.address.address();
        config.netmask = v4.address.netmask();
        config.gateway = v4.gateway.unwrap_or(Ipv4Addr::UNSPECIFIED);
        for (slot, dns) in config.dns.iter_mut().zip(v4.dns_servers.iter()) {
            *slot = *dns;
        }
    }
    config.link_up = net.is_link_up();
    config
}

/// The Ethernet MAC address of `net` (zero on a medium without one).
fn mac(net: Stack<'_>) -> [u8; 6] {
    #[allow(unreachable_patterns)] // other media exist only with other embassy-net features
    match net.hardware_address() {
        HardwareAddress::Ethernet(addr) => addr.0,
        _ => [0; 6],
    }
}

/// Copies every change of address or link state of `net` into the adapter; the board's
/// `dhcp` flag and link speed are kept.
pub(crate) async fn track<
    D: Device,
    const S: usize,
    const C: usize,
    const F: usize,
    const L: usize,
>(
    net: Stack<'_>,
    adapter: &SharedAdapter<D, S, C, F, L>,
) -> ! {
    loop {
        let now = network_config(net);
        with_adapter(adapter, |a| {
            let old = *a.network();
            if old.ip != now.ip || old.link_up != now.link_up {
                info!("interface: ip {}, link up {}", now.ip, now.link_up);
            }
            a.set_network(NetworkConfig {
                dhcp: old.dhcp,
                link_speed_mbps: old.link_speed_mbps,
                ..now
            });
        });
        let config_change = async {
            if now.ip.is_unspecified() {
                net.wait_config_up().await
            } else {
                net.wait_config_down().await
            }
        };
        let link_change = async {
            if now.link_up {
                net.wait_link_down().await
            } else {
                net.wait_link_up().await
            }
        };
        select(config_change, link_change).await;
    }
}

/// An IPv4 endpoint as a socket address (`None` for IPv6).
pub(crate) fn v4_endpoint(endpoint: IpEndpoint) -> Option<SocketAddrV4> {
    match IpAddr::from(endpoint.addr) {
        IpAddr::V4(ip) => Some(SocketAddrV4::new(ip, endpoint.port)),
        IpAddr::V6(_) => None,
    }
}
