//! `cargo xtask bench`: benchmarks, never timed tests. Writes `target/bench/report.json`
//! and prints a table:
//!
//! - first, the boards' footprint ([`crate::footprint`], its own `footprint.json`);
//! - instructions per Class 1 cycle (consume one O->T, produce one T->O) from callgrind, as
//!   the difference of two runs of different lengths so set-up cancels out;
//! - nanoseconds per cycle, natively (median of three runs);
//! - on the host TAP: 10 connections at a 1 ms RPI for 60 s, T->O intervals per connection,
//!   packets lost and connections timed out, measured by the project's scanner;
//! - on the emulated Cortex-M board, instructions per Class 1 cycle with a breakdown by part,
//!   and 10 connections at 1 ms and 2 ms ([`crate::bench_qemu`]);
//! - a plant in one process: N = 1 to 256 devices of one `enip-host --devices`, each with an
//!   owner at 10 ms and an explicit request a second ([`crate::bench_fleet`]);
//! - beside it, the host's own floor: a plain thread sleeping to 1 ms deadlines for 10 s. On
//!   a shared virtual machine its p99 already exceeds 1.1 ms, and no program here can beat it.

use std::fs;
use std::process::{Command, Stdio};

use crate::bench_scale::Scale;
use crate::util::{self, cargo, err, output, run, Result};
use enip_lab::netns::BOARD_IP;
use enip_lab::rig::{Board, Options, Rig};
use enip_lab::scanner::{self as scanner_run, ScannerRun};

/// The TAP run: connections and RPI (its length is the [`Scale`]'s).
const TAP_CONNECTIONS: u32 = 10;
const TAP_RPI_US: u32 = 1_000;
/// The TAP run's watchdog: multiplier code 3 is x32, 32 ms at a 1 ms RPI. This machine's own
/// scheduling stalls reach 15-20 ms (see the timer baseline), which a x16 watchdog mistakes
/// for a dead originator.
const TAP_MULTIPLIER: &str = "3";
/// Runs every benchmark at `scale` and writes the report.
pub fn run_all(scale: Scale) -> Result {
    // The check leaves the footprint to its own step of `cargo xtask test`, just before.
    if scale == Scale::Full {
        crate::footprint::footprint()?;
    }
    // Two builds: together, cargo would build the stack with the host board's `log` feature
    // for the drivers too, and the counts are the stack's as a device builds it by default.
    let host = scale.enip_host()?;
    run(cargo().args(["build", "--release", "-p", "host-tests", "--bins"]))?;
    let bin = util::target_dir().join("release");
    let cycle = bin.join("io_cycle");
    let cycle = cycle.to_str().unwrap_or("io_cycle");

    let dir = scale.dir();
    fs::create_dir_all(&dir).map_err(|e| util::Error(format!("{}: {e}", dir.display())))?;
    let (short, long, per_cycle) = per_iteration(cycle, scale)?;
    let explicit = bin.join("explicit_cycle");
    let explicit = per_iteration(explicit.to_str().unwrap_or("explicit_cycle"), scale)?;
    let in_runtime = bin.join("io_runtime");
    let in_runtime = per_iteration(in_runtime.to_str().unwrap_or("io_runtime"), scale)?;

    let (native_cycles, native_runs) = scale.native();
    let mut ns: Vec<f64> = (0..native_runs)
        .map(|_| native_ns(cycle, native_cycles))
        .collect::<Result<_>>()?;
    ns.sort_by(f64::total_cmp);
    let ns_median = ns[ns.len() / 2];

    let (tap_seconds, baseline_seconds) = scale.tap_seconds();
    let baseline =
        output(Command::new(bin.join("timer_baseline")).arg(baseline_seconds.to_string()))
            .ok_or_else(|| util::Error("timer_baseline failed".into()))?;
    let tap = tap_run(&host, &bin, &dir, tap_seconds)?;
    let qemu = crate::bench_qemu::run_all(scale)?;
    let host_runtime = crate::bench_host::measure(scale)?;
    let fleet = match scale {
        Scale::Full => crate::bench_fleet::measure_all()?,
        Scale::Check => crate::bench_fleet::check()?,
    };

    let parsed =
        |doc: &str| serde_json::from_str::<serde_json::Value>(doc.trim()).unwrap_or_default();
    let cycles = scale.callgrind_cycles();
    let report = serde_json::json!({
        "class1_cycle": {
            "instructions_per_cycle": (per_cycle * 10.0).round() / 10.0,
            "callgrind_runs": [[cycles.0, short], [cycles.1, long]],
            "ns_per_cycle_median": (ns_median * 10.0).round() / 10.0,
            "ns_per_cycle_runs": ns,
        },
        "class1_cycle_as_the_link_task_calls": {
            "instructions_per_cycle": (in_runtime.2 * 10.0).round() / 10.0,
            "callgrind_runs": [[cycles.0, in_runtime.0], [cycles.1, in_runtime.1]],
        },
        "explicit_request": {
            "instructions_per_get_attribute_single": (explicit.2 * 10.0).round() / 10.0,
            "callgrind_runs": [[cycles.0, explicit.0], [cycles.1, explicit.1]],
        },
        "timer_baseline": parsed(&baseline),
        "tap": parsed(&tap),
        "qemu": qemu,
        "host_runtime": host_runtime,
        "fleet": fleet,
    })
    .to_string();
    let path = dir.join("report.json");
    fs::write(&path, &report).map_err(|e| util::Error(format!("{}: {e}", path.display())))?;
    println!();
    println!("{:<52} {:>12}", "benchmark", "value");
    println!(
        "{:<52} {:>12.1}",
        "instructions per Class 1 cycle (callgrind)", per_cycle
    );
    println!(
        "{:<52} {:>12.1}",
        "the same as the link task calls it (io_runtime)", in_runtime.2
    );
    println!(
        "{:<52} {:>12.1}",
        "ns per Class 1 cycle (native, median)", ns_median
    );
    println!(
        "{:<52} {:>12.1}",
        "stack instructions per Get_Attribute_Single (callgrind)", explicit.2
    );
    let tap_run_name = format!("TAP 10 x 1 ms, {tap_seconds} s");
    let rows: [(String, &str, &str); 6] = [
        (
            format!("{tap_run_name}: worst p99 T->O interval (us)"),
            &tap,
            "worst_p99_us",
        ),
        (
            format!("{tap_run_name}: worst max T->O interval (us)"),
            &tap,
            "worst_max_us",
        ),
        (format!("{tap_run_name}: packets lost"), &tap, "total_lost"),
        (
            format!("{tap_run_name}: connections timed out"),
            &tap,
            "timeouts",
        ),
        (
            "host floor: 1 ms sleep loop p99 interval (us)".into(),
            &baseline,
            "p99_us",
        ),
        (
            "host floor: 1 ms sleep loop max interval (us)".into(),
            &baseline,
            "max_us",
        ),
    ];
    for (name, doc, key) in rows {
        let v = crate::json::number(doc, key).map_or("?".to_string(), |n| n.to_string());
        println!("{name:<52} {v:>12}");
    }
    println!("report: {}", path.display());
    Ok(())
}

