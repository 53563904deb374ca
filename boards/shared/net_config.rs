//! What every embassy-net board on real hardware (the NUCLEOs, the W5500-EVB-Pico) does the
//! same way with its interface configuration and its store, `#[path]`-included at the
//! board crate's root: the static or DHCP configuration, the store attached to the adapter,
//! the static configuration a scanner stored (TCP/IP attribute 5), the MAC address from a
//! unique ID. The including crate has a `dhcp` feature and logs with `defmt`.

use core::net::Ipv4Addr;

use defmt::{info, warn};
use enip_firmware::{AdapterCell, SharedAdapter};
use enip_stack::nv::SharedStore;
use enip_stack::objects::TcpIpState;
use enip_stack::{Adapter, Device};

/// A static IPv4 configuration: address, prefix length, optional gateway.
pub fn static_ipv4(
    address: [u8; 4],
    prefix_len: u8,
    gateway: Option<[u8; 4]>,
) -> embassy_net::Config {
    embassy_net::Config::ipv4_static(embassy_net::StaticConfigV4 {
        address: embassy_net::Ipv4Cidr::new(Ipv4Addr::from(address), prefix_len),
        gateway: gateway.map(Ipv4Addr::from),
        dns_servers: Default::default(),
    })
}

/// An address from DHCP (the `dhcp` feature).
#[cfg(feature = "dhcp")]
pub fn dhcp() -> embassy_net::Config {
    embassy_net::Config::dhcpv4(Default::default())
}

/// The adapter `build` makes, shared in `home` with the flash store `store` attached (its
/// TCP/IP settings loaded from it); `None` if `home` was used before. Never inlined: the
/// adapter's parts are on the stack only while it runs (about 44 KiB deep with the default
/// capacities), not in the main task's frame for good.
#[inline(never)]
pub(crate) fn share_with_store<D: Device>(
    home: &'static AdapterCell<D>,
    build: impl FnOnce() -> Adapter<D>,
    store: &'static mut SharedStore,
) -> Option<&'static SharedAdapter<D>> {
    let adapter = home.share(build)?;
    enip_firmware::with_adapter(adapter, |a| {
        // TCP/IP capability bit 2: a scanner may set DHCP only where the image has a client.
        a.set_dhcp_client(cfg!(feature = "dhcp"));
        match a.attach_store(store) {
            Ok(true) => info!("TCP/IP settings loaded from flash"),
            Ok(false) => info!("no TCP/IP settings in flash: factory defaults"),
            Err(e) => warn!("flash store unreadable ({}): factory defaults", e),
        }
    });
    Some(adapter)
}

/// The static interface configuration stored in flash (TCP/IP attribute 5, set by a
/// scanner and applied here, at the next boot), if configuration control says static.
pub(crate) fn stored_network(store: &mut SharedStore) -> Option<embassy_net::Config> {
    let stored = match TcpIpState::stored(store) {
        Ok(s) => s?,
        Err(e) => {
            warn!("flash store unreadable ({}): built-in network settings", e);
            return None;
        }
    };
    let Some(i) = stored.static_interface() else {
        info!("no static interface configuration stored: built-in network settings");
        return None;
    };
    let prefix = u32::from(i.netmask).count_ones() as u8;
    info!(
        "interface {=[u8]}/{} from the stored TCP/IP configuration",
        i.ip.octets(),
        prefix
    );
    let gateway = (!i.gateway.is_unspecified()).then_some(i.gateway.octets());
    Some(static_ipv4(i.ip.octets(), prefix, gateway))
}

/// True if `network` asks for DHCP.
pub(crate) fn is_dhcp(network: &embassy_net::Config) -> bool {
    #[cfg(feature = "dhcp")]
    {
        matches!(network.ipv4, embassy_net::ConfigV4::Dhcp(_))
    }
    #[cfg(not(feature = "dhcp"))]
    {
        let _ = network;
        false
    }
}

/// A locally administered unicast MAC address (02:xx:xx:xx:xx:xx) from a chip's unique ID
/// (the STM32's 96 bits, the Pico flash's 64): its FNV-1a hash, so chips of one wafer lot
/// still differ in the five bytes kept.
pub(crate) fn mac_from_uid<const N: usize>(uid: [u8; N]) -> [u8; 6] {
    let hash = uid.iter().fold(0xCBF2_9CE4_8422_2325u64, |h, b| {
        (h ^ u64::from(*b)).wrapping_mul(0x0000_0100_0000_01B3)
    });
    let h = hash.to_le_bytes();
    [0x02, h[0], h[1], h[2], h[3], h[4]]
}
