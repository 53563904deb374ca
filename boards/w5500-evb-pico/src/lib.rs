//! `enip_w5500_evb_pico`: any [`enip_stack::Device`] as an EtherNet/IP adapter on the WIZnet
//! W5500-EVB-Pico (RP2040 and a W5500 Ethernet controller on SPI0), with one call from the
//! firmware's `main`:
//!
//! ```ignore
//! static ADAPTER: enip_w5500_evb_pico::AdapterCell<my_device::MyDevice> =
//!     enip_w5500_evb_pico::AdapterCell::new();
//!
//! #[embassy_executor::main]
//! async fn main(spawner: embassy_executor::Spawner) {
//!     let network = enip_w5500_evb_pico::static_ipv4([192, 168, 1, 10], 24, None);
//!     let device = |_store| my_device::MyDevice::new();
//!     enip_w5500_evb_pico::run(spawner, &ADAPTER, device, network).await
//! }
//! ```
//!
//! [`run`] initialises the chip (125 MHz from the 12 MHz crystal), resets the W5500 and opens
//! its socket 0 in MACRAW mode through `embassy-net-wiznet` (SPI0 at 31.25 MHz: SCK GP18,
//! MOSI GP19, MISO GP16, chip select GP17, interrupt GP21, reset GP20, the pins of embassy's
//! own W5500-EVB-Pico examples), whose runner task moves frames between the W5500 and the
//! driver it hands to the link task (Class 1 I/O, then every other frame on to embassy-net),
//! as the STM32 boards hand their MAC. The MAC address is derived from the QSPI flash's
//! unique ID, the network seed comes from the ring oscillator. It runs the adapter (shared in
//! the firmware's `static` [`AdapterCell`]) behind the board's RPI floor ([`limits`]: the
//! Class 1 rate its SPI link sustains), with the non-volatile store on the QSPI flash
//! ([`nv_flash`]), and shows the Network Status on the user LED ([`led`]). Logs are defmt
//! over RTT; an Identity Reset restarts the chip. The firmware's build script links with the
//! board's `board-link.x` (written by this crate's build script from its `memory.x` and
//! cortex-m-rt's `link.x`), embassy-rp's `link-rp.x` and defmt's `defmt.x`, through flip-link.
//!
//! The call stack is painted at boot ([`stack`]; its high-water mark is readable through the
//! diagnostics object, `enip_firmware::diagnostics`). The RP2040 watchdog is fed while the
//! executor and the link task run, with a timeout ([`WATCHDOG_TIMEOUT_US`]) above the longest
//! stall the firmware has, a store sector erase (400 ms at most). A panic and any other
//! HardFault are logged over defmt and reset the chip.
#![no_std]

mod fault;
pub mod led;
pub mod limits;
#[path = "../../shared/net_config.rs"]
mod net_config;
pub mod nv_flash;
#[path = "../../shared/stack.rs"]
pub mod stack;

use core::cell::RefCell;
use core::pin::pin;

use defmt::{info, panic, warn};
use embassy_executor::Spawner;
use embassy_net::{Runner, StackResources};
use embassy_net_wiznet::chip::W5500;
use embassy_net_wiznet::{InitError, State};
use embassy_rp::bind_interrupts;
use embassy_rp::clocks::RoscRng;
use embassy_rp::dma;
use embassy_rp::gpio::{Input, Level, Output, Pull};
use embassy_rp::peripherals::{DMA_CH0, DMA_CH1, SPI0};
use embassy_rp::spi::{self, Spi};
use embassy_rp::watchdog::Watchdog;
use embassy_time::{Delay, Duration};
use embedded_hal_bus::spi::ExclusiveDevice;
use enip_firmware::diagnostics::Platform;
use enip_firmware::link::{IoPort, LinkChecksums, LinkFrames, NetDriver};
use enip_firmware::watchdog::{beating, keep_fed, Heartbeat};
use enip_firmware::{Diagnosed, Resources, RpiFloor};
use enip_stack::nv::{AbStore, SharedStore};
use enip_stack::{Adapter, Device};
use led::PicoLed;
#[cfg(feature = "dhcp")]
pub use net_config::dhcp;
pub use net_config::static_ipv4;
use net_config::{is_dhcp, mac_from_uid, share_with_store, stored_network};
use nv_flash::{QspiDriver, QspiFlash};
use static_cell::{ConstStaticCell, StaticCell};
use {defmt_rtt as _, panic_probe as _};

bind_interrupts!(struct Irqs {
    DMA_IRQ_0 => dma::InterruptHandler<DMA_CH0>, dma::InterruptHandler<DMA_CH1>;
});