/// The figures every report must hold, as JSON pointers.
const FIGURES: [&str; 34] = [
    "/class1_cycle/instructions_per_cycle",
    "/class1_cycle/ns_per_cycle_median",
    "/class1_cycle_as_the_link_task_calls/instructions_per_cycle",
    "/explicit_request/instructions_per_get_attribute_single",
    "/timer_baseline/p99_us",
    "/tap/worst_p99_us",
    "/tap/total_lost",
    "/tap/timeouts",
    "/qemu/instructions_per_cycle/0/per_cycle",
    "/qemu/instructions_per_cycle/1/per_cycle",
    "/qemu/latency/o_t_to_write_assembly/instructions",
    "/qemu/latency/change_of_state_to_driver/instructions",
    "/qemu/latency/application_triggered_to_driver/instructions",
    "/qemu/explicit/instructions_per_request",
    "/qemu/timing/0/worst_p99_us",
    "/qemu/timing/1/worst_p99_us",
    "/qemu/cores/mps2-an385/instructions_per_cycle/0/per_cycle",
    "/qemu/cores/mps2-an500/instructions_per_cycle/0/per_cycle",
    "/qemu/cores/mps2-an505/instructions_per_cycle/0/per_cycle",
    "/host_runtime/enip-host --tap/instructions_per_cycle",
    "/host_runtime/enip-host --tap/context_switches_per_cycle",
    "/host_runtime/enip-host --tap/requests_per_second_3_sessions",
    "/host_runtime/enip-host --bind/instructions_per_cycle",
    "/host_runtime/enip-host --bind/context_switches_per_cycle",
    "/host_runtime/enip-host --bind/requests_per_second_1_session",
    "/host_runtime/enip-host --bind/requests_per_second_3_sessions",
    "/host_runtime/enip-host --bind/cpu_us_per_request_3_sessions",
    "/host_runtime/enip-host --bind/cpu_us_per_request_at_common_rate",
    "/host_runtime/enip-host --tap/instructions_per_request_3_sessions",
    "/host_runtime/enip-host --bind/instructions_per_request_3_sessions",
    "/fleet/runs/1/lost",
    "/fleet/runs/1/timeouts",
    "/fleet/runs/1/cpu_us_per_device_second",
    "/fleet/runs/1/rss_kib",
];

