//! `enip-qemu-mps2`: the EtherNet/IP adapter on QEMU's `mps2-an386` machine (Cortex-M4 at
//! 25 MHz, LAN9118 Ethernet at 0x4020_0000 on IRQ 13).
//!
//! The board builds the embassy-net stack over its [`lan9118`] driver and hands it to the
//! same `firmware` every board runs. Time comes from the CMSDK timers ([`time`]), logs go to
//! UART0 ([`uart`], QEMU's standard output with `-nographic`). The static address is set at
//! build time (`ENIP_IP`, default 198.18.0.2/24; `ENIP_GATEWAY`), the profile by a
//! `profile-NAME` feature (default `generic`).
#![no_std]
#![no_main]

mod irq;
mod lan9118;
mod mmio;
mod time;
mod uart;

/// The device profile chosen by the `profile-NAME` feature.
mod profile {
    include!(concat!(env!("OUT_DIR"), "/profile.rs"));
}

/// The build-time network settings.
mod network {
    include!(concat!(env!("OUT_DIR"), "/network.rs"));
}

use core::net::Ipv4Addr;

use embassy_executor::Spawner;
use embassy_net::{Ipv4Cidr, Runner, StackResources, StaticConfigV4};
use enip_firmware::{Resources, SharedAdapter};
use enip_stack::Adapter;
use lan9118::Lan9118;
use static_cell::StaticCell;

/// Sockets of the embassy-net stack: what the runtime needs (3 TCP and 1 UDP on 44818, 2 UDP on 2222).
const SOCKETS: usize = enip_firmware::SOCKETS;

static NET_RESOURCES: StaticCell<StackResources<SOCKETS>> = StaticCell::new();
static ADAPTER: StaticCell<SharedAdapter<profile::Chosen>> = StaticCell::new();
static FIRMWARE_RESOURCES: StaticCell<Resources> = StaticCell::new();

#[embassy_executor::main]
async fn main(spawner: Spawner) {
    time::init();
    uart::init(log::LevelFilter::Info);
    log::info!("enip-qemu-mps2: booting (profile {})", profile::NAME);

    let device = match Lan9118::new() {
        Ok(d) => d,
        Err(e) => panic!("LAN9118: {e:?}"),
    };
    let mac = device.mac();
    let address = Ipv4Addr::from(network::ADDRESS);
    let config = embassy_net::Config::ipv4_static(StaticConfigV4 {
        address: Ipv4Cidr::new(address, network::PREFIX_LEN),
        gateway: network::GATEWAY.map(Ipv4Addr::from),
        dns_servers: Default::default(),
    });
    let seed = seed(mac);
    let (net, runner) = embassy_net::new(
        device,
        config,
        NET_RESOURCES.init(enip_firmware::stack_resources()),
        seed,
    );
    let adapter = Adapter::new(
        profile::Chosen::new(),
        enip_firmware::network_config(net),
        seed.rotate_left(32),
    );
    let adapter = ADAPTER.init(enip_firmware::share(adapter));
    match net_task(runner) {
        Ok(task) => spawner.spawn(task),
        Err(e) => panic!("cannot spawn the network task: {e:?}"),
    }
    log::info!(
        "enip-qemu-mps2: MAC {:02x?}, listening on {address}/{}",
        mac,
        network::PREFIX_LEN
    );
    enip_firmware::run(
        net,
        adapter,
        FIRMWARE_RESOURCES.init_with(Resources::new),
        on_reset,
    )
    .await
}

/// Seeds for the network stack and the adapter. The machine has no random number
/// generator: the MAC address and the controller's free-running count since reset are the
/// only things that differ between runs.
fn seed(mac: [u8; 6]) -> u64 {
    let mut bytes = [0u8; 8];
    bytes[..6].copy_from_slice(&mac);
    let count = u64::from(Lan9118::free_running_count());
    (u64::from_le_bytes(bytes) ^ count.rotate_left(40)).wrapping_mul(0x9E37_79B9_7F4A_7C15)
}

/// Moves frames between the LAN9118 and the network stack.
#[embassy_executor::task]
async fn net_task(mut runner: Runner<'static, Lan9118>) -> ! {
    runner.run().await
}

/// Identity Reset: restart the machine (QEMU resets it, or exits with `-no-reboot`).
fn on_reset(kind: u8) {
    log::warn!("identity reset (type {kind}): restarting");
    cortex_m::peripheral::SCB::sys_reset();
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo<'_>) -> ! {
    uart::panic_report(info);
    loop {
        cortex_m::asm::wfi();
    }
}