/// The W5500 on SPI0, its chip select driven around each transaction.
type W5500Spi = ExclusiveDevice<Spi<'static, SPI0, spi::Async>, Output<'static>, Delay>;
/// The task that moves frames between the W5500 and [`Driver`].
type WiznetRunner =
    embassy_net_wiznet::Runner<'static, W5500, W5500Spi, Input<'static>, Output<'static>>;
/// The Ethernet driver the link task owns: the W5500's frames, through embassy-net-wiznet.
type Driver = embassy_net_wiznet::Device<'static>;

/// A `static` home for the adapter over a device `D`, behind the board's RPI floor and with
/// the board's diagnostics object in front: `static ADAPTER: AdapterCell<MyDevice> =
/// AdapterCell::new();`.
pub type AdapterCell<D> = enip_firmware::AdapterCell<Diagnosed<RpiFloor<D>>>;

/// What the board tells the diagnostics object: its stack (no fault trigger on hardware).
const PLATFORM: Platform = Platform {
    stack: stack::measure,
    provoke: None,
};
/// The watchdog's timeout: 2 s, above a store sector erase (45 ms typical, 400 ms at most)
/// with the CPU stalled, plus a feeding period. (The RP2040's allows 8.3 s at most.)
pub const WATCHDOG_TIMEOUT_US: u32 = 2_000_000;
/// How often the watchdog task checks the link task and feeds the watchdog.
const FEED_PERIOD: Duration = Duration::from_millis(500);
/// The link task's polls, watched by the watchdog task.
static HEARTBEAT: StaticCell<Heartbeat> = StaticCell::new();
/// The SPI clock asked for, as embassy's W5500-EVB-Pico examples do: the RP2040 gives the
/// fastest it can at or below it, 31.25 MHz ([`limits::SPI_HZ`]).
const SPI_REQUEST_HZ: u32 = 50_000_000;

/// Sockets of the embassy-net stack: what the runtime needs, and one for DHCP.
const SOCKETS: usize = enip_firmware::SOCKETS + 1;
/// Frames (1514 bytes each) queued between the W5500's runner and the link task: received,
/// to send.
const RX_PACKETS: usize = 4;
const TX_PACKETS: usize = 4;

static WIZNET: ConstStaticCell<State<RX_PACKETS, TX_PACKETS>> = ConstStaticCell::new(State::new());
static NET_RESOURCES: ConstStaticCell<StackResources<SOCKETS>> =
    ConstStaticCell::new(enip_firmware::stack_resources());
static FIRMWARE_RESOURCES: StaticCell<Resources> = StaticCell::new();
static LINK_FRAMES: ConstStaticCell<LinkFrames> = ConstStaticCell::new(LinkFrames::new());
/// The non-volatile store on the QSPI flash: the TCP/IP settings and the device's own.
static NV_STORE: StaticCell<RefCell<AbStore<QspiFlash>>> = StaticCell::new();
/// The adapter's handle to it.
static NV_HANDLE: StaticCell<SharedStore> = StaticCell::new();