/// `cargo xtask bench --check` (a step of `cargo xtask test`): every part of the benchmark
/// once and briefly, then that its report holds every figure as a number. What the figures
/// say is the benchmark's business, not a test's.
pub fn check() -> Result {
    run_all(Scale::Check)?;
    let path = Scale::Check.dir().join("report.json");
    let text =
        fs::read_to_string(&path).map_err(|e| util::Error(format!("{}: {e}", path.display())))?;
    let report: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| util::Error(format!("{}: {e}", path.display())))?;
    let missing: Vec<&str> = FIGURES
        .iter()
        .copied()
        .filter(|f| report.pointer(f).and_then(|v| v.as_f64()).is_none())
        .collect();
    if missing.is_empty() {
        println!("bench check: all {} figures reported", FIGURES.len());
        Ok(())
    } else {
        err(format!(
            "{}: no figure at {}",
            path.display(),
            missing.join(", ")
        ))
    }
}

/// Instructions per iteration of the driver program `bin` (`io_cycle`, `io_runtime`,
/// `explicit_cycle`):
/// the short and long runs' totals and their difference per iteration.
fn per_iteration(bin: &str, scale: Scale) -> Result<(u64, u64, f64)> {
    let (a, b) = scale.callgrind_cycles();
    let short = callgrind(bin, a, scale)?;
    let long = callgrind(bin, b, scale)?;
    let per = long.saturating_sub(short) as f64 / (b - a) as f64;
    Ok((short, long, per))
}

/// Total instructions of `bin cycles` under callgrind.
fn callgrind(bin: &str, cycles: u64, scale: Scale) -> Result<u64> {
    let name = bin.rsplit('/').next().unwrap_or(bin);
    let out_file = scale.dir().join(format!("callgrind.{name}.{cycles}.out"));
    let o = Command::new("valgrind")
        .args([
            "--tool=callgrind",
            &format!("--callgrind-out-file={}", out_file.display()),
            bin,
            &cycles.to_string(),
        ])
        .stdout(Stdio::null())
        .output()
        .map_err(|e| util::Error(format!("valgrind: {e}")))?;
    if !o.status.success() {
        return err(format!(
            "valgrind {bin}: {}",
            String::from_utf8_lossy(&o.stderr)
        ));
    }
    callgrind_total(&out_file)
}

/// The total instruction count of a callgrind profile (its `totals:` or `summary:` line).
pub(crate) fn callgrind_total(path: &std::path::Path) -> Result<u64> {
    let text =
        fs::read_to_string(path).map_err(|e| util::Error(format!("{}: {e}", path.display())))?;
    text.lines()
        .find_map(|l| {
            l.strip_prefix("totals:")
                .or_else(|| l.strip_prefix("summary:"))
        })
        .and_then(|v| v.split_whitespace().next()?.parse().ok())
        .ok_or_else(|| util::Error(format!("{}: no totals line", path.display())))
}

/// Nanoseconds per cycle of one native run.
fn native_ns(cycle: &str, cycles: u64) -> Result<f64> {
    let out = output(Command::new(cycle).arg(cycles.to_string()))
        .ok_or_else(|| util::Error("io_cycle failed".into()))?;
    crate::json::find(&out, "ns_per_cycle")
        .and_then(|v| v.as_f64())
        .ok_or_else(|| util::Error(format!("io_cycle printed {out:?}")))
}

/// The host board `host` on a TAP with [`TAP_CONNECTIONS`] at [`TAP_RPI_US`] for `seconds`,
/// measured by the project's scanner from `bin` (files in `dir`); returns its JSON report.
fn tap_run(
    host: &std::path::Path,
    bin: &std::path::Path,
    dir: &std::path::Path,
    seconds: u32,
) -> Result<String> {
    if !util::is_root() {
        return err("the TAP benchmark needs root (network namespaces)");
    }
    let log = dir.join("board.log");
    let board = Board::Host {
        bin: host,
        profile: "generic",
        extra: &[],
        answers_at: BOARD_IP,
    };
    let mut rig = Rig::launch(board, &Options::logged("enipbench0", &log))?;
    let json = dir.join("tap.json");
    let run = ScannerRun {
        bin: &bin.join("scanner"),
        connections: TAP_CONNECTIONS,
        rpi_us: TAP_RPI_US,
        seconds,
        multiplier: TAP_MULTIPLIER,
        json: &json,
    };
    let (_, report) = scanner_run::run(rig.ns(), &run)
        .map_err(|e| util::Error(format!("scanner: {e}; board log: {}", log.display())))?;
    rig.check_alive()?;
    Ok(report.to_string())
}
