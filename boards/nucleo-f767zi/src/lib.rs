//! `enip_nucleo_f767zi`: any [`enip_stack::Device`] as an EtherNet/IP adapter on the STM32
//! NUCLEO-F767ZI, with one call from the firmware's `main`:
//!
//! ```ignore
//! static ADAPTER: enip_nucleo_f767zi::AdapterCell<my_device::MyDevice> =
//!     enip_nucleo_f767zi::AdapterCell::new();
//!
//! #[embassy_executor::main]
//! async fn main(spawner: embassy_executor::Spawner) {
//!     let network = enip_nucleo_f767zi::static_ipv4([192, 168, 1, 10], 24, None);
//!     let device = |_store| my_device::MyDevice::new();
//!     enip_nucleo_f767zi::run(spawner, &ADAPTER, device, network).await
//! }
//! ```
//!
//! [`run`] initialises the chip (216 MHz), builds the embassy-net stack over the on-chip
//! Ethernet MAC (RMII to the LAN8742A PHY at address 0, `GenericPhy` over MDIO) with the MAC
//! address derived from the chip's unique ID and the network seed from the RNG, gives the
//! MAC to the link task (Class 1 I/O, then every other frame on to embassy-net), runs the
//! adapter (shared in the firmware's `static` [`AdapterCell`]) and shows the ODVA Module and Network Status on the LEDs ([`leds`]). Logs are
//! defmt over RTT; an Identity Reset restarts the chip. The firmware's build script links
//! with `memory.x` (the STM32F767ZI map), cortex-m-rt's `link.x` and defmt's `defmt.x`,
//! through flip-link (the stack below the statics, so an overflow faults).
//!
//! The call stack is painted at boot ([`stack`]; its high-water mark is readable through the
//! diagnostics object, `enip_firmware::diagnostics`). The independent watchdog (IWDG) is fed
//! while the executor and the link task run, with a timeout ([`WATCHDOG_TIMEOUT_US`]) above
//! the longest stall the firmware has: erasing a 256 KiB store sector, up to 4 s. A panic
//! (panic-probe: `udf`) and any other HardFault are logged over defmt and reset the chip;
//! with a debugger attached, `probe-rs run` catches the fault first and shows the backtrace.
#![no_std]

mod clocks;
#[path = "../../shared/fault.rs"]
mod fault;
pub mod leds;
#[path = "../../shared/net_config.rs"]
mod net_config;
pub mod nv_flash;
#[path = "../../shared/stack.rs"]
pub mod stack;

use core::pin::pin;

use core::cell::RefCell;
use defmt::{info, panic, warn};
use embassy_executor::Spawner;
use embassy_net::{Runner, StackResources};
use embassy_stm32::eth::{self, Ethernet, GenericPhy, PacketQueue, Sma};
use embassy_stm32::gpio::{Level, Output, Speed};
use embassy_stm32::peripherals::{ETH, ETH_SMA, IWDG, RNG};
use embassy_stm32::rng::{self, Rng};
use embassy_stm32::wdg::IndependentWatchdog;
use embassy_stm32::{bind_interrupts, uid};
use embassy_time::Duration;
use enip_firmware::diagnostics::Platform;
use enip_firmware::link::{IoPort, LinkFrames, NetDriver, PolledLink, PHY_READ_PERIOD};
use enip_firmware::watchdog::{beating, keep_fed, Heartbeat};
use enip_firmware::{Diagnosed, Resources};
use enip_stack::nv::{AbStore, SharedStore};
use enip_stack::{Adapter, Device};
use leds::NucleoLeds;
#[cfg(feature = "dhcp")]
pub use net_config::dhcp;
pub use net_config::static_ipv4;
use net_config::{is_dhcp, mac_from_uid, share_with_store, stored_network};
use nv_flash::OnChipFlash;
use static_cell::{ConstStaticCell, StaticCell};
use {defmt_rtt as _, panic_probe as _};

bind_interrupts!(struct Irqs {
    ETH => eth::InterruptHandler;
    RNG => rng::InterruptHandler<RNG>;
});

/// The Ethernet driver: on-chip MAC, LAN8742A through the generic PHY driver, its link state
/// read once a period (`PolledLink`).
type Driver = PolledLink<Ethernet<'static, ETH, GenericPhy<Sma<'static, ETH_SMA>>>>;

/// A `static` home for the adapter over a device `D`, with the board's diagnostics object in
/// front of it: `static ADAPTER: AdapterCell<MyDevice> = AdapterCell::new();`.
pub type AdapterCell<D> = enip_firmware::AdapterCell<Diagnosed<D>>;

/// What the board tells the diagnostics object: its stack (no fault trigger on hardware).
const PLATFORM: Platform = Platform {
    stack: stack::measure,
    provoke: None,
};
/// The independent watchdog's timeout: 8 s at the LSI's nominal 32 kHz (at least 5.4 s at its
/// fastest, 47 kHz), above a 256 KiB sector erase (2 s typical, 4 s at most), which stalls
/// the CPU with the executor.
pub const WATCHDOG_TIMEOUT_US: u32 = 8_000_000;
/// How often the watchdog task checks the link task and feeds the watchdog.
const FEED_PERIOD: Duration = Duration::from_millis(500);
/// The link task's polls, watched by the watchdog task.
static HEARTBEAT: StaticCell<Heartbeat> = StaticCell::new();

