//! `enip_host`: any [`enip_stack::Device`] as an EtherNet/IP adapter on Linux, with one call:
//! on a TAP device with its own TCP/IP stack (`--tap`), or on the kernel's sockets at one of
//! the host's addresses (`--bind`, [`Link::Kernel`]).
//!
//! A device program's whole `main` is [`run_device`], which also prints the device's EDS
//! (`--eds`, from an [`enip_stack::eds::EdsInfo`]):
//!
//! ```no_run
//! # fn my_device() -> enip_profiles::Generic { enip_profiles::Generic::new() }
//! fn main() {
//!     let eds = enip_stack::eds::EdsInfo { vendor_name: "Acme", ..Default::default() };
//!     enip_host::run_device(my_device(), &eds)
//! }
//! ```
//!
//! A program with options of its own parses them with [`Command::from_env_args`] (or
//! [`Options::from_env_args`], without `--eds`) and calls [`run`]. The command line needs
//! either `--tap IFNAME --ip A.B.C.D/LEN` or `--bind A.B.C.D` (without them it says so, with
//! the usage, and exits 2); `--eds` and `--help` need neither. [`Options::new`] and
//! [`Options::bind`] build the options in code instead.
//!
//! On a TAP, [`run`] opens it (refusing one that does not exist, unless
//! [`TapOptions::create`]), builds the embassy-net stack with [`enip_firmware::SOCKETS`]
//! sockets and runs the firmware runtime on the main thread, on the executor of
//! [`enip_host_runtime`] (waiting in one `ppoll` on the TAP and the next timer); on kernel
//! sockets it drives the same [`enip_stack::Adapter`] from one `ppoll` event loop (TCP and
//! UDP 44818, UDP 2222). Either way it wraps the device in a [`enip_stack::Adapter`], logs
//! to stderr (`RUST_LOG`, default `info`), exits 0 on SIGINT or SIGTERM (on a TAP after the
//! LLDP shutdown frame, so that neighbours forget the adapter at once; on kernel sockets the
//! kernel owns the link and no LLDP runs) and 1 on any start-up error.
//! The TCP/IP settings a scanner sets are kept in the non-volatile store, a file with
//! [`Options::nv_file`] (`--nv-file`), so that a restart comes up at the address set; a
//! device profile keeps its saved settings in the same store ([`shared_store`]).
//!
//! [`run_fleet`] runs many devices in one process on the kernel's sockets, each at its own
//! address with its own store ([`own_store`]) and identity ([`Renamed`]), on one thread:
//! `enip-host --devices FILE` reads them from a device list ([`read_device_list`], or
//! [`parse_device_list`] from its text).

mod device_list;
mod device_log;
mod device_main;
mod kernel;
mod netlink;
mod nv_file;
mod options;
mod renamed;
mod runner;
mod signals;
mod tap;
mod tap_device;

pub use device_list::{
    parse as parse_device_list, read as read_device_list, DeviceEntry, MAX_DEVICES,
};
pub use device_main::{device_usage, run_device, Command};
pub use kernel::Spec as DeviceSpec;
pub use nv_file::own as own_store;
pub use nv_file::shared as shared_store;
pub use options::{Link, Options, Parsed, TapOptions, TlsOptions, DEFAULT_MAC, OPTIONS_USAGE};
pub use renamed::{Renamed, MAX_PRODUCT_NAME};
pub use runner::{run, run_fleet};

/// The running program's file name, for messages.
pub fn program_name() -> String {
    std::env::args()
        .next()
        .as_deref()
        .map(std::path::Path::new)
        .and_then(|p| p.file_name())
        .map_or_else(|| "enip-host".into(), |n| n.to_string_lossy().into_owned())
}
