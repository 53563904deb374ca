//! The reference stack beside `bench --fleet`: OpENer's POSIX sample application (the build
//! `ENIP_OPENER_BIN` names), one process per device as its global state demands, each in a
//! network namespace of its own (it binds the wildcard address for UDP 44818 and 2222, so two
//! cannot share one), one end of a veth pair each, the other ends in a bridge in the peers'
//! namespace; the same `fleet_scanner` run as against the fleet, its CPU time and resident
//! memory summed over the N processes.

use std::fs;
use std::net::Ipv4Addr;
use std::path::Path;
use std::time::Duration;

use enip_lab::netns::Namespace;
use enip_lab::process::{run_bounded, LoggedChild, SIGTERM};
use serde_json::Value;

use crate::bench_fleet::{real_time, scanner_command, FIRST, PEERS_IP};
use crate::util::{err, Error, Result};

/// The sizes OpENer is measured at (a namespace and a process each).
pub const SIZES: [u32; 2] = [1, 16];
/// The bridge in the peers' namespace.
const BRIDGE: &str = "enipbr0";
/// Each device's end of its veth pair, in its namespace.
const DEVICE_LINK: &str = "eth0";
/// How long the OpENer processes get to come up.
const START: Duration = Duration::from_secs(2);

/// One OpENer process and the namespace it runs in (dropped in this order).
struct Device {
    process: LoggedChild,
    _ns: Namespace,
}

/// `n` OpENer processes of `opener` for `seconds`, measured by `fleet_scanner` from `bin`
/// (working files in `dir`): the scanner's JSON report.
pub fn measure(opener: &Path, bin: &Path, dir: &Path, n: u32, seconds: u64) -> Result<Value> {
    let peers = Namespace::create()?;
    peers.exec_checked("ip", &["link", "add", BRIDGE, "type", "bridge"])?;
    peers.exec_checked("ip", &["addr", "add", PEERS_IP, "dev", BRIDGE])?;
    peers.exec_checked("ip", &["link", "set", BRIDGE, "up"])?;
    let mut devices = Vec::new();
    for i in 0..n {
        let ns = Namespace::create()?;
        let end = format!("enipo{i}");
        let peer = ["peer", "name", DEVICE_LINK, "netns", ns.name()];
        peers.exec_checked(
            "ip",
            &[&["link", "add", &end, "type", "veth"][..], &peer].concat(),
        )?;
        peers.exec_checked("ip", &["link", "set", &end, "master", BRIDGE, "up"])?;
        let ip = format!("{}/16", Ipv4Addr::from(u32::from(FIRST) + i));
        ns.exec_checked("ip", &["addr", "add", &ip, "dev", DEVICE_LINK])?;
        ns.exec_checked("ip", &["link", "set", DEVICE_LINK, "up"])?;
        // OpENer keeps its non-volatile data in its working directory.
        let work = dir.join(format!("opener-{i}"));
        fs::create_dir_all(&work).map_err(|e| Error(format!("{}: {e}", work.display())))?;
        let mut cmd = ns.command(opener);
        cmd.arg(DEVICE_LINK).current_dir(&work);
        devices.push(Device {
            process: LoggedChild::spawn("OpENer", cmd)?,
            _ns: ns,
        });
    }
    std::thread::sleep(START);
    for d in &mut devices {
        if d.process.exited().is_some() {
            return err(format!("OpENer ended: {}", d.process.tail(10)));
        }
        real_time(d.process.id())?;
    }
    let pids: Vec<u32> = devices.iter().map(|d| d.process.id()).collect();
    let scanner = scanner_command(&peers, bin, n, seconds, &pids);
    let out = run_bounded(scanner, None, Duration::from_secs(seconds + 120))?;
    for d in &mut devices {
        d.process.stop(SIGTERM, Duration::from_secs(3));
    }
    if !out.status.success() {
        return err(format!(
            "{n} OpENer processes: the scanner {} ({})",
            out.status,
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    serde_json::from_slice(&out.stdout)
        .map_err(|e| Error(format!("fleet_scanner printed no report: {e}")))
}
