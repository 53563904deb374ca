//! `enip-host`: the EtherNet/IP adapter on a Linux host, attached to an existing TAP device.

mod args;
mod nvram;
mod signals;
mod tap;

use std::process::exit;

use embassy_executor::{Executor, Spawner};
use embassy_net::{Ipv4Cidr, Runner, Stack, StackResources, StaticConfigV4};
use embassy_net_tuntap::TunTapDevice;
use firmware::{Profile, Resources, SharedAdapter};
use stack::Adapter;
use static_cell::{ConstStaticCell, StaticCell};

use args::{Args, Command};

/// Sockets of the embassy-net stack: 3 TCP + 2 UDP for the adapter, DHCP later, spares.
const SOCKETS: usize = 8;

static EXECUTOR: StaticCell<Executor> = StaticCell::new();
static NET_RESOURCES: StaticCell<StackResources<SOCKETS>> = StaticCell::new();
static ADAPTER: StaticCell<SharedAdapter<Profile>> = StaticCell::new();
static FIRMWARE_RESOURCES: ConstStaticCell<Resources> = ConstStaticCell::new(Resources::new());

fn main() {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("info")).init();
    let mut args = match args::parse(std::env::args().skip(1)) {
        Ok(Command::Run(a)) => a,
        Ok(Command::Help) => {
            println!("{}", args::USAGE);
            return;
        }
        Err(e) => {
            eprintln!("enip-host: {e}\n\n{}", args::USAGE);
            exit(2);
        }
    };
    if let Err(e) = nvram::set_up(&mut args) {
        eprintln!("enip-host: {e}");
        exit(1);
    }
    if let Err(e) = signals::exit_on_termination() {
        eprintln!("enip-host: cannot install signal handlers: {e}");
        exit(1);
    }
    let device = tap::open(&args.tap, args.create_tap).unwrap_or_else(|e| {
        eprintln!("enip-host: {e}");
        exit(1);
    });
    EXECUTOR.init(Executor::new()).run(|spawner| {
        if let Err(e) = start(spawner, device, *args) {
            eprintln!("enip-host: {e}");
            exit(1);
        }
    })
}

/// Builds the network stack on the TAP device and the adapter, and spawns their tasks.
fn start(spawner: Spawner, mut device: TunTapDevice, args: Args) -> Result<(), String> {
    device.set_hardware_address(args.mac);
    let config = embassy_net::Config::ipv4_static(StaticConfigV4 {
        address: Ipv4Cidr::new(args.ip, args.prefix_len),
        gateway: args.gateway,
        dns_servers: Default::default(),
    });
    let seed = seed();
    let (net, runner) = embassy_net::new(
        device,
        config,
        NET_RESOURCES.init(StackResources::new()),
        seed,
    );
    let name = args.profile.name();
    let adapter = Adapter::new(
        args.profile,
        firmware::network_config(net),
        seed.rotate_left(32),
    );
    let adapter = ADAPTER.init(firmware::share(adapter));
    let spawn_error = |e| format!("cannot spawn a task: {e:?}");
    spawner.spawn(net_task(runner).map_err(spawn_error)?);
    spawner.spawn(
        adapter_task(net, adapter, FIRMWARE_RESOURCES.take(), args.tap, name)
            .map_err(spawn_error)?,
    );
    Ok(())
}

/// A random seed for the network stack and the adapter, from the OS or else the clock.
fn seed() -> u64 {
    getrandom::u64().unwrap_or_else(|_| {
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0x5EED, |d| d.as_nanos() as u64)
    })
}

/// Moves frames between the TAP device and the network stack.
#[embassy_executor::task]
async fn net_task(mut runner: Runner<'static, TunTapDevice>) -> ! {
    runner.run().await
}

/// Runs the adapter, and announces it once the interface is up and the sockets listen.
#[embassy_executor::task]
async fn adapter_task(
    net: Stack<'static>,
    adapter: &'static SharedAdapter<Profile>,
    resources: &'static mut Resources,
    tap: String,
    profile: &'static str,
) -> ! {
    let announce = async {
        net.wait_config_up().await;
        let ip = net.config_v4().map(|c| c.address.address());
        // `run` was polled first by the join, so its sockets already listen.
        eprintln!(
            "enip-host: listening on {} (tap {tap}, profile {profile})",
            ip.map_or_else(|| "?".into(), |ip| ip.to_string())
        );
    };
    let (never, ()) =
        embassy_futures::join::join(firmware::run(net, adapter, resources, on_reset), announce)
            .await;
    never
}

/// Identity Reset: a host process does not restart itself, so it only reports the request.
fn on_reset(kind: u8) {
    log::warn!("identity reset (type {kind}) requested; the host board does not restart");
}
