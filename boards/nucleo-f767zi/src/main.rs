//! `enip-nucleo-f767zi`: the EtherNet/IP adapter on the STM32 NUCLEO-F767ZI.
//!
//! The board builds the embassy-net stack over the on-chip Ethernet MAC (RMII to the
//! LAN8742A PHY at address 0, managed through `GenericPhy` over the MDIO bus), with the MAC
//! address derived from the chip's unique ID and the network seed from the RNG, and hands it
//! to the same `firmware` every board runs. The LEDs show the ODVA Module and Network
//! Status ([`leds`]); logs are defmt over RTT.
//!
//! Build-time settings: `ENIP_IP` (default 192.168.1.10/24) and `ENIP_GATEWAY` for the
//! static address, or the `dhcp` feature; the profile by a `profile-NAME` feature (default
//! `generic`).
#![no_std]
#![no_main]

mod clocks;
mod leds;

/// The device profile chosen by the `profile-NAME` feature.
mod profile {
    include!(concat!(env!("OUT_DIR"), "/profile.rs"));
}

/// The build-time network settings.
#[cfg(not(feature = "dhcp"))]
mod network {
    include!(concat!(env!("OUT_DIR"), "/network.rs"));
}

use defmt::{info, panic, warn};
use embassy_executor::Spawner;
use embassy_net::{Runner, StackResources};
use embassy_stm32::eth::{self, Ethernet, GenericPhy, PacketQueue, Sma};
use embassy_stm32::gpio::{Level, Output, Speed};
use embassy_stm32::peripherals::{ETH, ETH_SMA, RNG};
use embassy_stm32::rng::{self, Rng};
use embassy_stm32::{bind_interrupts, uid};
use firmware::{Resources, SharedAdapter};
use leds::NucleoLeds;
use stack::Adapter;
use static_cell::{ConstStaticCell, StaticCell};
use {defmt_rtt as _, panic_probe as _};

bind_interrupts!(struct Irqs {
    ETH => eth::InterruptHandler;
    RNG => rng::InterruptHandler<RNG>;
});

/// The Ethernet driver: on-chip MAC, LAN8742A through the generic PHY driver.
type Device = Ethernet<'static, ETH, GenericPhy<Sma<'static, ETH_SMA>>>;

/// Sockets of the embassy-net stack: 3 TCP and 1 UDP on 44818, 2 UDP on 2222, and DHCP.
const SOCKETS: usize = firmware::SOCKETS + cfg!(feature = "dhcp") as usize;
/// DMA descriptors and buffers of the MAC (1536 bytes each): transmit, receive.
const TX_PACKETS: usize = 4;
const RX_PACKETS: usize = 8;

static PACKETS: ConstStaticCell<PacketQueue<TX_PACKETS, RX_PACKETS>> =
    ConstStaticCell::new(PacketQueue::new());
static NET_RESOURCES: StaticCell<StackResources<SOCKETS>> = StaticCell::new();
static ADAPTER: StaticCell<SharedAdapter<profile::Chosen>> = StaticCell::new();
static FIRMWARE_RESOURCES: StaticCell<Resources> = StaticCell::new();

#[embassy_executor::main]
async fn main(spawner: Spawner) {
    let p = embassy_stm32::init(clocks::config());
    info!("enip-nucleo-f767zi: booting (profile {})", profile::NAME);

    let leds = NucleoLeds {
        ld1_green: Output::new(p.PB0, Level::Low, Speed::Low),
        ld2_blue: Output::new(p.PB7, Level::Low, Speed::Low),
        ld3_red: Output::new(p.PB14, Level::Low, Speed::Low),
    };
    let seed = Rng::new(p.RNG, Irqs).next_u64();
    let mac = mac_from_uid(uid::uid());
    let phy = GenericPhy::new(Sma::new(p.ETH_SMA, p.PA2, p.PC1), 0);
    let device = Ethernet::new_with_phy(
        PACKETS.take(),
        p.ETH,
        Irqs,
        p.PA1,  // REF_CLK
        p.PA7,  // CRS_DV
        p.PC4,  // RXD0
        p.PC5,  // RXD1
        p.PG13, // TXD0
        p.PB13, // TXD1
        p.PG11, // TX_EN
        mac,
        phy,
    );
    let (net, runner) = embassy_net::new(
        device,
        net_config(),
        NET_RESOURCES.init(firmware::stack_resources()),
        seed,
    );
    let mut interface = firmware::network_config(net);
    interface.dhcp = cfg!(feature = "dhcp");
    let adapter = Adapter::new(profile::Chosen::new(), interface, seed.rotate_left(32));
    let adapter = ADAPTER.init(firmware::share(adapter));
    match (net_task(runner), indicator_task(adapter, leds)) {
        (Ok(net), Ok(indicators)) => {
            spawner.spawn(net);
            spawner.spawn(indicators);
        }
        _ => panic!("cannot spawn the board's tasks"),
    }
    info!("enip-nucleo-f767zi: MAC {=[u8]:02x}", mac);
    firmware::run(
        net,
        adapter,
        FIRMWARE_RESOURCES.init_with(Resources::new),
        on_reset,
    )
    .await
}

/// The interface configuration: DHCP with the `dhcp` feature, else the build-time address.
fn net_config() -> embassy_net::Config {
    #[cfg(feature = "dhcp")]
    {
        embassy_net::Config::dhcpv4(Default::default())
    }
    #[cfg(not(feature = "dhcp"))]
    {
        use core::net::Ipv4Addr;
        embassy_net::Config::ipv4_static(embassy_net::StaticConfigV4 {
            address: embassy_net::Ipv4Cidr::new(
                Ipv4Addr::from(network::ADDRESS),
                network::PREFIX_LEN,
            ),
            gateway: network::GATEWAY.map(Ipv4Addr::from),
            dns_servers: Default::default(),
        })
    }
}

/// A locally administered unicast MAC address (02:xx:xx:xx:xx:xx) from the 96-bit unique
/// ID: its FNV-1a hash, so boards of one wafer lot still differ in the five bytes kept.
fn mac_from_uid(uid: [u8; 12]) -> [u8; 6] {
    let hash = uid.iter().fold(0xCBF2_9CE4_8422_2325u64, |h, b| {
        (h ^ u64::from(*b)).wrapping_mul(0x0000_0100_0000_01B3)
    });
    let h = hash.to_le_bytes();
    [0x02, h[0], h[1], h[2], h[3], h[4]]
}

/// Moves frames between the Ethernet MAC and the network stack.
#[embassy_executor::task]
async fn net_task(mut runner: Runner<'static, Device>) -> ! {
    runner.run().await
}

/// Shows the Module and Network Status on the LEDs.
#[embassy_executor::task]
async fn indicator_task(adapter: &'static SharedAdapter<profile::Chosen>, leds: NucleoLeds) -> ! {
    firmware::indicators::indicate(adapter, leds).await
}

/// Identity Reset: restart the microcontroller.
fn on_reset(kind: u8) {
    warn!("identity reset (type {}): restarting", kind);
    cortex_m::peripheral::SCB::sys_reset();
}
