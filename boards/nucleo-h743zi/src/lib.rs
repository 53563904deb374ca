//! `enip_nucleo_h743zi`: any [`enip_stack::Device`] as an EtherNet/IP adapter on the STM32
//! NUCLEO-H743ZI (or NUCLEO-H743ZI2), with one call from the firmware's `main`:
//!
//! ```ignore
//! static ADAPTER: enip_nucleo_h743zi::AdapterCell<my_device::MyDevice> =
//!     enip_nucleo_h743zi::AdapterCell::new();
//!
//! #[embassy_executor::main]
//! async fn main(spawner: embassy_executor::Spawner) {
//!     let network = enip_nucleo_h743zi::static_ipv4([192, 168, 1, 10], 24, None);
//!     let device = |_store| my_device::MyDevice::new();
//!     enip_nucleo_h743zi::run(spawner, &ADAPTER, device, network).await
//! }
//! ```
//!
//! [`run`] initialises the chip (400 MHz: the `clocks` module), builds the embassy-net stack
//! over the on-chip Ethernet MAC (RMII to the LAN8742A PHY at address 0, `GenericPhy` over
//! MDIO: the link state is the PHY's) with the MAC address derived from the chip's unique ID
//! and the network seed from the RNG, mounts the non-volatile store in flash bank 2
//! ([`nv_flash`]), gives the MAC to the link task (Class 1 I/O, then every other frame on to
//! embassy-net), runs the adapter (shared in the firmware's `static` [`AdapterCell`]) and shows
//! the ODVA Module and Network Status on the LEDs ([`leds`]). Logs are defmt over RTT; an
//! Identity Reset restarts the chip. The firmware's build script links with this crate's
//! `memory.x` (program in bank 1, RAM in the AXI SRAM the Ethernet DMA reaches), cortex-m-rt's
//! `link.x` and defmt's `defmt.x`, through flip-link (the stack below the statics).
//!
//! The call stack is painted at boot ([`stack`]). The independent watchdog (IWDG1) is fed
//! while the executor and the link task run, with a timeout ([`WATCHDOG_TIMEOUT_US`]) above
//! the longest stall the firmware has: erasing a 128 KiB store sector. A panic and any other
//! HardFault are logged over defmt and reset the chip.
#![no_std]

mod clocks;
#[path = "../../shared/stm32_eth.rs"]
mod common;
#[path = "../../shared/fault.rs"]
mod fault;
#[path = "../../shared/nucleo_leds.rs"]
pub mod leds;
#[path = "../../shared/net_config.rs"]
mod net_config;
pub mod nv_flash;
#[path = "../../shared/stack.rs"]
pub mod stack;

use embassy_executor::Spawner;
use embassy_stm32::eth::{self, Ethernet, GenericPhy, PacketQueue, Sma};
use embassy_stm32::gpio::{Level, Output, Speed};
use embassy_stm32::peripherals::{ETH, ETH_SMA, IWDG1, RNG};
use embassy_stm32::rng::{self, Rng};
use embassy_stm32::wdg::IndependentWatchdog;
use embassy_stm32::{bind_interrupts, uid};
use enip_firmware::link::{PolledLink, PHY_READ_PERIOD};
use enip_stack::nv::SharedStore;
use enip_stack::Device;
use static_cell::ConstStaticCell;
use {defmt_rtt as _, panic_probe as _};

use common::hard_fault;
pub use common::AdapterCell;
#[cfg(feature = "dhcp")]
pub use net_config::dhcp;
pub use net_config::static_ipv4;

bind_interrupts!(struct Irqs {
    ETH => eth::InterruptHandler;
    RNG => rng::InterruptHandler<RNG>;
});

/// The Ethernet driver: on-chip MAC, LAN8742A through the generic PHY driver, its link state
/// read once a period (`PolledLink`).
type Driver = PolledLink<Ethernet<'static, ETH, GenericPhy<Sma<'static, ETH_SMA>>>>;
/// The independent watchdog.
type Watchdog = IndependentWatchdog<'static, IWDG1>;
/// The board's name in the logs.
const BOARD: &str = "enip-nucleo-h743zi";

/// The independent watchdog's timeout: 8 s at the LSI's nominal 32 kHz, above a 128 KiB
/// sector erase (about 1 s typical, a few at most), which holds the executor.
pub const WATCHDOG_TIMEOUT_US: u32 = 8_000_000;

/// DMA descriptors and buffers of the MAC (1536 bytes each): transmit, receive.
const TX_PACKETS: usize = 4;
const RX_PACKETS: usize = 8;
static PACKETS: ConstStaticCell<PacketQueue<TX_PACKETS, RX_PACKETS>> =
    ConstStaticCell::new(PacketQueue::new());

/// Runs the device `device` builds from the board's non-volatile store (on the on-chip
/// flash; a device with nothing to save ignores it), shared in `home`, with the interface
/// configuration `network`; never returns. Call it once, from the firmware's `main` task.
pub async fn run<D: Device>(
    spawner: Spawner,
    home: &'static AdapterCell<D>,
    device: impl FnOnce(SharedStore) -> D,
    network: embassy_net::Config,
) -> ! {
    stack::paint();
    let p = embassy_stm32::init(clocks::config());
    let leds = leds::NucleoLeds {
        ld1_green: Output::new(p.PB0, Level::Low, Speed::Low),
        // LD2 is yellow on PE1 on the NUCLEO-H743ZI2 (blue on PB7 on the first NUCLEO-H743ZI).
        ld2_yellow: Output::new(p.PE1, Level::Low, Speed::Low),
        ld3_red: Output::new(p.PB14, Level::Low, Speed::Low),
    };
    let seed = Rng::new(p.RNG, Irqs).next_u64();
    let mac = net_config::mac_from_uid(uid::uid());
    let phy = GenericPhy::new(Sma::new(p.ETH_SMA, p.PA2, p.PC1), 0);
    let ethernet = Ethernet::new_with_phy(
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
    // The link state read over MDIO once every 100 ms, not at every link task wake-up.
    let driver = PolledLink::new(ethernet, PHY_READ_PERIOD);
    let hw = common::Hardware {
        driver,
        mac,
        seed,
        leds,
        store: common::mount(nv_flash::store(p.FLASH)),
        dog: IndependentWatchdog::new(p.IWDG1, WATCHDOG_TIMEOUT_US),
    };
    common::run(spawner, home, device, network, hw).await
}

/// Stops IWDG1 while the core is halted by a debugger.
fn freeze_watchdog_when_halted() {
    embassy_stm32::pac::DBGMCU
        .apb4fzr1()
        .modify(|w| w.set_iwdg1(true));
}
