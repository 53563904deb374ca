//! `enip-qemu-mps2`: the emulated board's firmware running one of the shipped device
//! profiles. The static address is set at build time (`ENIP_IP`, default 198.18.0.2/24;
//! `ENIP_GATEWAY`), the profile by a `profile-NAME` feature (default `generic`), Address
//! Conflict Detection by `ENIP_ACD` (`on` by default; the test images not about it are built
//! with `off`); everything else is [`enip_qemu_mps2::run`].
#![no_std]
#![no_main]

/// The build-time Address Conflict Detection choice.
mod acd {
    include!(concat!(env!("OUT_DIR"), "/acd.rs"));
}

/// The device profile chosen by the `profile-NAME` feature.
mod profile {
    include!(concat!(env!("OUT_DIR"), "/profile.rs"));
}

/// The build-time network settings.
mod network {
    include!(concat!(env!("OUT_DIR"), "/network.rs"));
}

use embassy_executor::Spawner;
use enip_profiles::PoweredUp;
use enip_qemu_mps2::AdapterCell;

/// The adapter over the chosen profile, for the whole run.
static ADAPTER: AdapterCell<profile::Chosen> = AdapterCell::new();

#[embassy_executor::main]
async fn main(spawner: Spawner) {
    let device = profile::Chosen::powered_up;
    let address = (network::ADDRESS, network::PREFIX_LEN, network::GATEWAY);
    enip_qemu_mps2::run(spawner, &ADAPTER, profile::NAME, device, address, acd::ACD).await
}
