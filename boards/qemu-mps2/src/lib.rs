//! `enip_qemu_mps2`: any [`enip_stack::Device`] as an EtherNet/IP adapter on QEMU's
//! `mps2-an386` machine (Cortex-M4 at 25 MHz, LAN9118 Ethernet at 0x4020_0000 on IRQ 13),
//! or with a cargo feature on `mps2-an385` (Cortex-M3), `mps2-an500` (Cortex-M7) or
//! `mps2-an505` (Cortex-M33, Secure state) ([`machine`]), with one call from the firmware's
//! `main`:
//!
//! ```ignore
//! #[embassy_executor::main]
//! async fn main(spawner: embassy_executor::Spawner) {
//!     static ADAPTER: enip_qemu_mps2::AdapterCell<my_device::MyDevice> =
//!         enip_qemu_mps2::AdapterCell::new();
//!     let device = |_store| my_device::MyDevice::new();
//!     let address = ([198, 18, 0, 2], 24, None);
//!     enip_qemu_mps2::run(spawner, &ADAPTER, "my device", device, address, true).await
//! }
//! ```
//!
//! [`run`] gives the [`lan9118`] driver to the link task (Class 1 I/O, then every other
//! frame on to embassy-net), builds the embassy-net stack and runs the adapter.
//! Time comes from the CMSDK timers ([`time`]), logs go to UART0 ([`uart`], QEMU's
//! standard output with `-nographic`). The call stack is painted at boot ([`stack`]) and its
//! high-water mark read through the diagnostics object (`enip_firmware::diagnostics`); the
//! CMSDK watchdog ([`watchdog`]) is fed while the executor and the link task run; a panic or
//! a HardFault (a stack overflow: the board links with flip-link, and an MPU guard
//! covers the bottom of the stack) is reported on UART0 and
//! resets the machine ([`faults`]).
#![no_std]

#[path = "../../shared/fault.rs"]
mod fault;
pub mod faults;
mod guard;
mod irq;
pub mod lan9118;
pub mod machine;
mod mmio;
#[path = "../../shared/stack.rs"]
pub mod stack;
pub mod time;
#[cfg(feature = "tls")]
mod tls;
pub mod uart;
pub mod watchdog;

/// The build-time test-image choice.
mod test_faults {
    include!(concat!(env!("OUT_DIR"), "/test_faults.rs"));
}

use core::cell::RefCell;
use core::net::Ipv4Addr;
use core::pin::pin;

use embassy_executor::Spawner;
use embassy_net::{Ipv4Cidr, Runner, Stack, StackResources, StaticConfigV4};
use embassy_time::Duration;
use enip_firmware::diagnostics::Platform;
use enip_firmware::link::{IoPort, LinkChecksums, LinkFrames, NetDriver};
use enip_firmware::watchdog::{beating, keep_fed, Heartbeat};
use enip_firmware::{Diagnosed, Resources};
use enip_stack::nv::{AbStore, RamFlash, SharedStore, IMAGE_SIZE, MAX_WRITE_SIZE};
use enip_stack::{Adapter, Device};
use faults::hard_fault;
use lan9118::Lan9118;
use static_cell::{ConstStaticCell, StaticCell};

/// A `static` home for the adapter over a device `D`, with the board's diagnostics object in
/// front of it: `static ADAPTER: AdapterCell<MyDevice> = AdapterCell::new();`.
pub type AdapterCell<D> = enip_firmware::AdapterCell<Diagnosed<D>>;

/// What the board tells the diagnostics object: its stack, and the fault trigger of test
/// images.
const PLATFORM: Platform = Platform {
    stack: stack::measure,
    provoke: if test_faults::TEST_FAULTS {
        Some(faults::provoke)
    } else {
        None
    },
};
/// How often the watchdog task checks the link task and feeds the watchdog.
const FEED_PERIOD: Duration = Duration::from_millis(250);
/// The link task's polls, watched by the watchdog task.
static HEARTBEAT: StaticCell<Heartbeat> = StaticCell::new();

/// Sockets of the embassy-net stack: what the runtime needs.
const SOCKETS: usize = enip_firmware::SOCKETS + if cfg!(feature = "tls") { 1 } else { 0 };