/// Runs the device `device` builds from the board's non-volatile store (on the QSPI flash; a
/// device with nothing to save ignores it), shared in `home`, with the interface
/// configuration `network`; never returns. Call it once, from the firmware's `main` task.
pub async fn run<D: Device>(
    spawner: Spawner,
    home: &'static AdapterCell<D>,
    device: impl FnOnce(SharedStore) -> D,
    network: embassy_net::Config,
) -> ! {
    stack::paint();
    let p = embassy_rp::init(Default::default());
    let led = PicoLed {
        led: Output::new(p.PIN_25, Level::Low),
    };
    let mut flash = QspiDriver::new_blocking(p.FLASH);
    let mut uid = [0u8; 8];
    if flash.blocking_unique_id(&mut uid).is_err() {
        warn!("flash unique ID unreadable: MAC from zeros");
    }
    let mac = mac_from_uid(uid);
    let seed = RoscRng.next_u64();
    let mut spi_config = spi::Config::default();
    spi_config.frequency = SPI_REQUEST_HZ;
    let (sck, mosi, miso) = (p.PIN_18, p.PIN_19, p.PIN_16);
    let spi = Spi::new(
        p.SPI0, sck, mosi, miso, p.DMA_CH0, p.DMA_CH1, Irqs, spi_config,
    );
    let Ok(spi) = ExclusiveDevice::new(spi, Output::new(p.PIN_17, Level::High), Delay);
    let int = Input::new(p.PIN_21, Pull::Up);
    let reset = Output::new(p.PIN_20, Level::High);
    let state = WIZNET.take();
    let (driver, wiznet) = match embassy_net_wiznet::new::<RX_PACKETS, TX_PACKETS, W5500, _, _, _>(
        mac, state, spi, int, reset,
    )
    .await
    {
        Ok(pair) => pair,
        Err(InitError::SpiError(_)) => panic!("W5500: SPI error"),
        Err(InitError::InvalidChipVersion { actual, .. }) => {
            panic!("W5500: chip version {=u8}, not a W5500", actual)
        }
    };
    let mut store = SharedStore::new(NV_STORE.init(RefCell::new(nv_flash::store(flash))));
    let network = stored_network(&mut store).unwrap_or(network);
    let dhcp = is_dhcp(&network);
    let frames: &'static LinkFrames = LINK_FRAMES.take();
    // The W5500 in MACRAW mode computes no checksums: the link task does the stack's, 16
    // bytes a step rather than smoltcp's 2 (`NetDriver::with_link_checksums`).
    let (net_driver, checksums) = NetDriver::with_link_checksums(frames, &driver);
    let (net, runner) = embassy_net::new(net_driver, network, NET_RESOURCES.take(), seed);
    let mut interface = enip_firmware::network_config(net);
    interface.dhcp = dhcp;
    let build = || {
        Adapter::new(
            Diagnosed::new(RpiFloor::new(device(store), limits::rpi_floor_us), PLATFORM),
            interface,
            seed.rotate_left(32),
        )
    };
    let Some(adapter) = share_with_store(home, build, NV_HANDLE.init(store)) else {
        panic!("enip_w5500_evb_pico::run called twice");
    };
    let heart: &'static Heartbeat = HEARTBEAT.init(Heartbeat::new());
    let dog = Watchdog::new(p.WATCHDOG);
    match (
        wiznet_task(wiznet),
        net_task(runner),
        link_task(driver, frames, adapter, heart, checksums),
        watchdog_task(dog, heart),
    ) {
        (Ok(wiznet), Ok(net), Ok(link), Ok(dog)) => {
            spawner.spawn(wiznet);
            spawner.spawn(net);
            spawner.spawn(link);
            spawner.spawn(dog);
        }
        _ => panic!("cannot spawn the W5500, network, link and watchdog tasks"),
    }
    info!("enip-w5500-evb-pico: MAC {=[u8]:02x}", mac);
    let resources = FIRMWARE_RESOURCES.init_with(Resources::new);
    let (never, _) = embassy_futures::join::join(
        enip_firmware::run(net, adapter, resources, on_reset),
        enip_firmware::indicators::indicate(adapter, led),
    )
    .await;
    never
}

/// Moves frames between the W5500 (over SPI) and the link task's driver.
#[embassy_executor::task]
async fn wiznet_task(runner: WiznetRunner) -> ! {
    runner.run().await
}

/// Moves frames between the link task and the network stack.
#[embassy_executor::task]
async fn net_task(mut runner: Runner<'static, NetDriver<'static>>) -> ! {
    runner.run().await
}

/// Owns the Ethernet driver: Class 1 I/O, and every other frame to and from the network stack.
#[embassy_executor::task]
async fn link_task(
    driver: Driver,
    frames: &'static LinkFrames,
    adapter: &'static dyn IoPort,
    heart: &'static Heartbeat,
    checksums: LinkChecksums,
) -> ! {
    let link = enip_firmware::link::run_with_link_checksums(
        driver,
        frames,
        adapter,
        checksums,
        &enip_firmware::link::TimeQueue,
    );
    beating(heart, pin!(link)).await
}

/// Starts the watchdog and feeds it while the executor runs and the link task is polled.
#[embassy_executor::task]
async fn watchdog_task(mut dog: Watchdog, heart: &'static Heartbeat) -> ! {
    let timeout = Duration::from_micros(u64::from(WATCHDOG_TIMEOUT_US));
    // A core halted by a debugger stops the watchdog with it rather than being reset.
    dog.pause_on_debug(true);
    dog.start(timeout);
    keep_fed(heart, FEED_PERIOD, || dog.feed(timeout)).await
}

/// The HardFault handler proper (see [`fault`]), on a fresh stack: logs the stack pointer
/// the fault was taken with and resets.
extern "C" fn hard_fault(sp: u32) -> ! {
    defmt::error!(
        "HardFault (stack overflow: {}): sp {=u32:#x}: resetting",
        fault::overflowed(sp),
        sp
    );
    cortex_m::peripheral::SCB::sys_reset()
}

/// Identity Reset: restart the microcontroller.
fn on_reset(kind: u8) {
    warn!("identity reset (type {}): restarting", kind);
    cortex_m::peripheral::SCB::sys_reset();
}
