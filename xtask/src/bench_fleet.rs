//! `cargo xtask bench --fleet`: a plant in one process. For N = 1, 16, 64, 128 and 256
//! devices, `enip-host --devices` runs N generic devices at N addresses of a veth pair
//! (198.19.0.1 onwards, in a namespace of its own); the project's `fleet_scanner`, in the
//! peers' namespace, holds one exclusive owner at 10 ms on every device and asks each one
//! explicit request (Get_Attribute_Single) a second, for 30 s (`--seconds`). Reported per N:
//! T->O datagrams lost (sequence gaps) and late (an interval over 2 RPIs), connections timed
//! out, explicit requests failed, the fleet process's CPU time (user + system) per
//! device-second over the run, and its resident memory, in all and per device.
//!
//! The fleet and the scanner run under SCHED_FIFO, as a plant's devices and its PLC would on
//! machines of their own: on this shared VM a process at normal priority is at times not
//! scheduled for hundreds of milliseconds, longer than the watchdog, which then times the
//! connections out whoever stalled.
//!
//! With `ENIP_OPENER_BIN` naming OpENer's POSIX build, the same runs against OpENer, one
//! process per device, for N = 1 and 16 ([`crate::bench_fleet_opener`]).
//!
//! Needs root (namespaces) and the release builds of `enip-host` and `fleet_scanner`, which
//! [`run_all`] makes. Writes `target/bench/fleet.json`.

use std::fs;
use std::net::Ipv4Addr;
use std::path::Path;
use std::time::Duration;

use enip_lab::netns::Lab;
use enip_lab::process::{run_bounded, LoggedChild, SIGTERM};
use serde_json::{json, Value};

use crate::bench_scale::Scale;
use crate::util::{self, cargo, err, run, Error, Result};

/// The fleet sizes measured.
pub const SIZES: [u32; 5] = [1, 16, 64, 128, 256];
/// The default length of each run, s.
pub const SECONDS: u64 = 30;
/// The owners' RPI.
const RPI_US: u32 = 10_000;
/// Their watchdog multiplier code: 2 (x16, 160 ms).
const MULTIPLIER: &str = "2";
/// The first device's address; the others follow (198.19.0.0/16, inside 198.18.0.0/15).
pub const FIRST: Ipv4Addr = Ipv4Addr::new(198, 19, 0, 1);
/// The peers' own address in that subnet.
pub const PEERS_IP: &str = "198.19.255.254/16";
/// The link device on the peers' side.
const LINK: &str = "enipfleet0";
/// SCHED_FIFO priority of the fleet and of the scanner.
const PRIORITY: &str = "10";
/// Bound for the fleet to open every device.
const START: Duration = Duration::from_secs(60);

/// Measures every size up to `max_devices` for `seconds` each, prints the table and writes
/// the report.
pub fn run_all(seconds: u64, max_devices: u32) -> Result {
    let report = measure(seconds, max_devices, Scale::Full)?;
    let path = Scale::Full.dir().join("fleet.json");
    fs::write(&path, report.to_string()).map_err(|e| Error(format!("{}: {e}", path.display())))?;
    println!("report: {}", path.display());
    Ok(())
}

/// Every size for [`SECONDS`] each (part of the whole `bench`); returns the report.
pub fn measure_all() -> Result<Value> {
    measure(SECONDS, 256, Scale::Full)
}

/// Measures N = 1 and 16 for 2 s each (`bench --check`); returns the report.
pub fn check() -> Result<Value> {
    measure(2, 16, Scale::Check)
}

/// Every size up to `max_devices`, `seconds` each; the JSON report, also printed as a table.
fn measure(seconds: u64, max_devices: u32, scale: Scale) -> Result<Value> {
    if !util::is_root() {
        return err("the fleet benchmark needs root (network namespaces)");
    }
    let host = scale.enip_host()?;
    run(cargo().args([
        "build",
        "--release",
        "-p",
        "host-tests",
        "--bin",
        "fleet_scanner",
    ]))?;
    let dir = scale.dir();
    fs::create_dir_all(&dir).map_err(|e| Error(format!("{}: {e}", dir.display())))?;
    let bin = util::target_dir().join("release");
    let mut runs = Vec::new();
    println!(
        "{:>11} {:>9} {:>6} {:>5} {:>8} {:>10} {:>9} {:>9} {:>12} {:>9} {:>10}",
        "devices",
        "T->O",
        "lost",
        "late",
        "timeouts",
        "expl. fail",
        "p99 us",
        "max us",
        "CPU us/dev-s",
        "RSS KiB",
        "KiB/device"
    );
    for n in SIZES.into_iter().filter(|n| *n <= max_devices) {
        let r = measure_size(&host, &bin, &dir, n, seconds)?;
        print_row(&n.to_string(), n, &r);
        runs.push(r);
    }
    let mut opener_runs = Vec::new();
    match std::env::var_os("ENIP_OPENER_BIN") {
        Some(opener) => {
            for n in crate::bench_fleet_opener::SIZES {
                let r =
                    crate::bench_fleet_opener::measure(opener.as_ref(), &bin, &dir, n, seconds)?;
                print_row(&format!("OpENer x{n}"), n, &r);
                opener_runs.push(r);
            }
        }
        None => println!("OpENer: not measured (set ENIP_OPENER_BIN to its POSIX build)"),
    }
    Ok(json!({"rpi_us": RPI_US, "seconds": seconds, "runs": runs, "opener": opener_runs}))
}