static NET_RESOURCES: ConstStaticCell<StackResources<SOCKETS>> =
    ConstStaticCell::new(enip_firmware::stack_resources());
static FIRMWARE_RESOURCES: StaticCell<Resources> = StaticCell::new();
/// The frames between the link task and embassy-net.
static LINK_FRAMES: ConstStaticCell<LinkFrames> = ConstStaticCell::new(LinkFrames::new());
/// The non-volatile store, in RAM: the TCP/IP settings and the device's own last until QEMU
/// exits.
static NV_STORE: StaticCell<RefCell<AbStore<RamFlash<NV_SECTOR>>>> = StaticCell::new();
/// The adapter's handle to it.
static NV_HANDLE: StaticCell<SharedStore> = StaticCell::new();
/// Bytes of a sector of the store's RAM flash: what one copy needs.
const NV_SECTOR: usize = MAX_WRITE_SIZE + IMAGE_SIZE;

/// Runs the device `device` builds from the board's non-volatile store (in RAM; a device
/// with nothing to save ignores it), shared in `home`, named `name` in the log, at the
/// static address `(address, prefix_len, gateway)`, probed for conflicts before use if `acd`
/// (and TCP/IP attribute 10 says so); never returns. Call it once, from the firmware's
/// `main` task.
pub async fn run<D: Device>(
    spawner: Spawner,
    home: &'static AdapterCell<D>,
    name: &str,
    device: impl FnOnce(SharedStore) -> D,
    address: ([u8; 4], u8, Option<[u8; 4]>),
    acd: bool,
) -> ! {
    let (net, adapter, _seed) = start(spawner, home, name, device, address, acd);
    let plaintext = enip_firmware::run(
        net,
        adapter,
        FIRMWARE_RESOURCES.init_with(Resources::new),
        on_reset,
    );
    #[cfg(feature = "tls")]
    let plaintext = tls::beside(net, adapter, _seed.rotate_left(17), plaintext);
    plaintext.await
}

/// [`run`]'s start: the machine, the driver, the network stack and the adapter set up and the
/// board's tasks spawned; the network stack, the shared adapter and the seed. Out of line
/// and not `async`: what it builds on the way (the driver, the adapter's parts) is on the
/// stack only while it runs, not in the `main` task's frame for good (68 KiB deep at boot
/// when it was inline).
#[inline(never)]
fn start<D: Device>(
    spawner: Spawner,
    home: &'static AdapterCell<D>,
    name: &str,
    device: impl FnOnce(SharedStore) -> D,
    (address, prefix_len, gateway): ([u8; 4], u8, Option<[u8; 4]>),
    acd: bool,
) -> (
    Stack<'static>,
    &'static enip_firmware::SharedAdapter<Diagnosed<D>>,
    u64,
) {
    stack::paint();
    guard::install();
    time::init();
    uart::init(log::LevelFilter::Info);
    let machine = machine::THIS;
    log::info!(
        "enip-qemu-mps2: booting on {} ({}), profile {name}",
        machine.name,
        machine.core
    );
    let driver = match Lan9118::new() {
        Ok(d) => d,
        Err(e) => panic!("LAN9118: {e:?}"),
    };
    let mac = driver.mac();
    let address = Ipv4Addr::from(address);
    let config = embassy_net::Config::ipv4_static(StaticConfigV4 {
        address: Ipv4Cidr::new(address, prefix_len),
        gateway: gateway.map(Ipv4Addr::from),
        dns_servers: Default::default(),
    });
    let seed = seed(mac);
    let frames: &'static LinkFrames = LINK_FRAMES.take();
    let (net_driver, link_checksums) = NetDriver::with_link_checksums(frames, &driver);
    let (net, runner) = embassy_net::new(net_driver, config, NET_RESOURCES.take(), seed);
    let adapter = share_adapter(home, device, mount_store(), net, seed.rotate_left(32), acd);
    let heart: &'static Heartbeat = HEARTBEAT.init(Heartbeat::new());
    match (
        net_task(runner),
        link_task(driver, frames, adapter, heart, link_checksums),
        watchdog_task(heart),
    ) {
        (Ok(net), Ok(link), Ok(dog)) => {
            spawner.spawn(net);
            spawner.spawn(link);
            spawner.spawn(dog);
        }
        _ => panic!("cannot spawn the network, link and watchdog tasks"),
    }
    // Each byte through `u32`'s hex formatter, which the image has already; a byte list's
    // Debug would add more.
    let [a, b, c, d, e, g] = mac.map(u32::from);
    log::info!(
        "enip-qemu-mps2: MAC {a:02x}:{b:02x}:{c:02x}:{d:02x}:{e:02x}:{g:02x}, listening on {address}/{prefix_len}"
    );
    (net, adapter, seed)
}

