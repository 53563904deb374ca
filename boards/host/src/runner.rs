//! [`run`]: a device on the TAP, on the host runtime's executor ([`enip_host_runtime`]), or
//! on the kernel's sockets ([`crate::kernel`]).

use std::future::{poll_fn, Future};
use std::os::fd::AsRawFd;
use std::os::unix::net::UnixStream;
use std::path::Path;
use std::pin::Pin;
use std::process::exit;

use crate::tap_device::TapDevice;
use embassy_executor::Spawner;
use embassy_futures::select::{select, Either};
use embassy_net::{Ipv4Cidr, Runner, StackResources, StaticConfigV4};
use embassy_time::{with_timeout, Duration};
use enip_firmware::link::{IoPort, LinkChecksums, LinkFrames, NetDriver};
use enip_firmware::Resources;
use enip_host_runtime::Readable;
use enip_stack::nv::SharedStore;
use enip_stack::objects::TcpIpState;
use enip_stack::{Adapter, Device};

use crate::nv_file;
use crate::options::{Link, TapOptions};
use crate::{kernel, program_name, signals, tap, Options};

/// Sockets of the embassy-net stack: what the adapter needs, and none to spare.
const SOCKETS: usize = enip_firmware::SOCKETS;

/// How long the LLDP shutdown frame may wait for the TAP on exit.
const SHUTDOWN_SEND: Duration = Duration::from_millis(200);

/// The adapter's whole run, type-erased so that one (non-generic) task can drive it.
type AdapterRun = Pin<&'static mut dyn Future<Output = ()>>;

/// Runs `device` on the TAP interface or the kernel address `options` names until SIGINT or
/// SIGTERM (exit 0); any start-up error is printed and exits 1.
pub fn run<D: Device + 'static>(device: D, options: Options) -> ! {
    crate::device_log::init();
    let program = program_name();
    // On the TAP the link task is told of the signal: it sends the LLDP shutdown frame.
    let (tell, told) = match options.link {
        Link::Tap(_) => UnixStream::pair().map_or_else(
            |e| {
                eprintln!("{program}: {e}");
                exit(1)
            },
            |(tell, told)| (Some(tell), Some(told)),
        ),
        Link::Kernel(_) => (None, None),
    };
    if let Err(e) = signals::exit_on_termination(tell) {
        eprintln!("{program}: cannot install signal handlers: {e}");
        exit(1);
    }
    match options.link {
        Link::Tap(ref link) => {
            let tap = tap::open(&link.name, link.create).unwrap_or_else(|e| {
                eprintln!("{program}: {e}");
                exit(1);
            });
            let store = open_store(&options, &program);
            run_tap(
                device,
                tap,
                store,
                link,
                options.nv_file.as_deref(),
                program,
                told,
            )
        }
        Link::Kernel(ip) => {
            let store = open_store(&options, &program);
            let device = kernel::Spec {
                label: None,
                ip,
                device,
                store,
                tls: options.tls.clone(),
            };
            kernel::run(vec![device], &program)
        }
    }
}

/// The non-volatile store `--nv-file` names (or one in RAM); exits 1 if it cannot be opened.
/// Runs every device of `devices` on the kernel's sockets at its own address, on this
/// thread, until SIGINT or SIGTERM (exit 0); any start-up error is printed, prefixed by the
/// device's label, and exits 1. Log lines of a device are prefixed by its label.
pub fn run_fleet<D: Device>(devices: Vec<kernel::Spec<D>>) -> ! {
    crate::device_log::init();
    let program = program_name();
    if let Err(e) = signals::exit_on_termination(None) {
        eprintln!("{program}: cannot install signal handlers: {e}");
        exit(1);
    }
    kernel::run(devices, &program)
}

fn open_store(options: &Options, program: &str) -> SharedStore {
    nv_file::shared(options.nv_file.as_deref()).unwrap_or_else(|e| {
        eprintln!("{program}: {e}");
        exit(1);
    })
}