/// Sockets of the embassy-net stack: what the runtime needs, and one for DHCP.
const SOCKETS: usize = enip_firmware::SOCKETS + 1;
/// DMA descriptors and buffers of the MAC (1536 bytes each): transmit, receive.
const TX_PACKETS: usize = 4;
const RX_PACKETS: usize = 8;

static PACKETS: ConstStaticCell<PacketQueue<TX_PACKETS, RX_PACKETS>> =
    ConstStaticCell::new(PacketQueue::new());
static NET_RESOURCES: ConstStaticCell<StackResources<SOCKETS>> =
    ConstStaticCell::new(enip_firmware::stack_resources());
static FIRMWARE_RESOURCES: StaticCell<Resources> = StaticCell::new();
static LINK_FRAMES: ConstStaticCell<LinkFrames> = ConstStaticCell::new(LinkFrames::new());
/// The non-volatile store on the on-chip flash: the TCP/IP settings and the device's own.
static NV_STORE: StaticCell<RefCell<AbStore<OnChipFlash>>> = StaticCell::new();
/// The adapter's handle to it.
static NV_HANDLE: StaticCell<SharedStore> = StaticCell::new();

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
    let leds = NucleoLeds {
        ld1_green: Output::new(p.PB0, Level::Low, Speed::Low),
        ld2_blue: Output::new(p.PB7, Level::Low, Speed::Low),
        ld3_red: Output::new(p.PB14, Level::Low, Speed::Low),
    };
    let seed = Rng::new(p.RNG, Irqs).next_u64();
    let mac = mac_from_uid(uid::uid());
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
    let mut store = SharedStore::new(NV_STORE.init(RefCell::new(nv_flash::store(p.FLASH))));
    let network = stored_network(&mut store).unwrap_or(network);
    let dhcp = is_dhcp(&network);
    let frames: &'static LinkFrames = LINK_FRAMES.take();
    let net_driver = NetDriver::new(frames, &driver);
    let (net, runner) = embassy_net::new(net_driver, network, NET_RESOURCES.take(), seed);
    let mut interface = enip_firmware::network_config(net);
    interface.dhcp = dhcp;
    let build = || {
        Adapter::new(
            Diagnosed::new(device(store), PLATFORM),
            interface,
            seed.rotate_left(32),
        )
    };
    let Some(adapter) = share_with_store(home, build, NV_HANDLE.init(store)) else {
        panic!("enip_nucleo_f767zi::run called twice");
    };
    let heart: &'static Heartbeat = HEARTBEAT.init(Heartbeat::new());
    let dog = IndependentWatchdog::new(p.IWDG, WATCHDOG_TIMEOUT_US);
    match (
        net_task(runner),
        link_task(driver, frames, adapter, heart),
        watchdog_task(dog, heart),
    ) {
        (Ok(net), Ok(link), Ok(dog)) => {
            spawner.spawn(net);
            spawner.spawn(link);
            spawner.spawn(dog);
        }
        _ => panic!("cannot spawn the network, link and watchdog tasks"),
    }
    info!("enip-nucleo-f767zi: MAC {=[u8]:02x}", mac);
    let resources = FIRMWARE_RESOURCES.init_with(Resources::new);
    let (never, _) = embassy_futures::join::join(
        enip_firmware::run(net, adapter, resources, on_reset),
        enip_firmware::indicators::indicate(adapter, leds),
    )
    .await;
    never
}

/// Moves frames between the Ethernet MAC and the network stack.
#[embassy_executor::task]
async fn net_task(mut runner: Runner<'static, NetDriver<'static>>) -> ! {
    runner.run().await
}

/// Owns the Ethernet MAC: Class 1 I/O, and every other frame to and from the network stack.
#[embassy_executor::task]
async fn link_task(
    driver: Driver,
    frames: &'static LinkFrames,
    adapter: &'static dyn IoPort,
    heart: &'static Heartbeat,
) -> ! {
    beating(
        heart,
        pin!(enip_firmware::link::run(driver, frames, adapter)),
    )
    .await
}

/// Starts the independent watchdog and feeds it while the executor runs and the link task
/// is polled.
#[embassy_executor::task]
async fn watchdog_task(
    mut dog: IndependentWatchdog<'static, IWDG>,
    heart: &'static Heartbeat,
) -> ! {
    // A core halted by a debugger (a breakpoint, `probe-rs run` stopping at a fault) stops
    // the watchdog with it rather than being reset under the debugger.
    embassy_stm32::pac::DBGMCU
        .apb1fzr()
        .modify(|w| w.set_iwdg(true));
    dog.unleash();
    keep_fed(heart, FEED_PERIOD, || dog.pet()).await
}

/// The HardFault handler proper (see the shared `fault` entry), on a fresh stack: logs the
/// fault registers and resets.
extern "C" fn hard_fault(sp: u32) -> ! {
    let f = fault::fault(sp);
    defmt::error!(
        "HardFault (stack overflow: {}): sp {=u32:#x} CFSR {=u32:#x} HFSR {=u32:#x} address {=u32:#x}: resetting",
        f.overflow,
        f.sp,
        f.cfsr,
        f.hfsr,
        f.address
    );
    cortex_m::peripheral::SCB::sys_reset()
}

/// Identity Reset: restart the microcontroller.
fn on_reset(kind: u8) {
    warn!("identity reset (type {}): restarting", kind);
    cortex_m::peripheral::SCB::sys_reset();
}