/// The adapter over the device `device` builds from the RAM store `store`, on the interface of
/// `net`, shared in `home` with the store attached, skipping conflict detection unless
/// `acd`. Out of line: its parts are on the stack only while it runs.
#[inline(never)]
fn share_adapter<D: Device>(
    home: &'static AdapterCell<D>,
    device: impl FnOnce(SharedStore) -> D,
    store: SharedStore,
    net: Stack<'static>,
    seed: u64,
    acd: bool,
) -> &'static enip_firmware::SharedAdapter<Diagnosed<D>> {
    let build = || {
        Adapter::new(
            Diagnosed::new(device(store), PLATFORM),
            enip_firmware::network_config(net),
            seed,
        )
    };
    let Some(adapter) = home.share(build) else {
        panic!("enip_qemu_mps2::run called twice");
    };
    enip_firmware::with_adapter(adapter, |a| attach_store(a, NV_HANDLE.init(store), acd));
    adapter
}

/// The RAM store, mounted. Out of line, called before [`share_adapter`]: its sector is built
/// on the stack before it moves into its static (10 KiB deep), apart from the adapter's parts.
#[inline(never)]
fn mount_store() -> SharedStore {
    SharedStore::new(NV_STORE.init(RefCell::new(AbStore::mount(RamFlash::new()))))
}

/// Attaches the RAM store to `adapter` (settings kept until power-off) and tells it to skip
/// conflict detection unless `acd`.
fn attach_store<D: Device>(
    adapter: &mut Adapter<Diagnosed<D>>,
    store: &'static mut SharedStore,
    acd: bool,
) {
    if let Err(e) = adapter.attach_store(store) {
        log::warn!("non-volatile store: {e}");
    }
    if !acd {
        log::info!("address conflict detection off in this image (ENIP_ACD=off)");
        adapter.skip_acd();
    }
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

/// Runs the TCP/IP stack on the frames the link task passes on.
#[embassy_executor::task]
async fn net_task(mut runner: Runner<'static, NetDriver<'static>>) -> ! {
    runner.run().await
}

/// Owns the LAN9118: Class 1 I/O, and every other frame to and from the network stack.
#[embassy_executor::task]
async fn link_task(
    driver: Lan9118,
    frames: &'static LinkFrames,
    adapter: &'static dyn IoPort,
    heart: &'static Heartbeat,
    checksums: LinkChecksums,
) -> ! {
    // The stack's checksums too (`NetDriver::with_link_checksums`): the image has the
    // flash to spare.
    // Its deadlines from the time driver's slot for it, not the queue (`time::LinkSlot`).
    let link = enip_firmware::link::run_with_link_checksums(
        driver,
        frames,
        adapter,
        checksums,
        &time::LinkSlot,
    );
    beating(heart, pin!(link)).await
}

/// Starts the watchdog and feeds it while the executor runs and the link task is polled.
#[embassy_executor::task]
async fn watchdog_task(heart: &'static Heartbeat) -> ! {
    watchdog::start();
    log::info!(
        "watchdog: fed every {} ms while the link task runs",
        FEED_PERIOD.as_millis()
    );
    keep_fed(heart, FEED_PERIOD, watchdog::feed).await
}

/// Identity Reset: restart the machine (QEMU resets it, or exits with `-no-reboot`).
fn on_reset(kind: u8) {
    log::warn!("identity reset (type {kind}): restarting");
    cortex_m::peripheral::SCB::sys_reset();
}