/// Runs `device` on `tap` on this thread's executor ([`enip_host_runtime::run`]) until
/// `stop` becomes readable (then exits 0), or forever; exits 1 if the executor's wait fails.
fn run_tap<D: Device + 'static>(
    device: D,
    tap: TapDevice,
    store: SharedStore,
    link: &TapOptions,
    nv_file: Option<&Path>,
    program: String,
    stop: Option<UnixStream>,
) -> ! {
    let adapter_run = start(device, tap, store, link, nv_file, program, stop);
    let Err(e) = enip_host_runtime::run(|spawner: Spawner| {
        let Started {
            runner,
            link,
            adapter,
        } = adapter_run;
        match (net_task(runner), link_task(link), adapter_task(adapter)) {
            (Ok(net), Ok(link), Ok(adapter)) => {
                spawner.spawn(net);
                spawner.spawn(link);
                spawner.spawn(adapter);
            }
            _ => {
                eprintln!("{}: cannot spawn the adapter's tasks", program_name());
                exit(1);
            }
        }
    });
    eprintln!("{}: executor: {e}", program_name());
    exit(1)
}

/// What the three tasks of the TAP board run.
struct Started {
    /// The TCP/IP stack on the frames the link task passes on.
    runner: Runner<'static, NetDriver<'static>>,
    /// The link task: the TAP, Class 1 I/O and every other frame.
    link: LinkShare,
    /// The adapter's explicit side.
    adapter: AdapterRun,
}

/// The link task's share: the TAP, the frames it passes to the stack, the adapter, and what
/// becomes readable when the program is to stop.
struct LinkShare {
    tap: TapDevice,
    frames: &'static LinkFrames,
    io: &'static dyn IoPort,
    /// The stack was told the link task does its checksums (the TAP does none).
    checksums: LinkChecksums,
    stop: Option<UnixStream>,
}

/// Builds the network stack and the adapter: the network runner, the link task's share and
/// the adapter's run.
fn start<D: Device + 'static>(
    device: D,
    mut tap: TapDevice,
    mut store: SharedStore,
    link: &TapOptions,
    nv_file: Option<&Path>,
    program: String,
    stop: Option<UnixStream>,
) -> Started {
    tap.set_hardware_address(link.mac);
    let config = embassy_net::Config::ipv4_static(interface(&mut store, link, nv_file));
    let seed = seed();
    let resources: &'static mut StackResources<SOCKETS> =
        Box::leak(Box::new(enip_firmware::stack_resources()));
    let frames: &'static LinkFrames = Box::leak(Box::new(LinkFrames::new()));
    let (driver, checksums) = NetDriver::with_link_checksums(frames, &tap);
    let (net, runner) = embassy_net::new(driver, config, resources, seed);
    let name = device.identity().product_name;
    let mut adapter = Adapter::new(
        device,
        enip_firmware::network_config(net),
        seed.rotate_left(32),
    );
    if let Err(e) = adapter.attach_store(Box::leak(Box::new(store))) {
        log::error!("non-volatile store unreadable ({e}): factory TCP/IP settings");
    }
    if !link.acd {
        log::info!("address conflict detection off in this run (--acd off)");
        adapter.skip_acd();
    }
    let adapter: &'static _ = Box::leak(Box::new(enip_firmware::share(adapter)));
    let buffers: &'static mut Resources = Box::leak(Box::new(Resources::new()));
    let tap_name = link.name.clone();
    let run = async move {
        let announce = async {
            net.wait_config_up().await;
            let ip = net.config_v4().map(|c| c.address.address());
            // `run` was polled first by the join, so its sockets already listen.
            eprintln!(
                "{program}: listening on {} (tap {tap_name}, device {name:?})",
                ip.map_or_else(|| "?".into(), |ip| ip.to_string())
            );
        };
        embassy_futures::join::join(
            enip_firmware::run(net, adapter, buffers, on_reset),
            announce,
        )
        .await;
    };
    let run: &'static mut dyn Future<Output = ()> = Box::leak(Box::new(run));
    Started {
        runner,
        link: LinkShare {
            tap,
            frames,
            io: adapter,
            checksums,
            stop,
        },
        adapter: Pin::static_mut(run),
    }
}

