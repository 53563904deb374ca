//! `fleet_scanner`: one exclusive owner on each of N devices at consecutive addresses (the
//! generic profile of a fleet), all at one RPI, plus one explicit request per device per
//! second, for a while; prints JSON: T->O lost and late, connections timed out, explicit
//! requests failed, and with `--measure-pid` (repeated for several) the CPU time over the run
//! and the resident memory of those processes, summed.

use std::net::Ipv4Addr;
use std::process::ExitCode;
use std::time::Duration;

use host_tests::scanner::fleet::{open_owners, run, FleetRecord};
use host_tests::scanner::stats::connection_stats;

struct Args {
    first: Ipv4Addr,
    devices: u32,
    rpi_us: u32,
    seconds: u64,
    multiplier: u8,
    /// Processes whose CPU time and resident memory are summed (`--measure-pid`, repeated).
    measure_pids: Vec<u32>,
}

const USAGE: &str = "usage: fleet_scanner --first IP --devices N [--rpi-us US] [--seconds S] \
                     [--multiplier CODE] [--measure-pid PID]...";

fn parse() -> Result<Args, String> {
    let mut a = Args {
        first: Ipv4Addr::new(198, 19, 0, 1),
        devices: 1,
        rpi_us: 10_000,
        seconds: 30,
        multiplier: 2,
        measure_pids: Vec::new(),
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let value = it
            .next()
            .ok_or_else(|| format!("{flag} needs a value\n{USAGE}"))?;
        let bad = |e: &dyn std::fmt::Display| format!("{flag}: {e}");
        match flag.as_str() {
            "--first" => a.first = value.parse().map_err(|e| bad(&e))?,
            "--devices" => a.devices = value.parse().map_err(|e| bad(&e))?,
            "--rpi-us" => a.rpi_us = value.parse().map_err(|e| bad(&e))?,
            "--seconds" => a.seconds = value.parse().map_err(|e| bad(&e))?,
            "--multiplier" => a.multiplier = value.parse().map_err(|e| bad(&e))?,
            "--measure-pid" => a.measure_pids.push(value.parse().map_err(|e| bad(&e))?),
            _ => return Err(USAGE.into()),
        }
    }
    Ok(a)
}

/// User and system CPU time of the processes `pids`, in seconds.
fn cpu_seconds(pids: &[u32]) -> f64 {
    pids.iter().map(|p| cpu_seconds_of(*p)).sum()
}

/// User and system CPU time of process `pid`, in seconds (0 if unreadable).
fn cpu_seconds_of(pid: u32) -> f64 {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
    // Fields after the command name (which may hold spaces): state is field 3, utime 14.
    let rest = stat.rsplit_once(')').map_or("", |(_, r)| r);
    let fields: Vec<u64> = rest
        .split_whitespace()
        .map(|f| f.parse().unwrap_or(0))
        .collect();
    let ticks = fields.get(11).unwrap_or(&0) + fields.get(12).unwrap_or(&0);
    ticks as f64 / rustix::param::clock_ticks_per_second() as f64
}

/// Resident memory of the processes `pids`, KiB.
fn rss_kib(pids: &[u32]) -> u64 {
    pids.iter().map(|p| rss_kib_of(*p)).sum()
}

/// Resident memory of process `pid`, KiB (0 if unreadable).
fn rss_kib_of(pid: u32) -> u64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmRSS:"))
        .and_then(|v| v.split_whitespace().next()?.parse().ok())
        .unwrap_or(0)
}

fn main() -> ExitCode {
    match parse().and_then(|a| measure(&a)) {
        Ok(doc) => {
            println!("{doc}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("fleet_scanner: {e}");
            ExitCode::FAILURE
        }
    }
}

fn measure(a: &Args) -> Result<serde_json::Value, String> {
    let targets: Vec<Ipv4Addr> = (0..a.devices)
        .map(|i| Ipv4Addr::from(u32::from(a.first) + i))
        .collect();
    let mut owned = open_owners(&targets, a.rpi_us, a.multiplier).map_err(|e| e.to_string())?;
    let rpi = Duration::from_micros(u64::from(a.rpi_us));
    let duration = Duration::from_secs(a.seconds);
    let (mut cpu_start, mut cpu_end) = (0.0, 0.0);
    let record = run(
        &mut owned,
        rpi,
        duration,
        || cpu_start = cpu_seconds(&a.measure_pids),
        || cpu_end = cpu_seconds(&a.measure_pids),
    )
    .map_err(|e| format!("run: {e}"))?;
    let rss = rss_kib(&a.measure_pids);
    let mut closed_gone = vec![false; owned.len()];
    for (o, gone) in owned.iter_mut().zip(&mut closed_gone) {
        // A connection the device timed out is no longer there to close (0x01/0x0107).
        *gone = !matches!(o.session.forward_close(o.opened.triad), Ok(r) if r.general == 0);
    }
    Ok(report(a, &record, &closed_gone, cpu_end - cpu_start, rss))
}

/// The run's figures as JSON.
fn report(
    a: &Args,
    record: &FleetRecord,
    closed_gone: &[bool],
    cpu: f64,
    rss_kib: u64,
) -> serde_json::Value {
    let rpi = u64::from(a.rpi_us);
    let end = a.seconds * 1_000_000;
    // The watchdog: the connection's timeout (4 << multiplier RPIs).
    let quiet = rpi * (4u64 << a.multiplier);
    let (mut received, mut lost, mut late, mut timeouts) = (0, 0, 0, 0);
    let (mut worst_p99, mut worst_max) = (0, 0);
    for (packets, gone) in record.packets.iter().zip(closed_gone) {
        let s = connection_stats(0, packets);
        received += s.received;
        lost += s.lost;
        worst_p99 = worst_p99.max(s.p99_us);
        worst_max = worst_max.max(s.max_us);
        // Late: a datagram more than one RPI after the one before was due (interval > 2 RPI).
        late += packets
            .windows(2)
            .filter(|w| w[1].0.saturating_sub(w[0].0) > 2 * rpi)
            .count();
        let silent_at_end = packets
            .last()
            .is_none_or(|(t, _)| end.saturating_sub(*t) > quiet);
        if *gone || silent_at_end {
            timeouts += 1;
        }
    }
    let device_seconds = f64::from(a.devices) * a.seconds as f64;
    serde_json::json!({
        "devices": a.devices,
        "rpi_us": a.rpi_us,
        "seconds": a.seconds,
        "sent": record.sent,
        "received": received,
        "expected": u64::from(a.devices) * end / rpi,
        "lost": lost,
        "late": late,
        "timeouts": timeouts,
        "worst_p99_us": worst_p99,
        "worst_max_us": worst_max,
        "explicit_ok": record.explicit_ok,
        "explicit_failed": record.explicit_failed,
        "explicit_worst_us": record.explicit_worst_us,
        "cpu_seconds": cpu,
        "cpu_us_per_device_second": if device_seconds > 0.0 { cpu * 1e6 / device_seconds } else { 0.0 },
        "rss_kib": rss_kib,
    })
}
