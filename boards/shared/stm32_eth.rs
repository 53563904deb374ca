//! What the STM32 NUCLEO-144 boards on embassy-stm32's ETH driver (NUCLEO-H743ZI,
//! NUCLEO-H563ZI) share, `#[path]`-included by each: the embassy-net stack over the MAC, the
//! link task, the non-volatile store attached to the adapter, the watchdog task, the fault
//! and reset handlers and the one `run` future. The including crate provides its chip's
//! pieces at its root: `Driver` (the MAC with its PHY), `Watchdog` (the IWDG), `BOARD` (its
//! name for the logs), `freeze_watchdog_when_halted`, `nv_flash::OnChipFlash`, `stack` and
//! `net_config` (`boards/shared/net_config.rs`).

use core::cell::RefCell;
use core::pin::pin;

use defmt::{info, panic, warn};
use embassy_executor::Spawner;
use embassy_net::{Runner, StackResources};
use embassy_time::Duration;
use enip_firmware::diagnostics::Platform;
use enip_firmware::indicators::Leds;
use enip_firmware::link::{IoPort, LinkFrames, NetDriver};
use enip_firmware::watchdog::{beating, keep_fed, Heartbeat};
use enip_firmware::{Diagnosed, Resources};
use enip_stack::nv::{AbStore, SharedStore};
use enip_stack::{Adapter, Device};
use static_cell::{ConstStaticCell, StaticCell};

use crate::net_config::{is_dhcp, share_with_store, stored_network};
use crate::nv_flash::OnChipFlash;
use crate::{Driver, Watchdog};

/// A `static` home for the adapter over a device `D`, with the board's diagnostics object in
/// front of it: `static ADAPTER: AdapterCell<MyDevice> = AdapterCell::new();`.
pub type AdapterCell<D> = enip_firmware::AdapterCell<Diagnosed<D>>;

/// What the board tells the diagnostics object: its stack (no fault trigger on hardware).
const PLATFORM: Platform = Platform {
    stack: crate::stack::measure,
    provoke: None,
};
/// How often the watchdog task checks the link task and feeds the watchdog.
const FEED_PERIOD: Duration = Duration::from_millis(500);
/// Sockets of the embassy-net stack: what the runtime needs, and one for DHCP.
const SOCKETS: usize = enip_firmware::SOCKETS + 1;

/// The link task's polls, watched by the watchdog task.
static HEARTBEAT: StaticCell<Heartbeat> = StaticCell::new();
static NET_RESOURCES: ConstStaticCell<StackResources<SOCKETS>> =
    ConstStaticCell::new(enip_firmware::stack_resources());
static FIRMWARE_RESOURCES: StaticCell<Resources> = StaticCell::new();
static LINK_FRAMES: ConstStaticCell<LinkFrames> = ConstStaticCell::new(LinkFrames::new());
/// The non-volatile store on the on-chip flash: the TCP/IP settings and the device's own.
static NV_STORE: StaticCell<RefCell<AbStore<OnChipFlash>>> = StaticCell::new();
/// The adapter's handle to it.
static NV_HANDLE: StaticCell<SharedStore> = StaticCell::new();

/// The chip, initialised by the board: what [`run`] builds the adapter from.
pub struct Hardware<L: Leds> {
    /// The MAC with its PHY, pins configured.
    pub driver: Driver,
    /// The MAC address the driver was given.
    pub mac: [u8; 6],
    /// A random seed (from the RNG) for the network stack and the adapter.
    pub seed: u64,
    /// The ODVA indicators.
    pub leds: L,
    /// The store on the on-chip flash ([`mount`]).
    pub store: SharedStore,
    /// The independent watchdog, not started yet.
    pub dog: Watchdog,
}

/// The store `store` in its `static` home, for [`Hardware::store`]. A plain function, so the
/// store's RAM image is never part of the `run` future.
pub fn mount(store: AbStore<OnChipFlash>) -> SharedStore {
    SharedStore::new(NV_STORE.init(RefCell::new(store)))
}

/// Runs the device `device` builds from the store in `hw`, shared in `home`, with the
/// interface configuration `network` (unless the store holds a static one); never returns.
pub async fn run<D: Device, L: Leds>(
    spawner: Spawner,
    home: &'static AdapterCell<D>,
    device: impl FnOnce(SharedStore) -> D,
    network: embassy_net::Config,
    hw: Hardware<L>,
) -> ! {
    let Hardware {
        driver,
        mac,
        seed,
        leds,
        store,
        dog,
    } = hw;
    let mut store = store;
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
        panic!("{}: run called twice", crate::BOARD);
    };
    let heart: &'static Heartbeat = HEARTBEAT.init(Heartbeat::new());
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
    info!("{}: MAC {=[u8]:02x}", crate::BOARD, mac);
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
async fn watchdog_task(mut dog: Watchdog, heart: &'static Heartbeat) -> ! {
    // A core halted by a debugger (a breakpoint, `probe-rs run` stopping at a fault) stops
    // the watchdog with it rather than being reset under the debugger.
    crate::freeze_watchdog_when_halted();
    dog.unleash();
    keep_fed(heart, FEED_PERIOD, || dog.pet()).await
}

/// The HardFault handler proper (see the shared `fault` entry), on a fresh stack: logs the
/// fault registers and resets.
pub extern "C" fn hard_fault(sp: u32) -> ! {
    let f = crate::fault::fault(sp);
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
