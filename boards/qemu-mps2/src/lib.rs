//! `enip_qemu_mps2`: any [`enip_stack::Device`] as an EtherNet/IP adapter on QEMU's
//! `mps2-an386` machine (Cortex-M4 at 25 MHz, LAN9118 Ethernet at 0x4020_0000 on IRQ 13),
//! with one call from the firmware's `main`:
//!
//! ```ignore
//! #[embassy_executor::main]
//! async fn main(spawner: embassy_executor::Spawner) {
//!     let device = |_store| my_device::MyDevice::new();
//!     enip_qemu_mps2::run(spawner, "my device", device, [198, 18, 0, 2], 24, None).await
//! }
//! ```
//!
//! [`run`] builds the embassy-net stack over the [`lan9118`] driver and runs the adapter.
//! Time comes from the CMSDK timers ([`time`]), logs go to UART0 ([`uart`], QEMU's
//! standard output with `-nographic`); a panic is reported there too.
#![no_std]

mod irq;
pub mod lan9118;
mod mmio;
pub mod time;
pub mod uart;

use core::cell::RefCell;
use core::net::Ipv4Addr;

use embassy_executor::Spawner;
use embassy_net::{Ipv4Cidr, Runner, StackResources, StaticConfigV4};
use enip_firmware::Resources;
use enip_stack::nv::{AbStore, RamFlash, SharedStore, IMAGE_SIZE, MAX_WRITE_SIZE};
use enip_stack::{Adapter, Device};
use lan9118::Lan9118;
use static_cell::{ConstStaticCell, StaticCell};

/// Sockets of the embassy-net stack: what the runtime needs.
const SOCKETS: usize = enip_firmware::SOCKETS;

static NET_RESOURCES: ConstStaticCell<StackResources<SOCKETS>> =
    ConstStaticCell::new(enip_firmware::stack_resources());
static FIRMWARE_RESOURCES: StaticCell<Resources> = StaticCell::new();
/// The non-volatile store, in RAM: the TCP/IP settings and the device's own last until QEMU
/// exits.
static NV_STORE: StaticCell<RefCell<AbStore<RamFlash<NV_SECTOR>>>> = StaticCell::new();
/// The adapter's handle to it.
static NV_HANDLE: StaticCell<SharedStore> = StaticCell::new();
/// Bytes of a sector of the store's RAM flash: what one copy needs.
const NV_SECTOR: usize = MAX_WRITE_SIZE + IMAGE_SIZE;

/// Runs the device `device` builds from the board's non-volatile store (in RAM; a device
/// with nothing to save ignores it), named `name` in the log, at the static address
/// `address`/`prefix_len` (gateway optional); never returns. Call it once, from the
/// firmware's `main` task.
pub async fn run<D: Device>(
    spawner: Spawner,
    name: &str,
    device: impl FnOnce(SharedStore) -> D,
    address: [u8; 4],
    prefix_len: u8,
    gateway: Option<[u8; 4]>,
) -> ! {
    time::init();
    uart::init(log::LevelFilter::Info);
    log::info!("enip-qemu-mps2: booting (profile {name})");
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
    let (net, runner) = embassy_net::new(driver, config, NET_RESOURCES.take(), seed);
    let store = SharedStore::new(NV_STORE.init(RefCell::new(AbStore::mount(RamFlash::new()))));
    // Built inside the call, so the main task's future holds one adapter, not two.
    let adapter = enip_firmware::share(with_store(
        Adapter::new(
            device(store),
            enip_firmware::network_config(net),
            seed.rotate_left(32),
        ),
        NV_HANDLE.init(store),
    ));
    match net_task(runner) {
        Ok(task) => spawner.spawn(task),
        Err(e) => panic!("cannot spawn the network task: {e:?}"),
    }
    log::info!("enip-qemu-mps2: MAC {mac:02x?}, listening on {address}/{prefix_len}");
    enip_firmware::run(
        net,
        &adapter,
        FIRMWARE_RESOURCES.init_with(Resources::new),
        on_reset,
    )
    .await
}

/// `adapter` with the RAM store attached (settings kept until power-off).
fn with_store<D: Device>(mut adapter: Adapter<D>, store: &'static mut SharedStore) -> Adapter<D> {
    if let Err(e) = adapter.attach_store(store) {
        log::warn!("non-volatile store: {e:?}");
    }
    adapter
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