/// One line of the table: `label`, a run of `n` devices and its report `r`.
fn print_row(label: &str, n: u32, r: &Value) {
    let f = |k: &str| r[k].as_f64().unwrap_or(0.0);
    println!(
        "{:>11} {:>9} {:>6} {:>5} {:>8} {:>10} {:>9} {:>9} {:>12.1} {:>9} {:>10.1}",
        label,
        f("received"),
        f("lost"),
        f("late"),
        f("timeouts"),
        f("explicit_failed"),
        f("worst_p99_us"),
        f("worst_max_us"),
        f("cpu_us_per_device_second"),
        f("rss_kib"),
        f("rss_kib") / f64::from(n),
    );
}

/// Puts every thread of process `pid` under SCHED_FIFO [`PRIORITY`] (util-linux `chrt`).
pub fn real_time(pid: u32) -> Result {
    let status = std::process::Command::new("chrt")
        .args(["--fifo", "--all-tasks", "--pid", PRIORITY, &pid.to_string()])
        .status()
        .map_err(|e| Error(format!("chrt: {e}")))?;
    if status.success() {
        Ok(())
    } else {
        err(format!("chrt --fifo --pid {pid}: {status}"))
    }
}

/// `fleet_scanner` from `bin` in `ns` under SCHED_FIFO against `n` devices from [`FIRST`]
/// for `seconds`, measuring the processes `pids`.
pub fn scanner_command(
    ns: &enip_lab::netns::Namespace,
    bin: &Path,
    n: u32,
    seconds: u64,
    pids: &[u32],
) -> std::process::Command {
    let mut scanner = ns.command("chrt");
    scanner
        .args(["--fifo", PRIORITY])
        .arg(bin.join("fleet_scanner"))
        .args(["--first", &FIRST.to_string()])
        .args(["--devices", &n.to_string()])
        .args(["--rpi-us", &RPI_US.to_string()])
        .args(["--seconds", &seconds.to_string()])
        .args(["--multiplier", MULTIPLIER]);
    for pid in pids {
        scanner.args(["--measure-pid", &pid.to_string()]);
    }
    scanner
}

/// One fleet of `n` devices of the board `host` for `seconds`: the JSON report of the scanner
/// from `bin`.
fn measure_size(host: &Path, bin: &Path, dir: &Path, n: u32, seconds: u64) -> Result<Value> {
    let lab = Lab::create_veth(LINK)?;
    lab.ns()
        .exec_checked("ip", &["addr", "add", PEERS_IP, "dev", LINK])?;
    let cidrs: Vec<String> = (0..n)
        .map(|i| format!("{}/16", Ipv4Addr::from(u32::from(FIRST) + i)))
        .collect();
    lab.add_board_addresses(&cidrs)?;
    let list = dir.join(format!("fleet-{n}.toml"));
    let text = format!(
        "[[device]]\nname = \"dev-{{n}}\"\naddress = \"{FIRST}\"\ncount = {n}\n\
         profile = \"generic\"\nserial_number = 0xF1EE0001\n"
    );
    fs::write(&list, text).map_err(|e| Error(format!("{}: {e}", list.display())))?;
    let mut cmd = lab.board_command(host);
    cmd.arg("--devices").arg(&list).env("RUST_LOG", "warn");
    let mut fleet = LoggedChild::spawn("enip-host --devices", cmd)?;
    let last = Ipv4Addr::from(u32::from(FIRST) + n - 1);
    fleet.wait_for_line(&format!("dev-{n}: listening on {last} "), START)?;
    real_time(fleet.id())?;
    let scanner = scanner_command(lab.ns(), bin, n, seconds, &[fleet.id()]);
    // Opening 256 sessions and connections, and closing them, takes a few seconds.
    let out = run_bounded(scanner, None, Duration::from_secs(seconds + 120))?;
    let alive = fleet.exited().is_none();
    fleet.stop(SIGTERM, Duration::from_secs(3));
    if !out.status.success() || !alive {
        return err(format!(
            "{n} devices: the scanner {} ({}), the fleet {}; fleet log:\n{}",
            out.status,
            String::from_utf8_lossy(&out.stderr).trim(),
            if alive { "ran" } else { "ended" },
            fleet.tail(20)
        ));
    }
    serde_json::from_slice(&out.stdout)
        .map_err(|e| Error(format!("fleet_scanner printed no report: {e}")))
}