/// The address to start with: the static interface configuration in the store, else
/// `--ip` and `--gateway`; says which in the log.
fn interface(store: &mut SharedStore, link: &TapOptions, nv_file: Option<&Path>) -> StaticConfigV4 {
    let from = nv_file.map_or_else(|| "RAM".into(), |p| p.display().to_string());
    let stored = TcpIpState::stored(store).unwrap_or_else(|e| {
        log::error!("non-volatile store {from}: {e}");
        None
    });
    if let Some(st) = stored.as_ref().filter(|st| st.config_control & 0x0F != 0) {
        log::warn!(
            "stored configuration control {:#x} asks for DHCP; this host adapter has none",
            st.config_control
        );
    }
    let Some(i) = stored.as_ref().and_then(|st| st.static_interface()) else {
        log::info!(
            "interface {}/{} from --ip (nothing stored in {from})",
            link.ip,
            link.prefix_len
        );
        return StaticConfigV4 {
            address: Ipv4Cidr::new(link.ip, link.prefix_len),
            gateway: link.gateway,
            dns_servers: Default::default(),
        };
    };
    let prefix = u32::from(i.netmask).count_ones() as u8;
    log::info!(
        "interface {}/{prefix} gateway {} from the stored TCP/IP configuration in {from} \
         (--ip {}/{} not used)",
        i.ip,
        i.gateway,
        link.ip,
        link.prefix_len
    );
    StaticConfigV4 {
        address: Ipv4Cidr::new(i.ip, prefix),
        gateway: (!i.gateway.is_unspecified()).then_some(i.gateway),
        dns_servers: i
            .dns
            .iter()
            .copied()
            .filter(|d| !d.is_unspecified())
            .collect(),
    }
}

/// A random seed for the network stack and the adapter, from the OS or else the clock.
pub(crate) fn seed() -> u64 {
    getrandom::u64().unwrap_or_else(|_| {
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0x5EED, |d| d.as_nanos() as u64)
    })
}

/// Runs the TCP/IP stack on the frames the link task passes on.
#[embassy_executor::task]
async fn net_task(mut runner: Runner<'static, NetDriver<'static>>) -> ! {
    runner.run().await
}

/// Owns the TAP: Class 1 I/O, LLDP, and every other frame to and from the network stack.
/// Told to stop, it sends the LLDP shutdown frame (the neighbours forget the adapter at
/// once) and exits 0.
#[embassy_executor::task]
async fn link_task(link: LinkShare) -> ! {
    let LinkShare {
        mut tap,
        frames,
        io,
        checksums,
        stop,
    } = link;
    let running = enip_firmware::link::run_with_link_checksums(
        &mut tap,
        frames,
        io,
        checksums,
        &enip_firmware::link::TimeQueue,
    );
    if let Either::First(never) = select(running, stop_requested(stop.as_ref())).await {
        match never {}
    }
    let _ = with_timeout(
        SHUTDOWN_SEND,
        enip_firmware::link::lldp_shutdown(&mut tap, io),
    )
    .await;
    exit(0)
}

/// Ready once `stop` is readable; never without one.
async fn stop_requested(stop: Option<&UnixStream>) {
    let Some(stop) = stop else {
        return std::future::pending().await;
    };
    let readable = Readable::new(stop.as_raw_fd());
    poll_fn(|cx| readable.poll_readable(cx)).await
}

/// Drives the adapter's run (it never ends).
#[embassy_executor::task]
async fn adapter_task(run: AdapterRun) {
    run.await
}

/// Identity Reset: a host process does not restart itself, so it only reports the request.
pub(crate) fn on_reset(kind: u8) {
    log::warn!("identity reset (type {kind}) requested; a host adapter does not restart");
}
