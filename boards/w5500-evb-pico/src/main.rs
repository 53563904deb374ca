//! `enip-w5500-evb-pico`: the board firmware running one of the shipped device profiles.
//!
//! Build-time settings: `ENIP_IP` (default 192.168.1.10/24) and `ENIP_GATEWAY` for the
//! static address, or the `dhcp` feature; the profile by a `profile-NAME` feature (default
//! `generic`). Everything else is [`enip_w5500_evb_pico::run`].
#![no_std]
#![no_main]

/// The device profile chosen by the `profile-NAME` feature.
mod profile {
    include!(concat!(env!("OUT_DIR"), "/profile.rs"));
}

/// The build-time network settings.
#[cfg(not(feature = "dhcp"))]
mod network {
    include!(concat!(env!("OUT_DIR"), "/network.rs"));
}

use embassy_executor::Spawner;
use enip_profiles::PoweredUp;
use enip_w5500_evb_pico::AdapterCell;

/// The adapter over the chosen profile, for the whole run.
static ADAPTER: AdapterCell<profile::Chosen> = AdapterCell::new();

#[embassy_executor::main]
async fn main(spawner: Spawner) {
    defmt::info!("enip-w5500-evb-pico: booting (profile {})", profile::NAME);
    let device = profile::Chosen::powered_up;
    enip_w5500_evb_pico::run(spawner, &ADAPTER, device, net_config()).await
}

/// The interface configuration: DHCP with the `dhcp` feature, else the build-time address.
fn net_config() -> embassy_net::Config {
    #[cfg(feature = "dhcp")]
    {
        enip_w5500_evb_pico::dhcp()
    }
    #[cfg(not(feature = "dhcp"))]
    {
        enip_w5500_evb_pico::static_ipv4(network::ADDRESS, network::PREFIX_LEN, network::GATEWAY)
    }
}
