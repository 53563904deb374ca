//! The microcontroller's part of `cargo xtask bench`: instructions the Cortex-M firmware
//! executes per Class 1 cycle on the emulated board (QEMU mps2-an386, release image, default
//! profile), whole firmware, broken down by part; and how the untraced board keeps up with
//! 10 connections at 1 ms and at 2 ms.
//!
//! `ENIP_QEMU_BENCH_ELF` measures a given image instead of today's (a before/after comparison).
//!
//! Counting: QEMU runs with `-d in_asm,exec,nochain`, its log written into a FIFO and read here
//! as it comes. `in_asm` gives every translation block's address and instructions when it is
//! translated; `exec` with `nochain` logs every execution of a block. The executor's idle loop
//! is left out: QEMU treats WFE as a no-op, so an idle M4 spins in `Executor::run`, and every
//! stretch between two WFEs that ran nothing outside that function is dropped. A cycle is one
//! O->T datagram handed to the adapter (a call of [`MARKER`]) and the T->O datagram the
//! board produces at the same RPI: after 100 datagrams per connection, the next 300 per
//! connection are counted ([`Scale::qemu_traced`]). The count does not depend on the host's speed, only
//! on how many datagrams one wake-up of the board finds waiting, which varies with the phase
//! of the scanner's clock: the median of three runs is reported. Each run also writes its
//! instructions per cycle by translation block (address, count, function) and the calls
//! per cycle of each function by calling block to `blocks-N.txt` beside the logs, for
//! attribution within a function.

use std::fs;
use std::path::Path;
use std::process::Command;
use std::thread;

use enip_lab::netns::Namespace;
use enip_lab::peers;
use enip_lab::rig::{Board, Options, Rig};
use enip_lab::scanner::{self as scanner_run, ScannerRun};

use crate::bench_qemu_trace::{count, Cost, Marks, Symbols};
use crate::bench_scale::Scale;
use crate::boards;
use crate::qemu;
use crate::util::{self, err, loud, run, Result};

/// Names an `enip-qemu-mps2` ELF to measure instead of building one (e.g. an older
/// commit's, for a before/after comparison).
const ELF_VAR: &str = "ENIP_QEMU_BENCH_ELF";
/// Set, `cargo xtask bench --qemu` makes one traced run and nothing else, a quick figure
/// while working on the firmware: of 1 connection, or with `explicit` of the requests.
const QUICK_VAR: &str = "ENIP_QEMU_BENCH_QUICK";
/// The function called once per O->T datagram (the adapter's Class 1 receive, called through
/// `IoPort`, so never inlined): the cycle counter.
pub const MARKER: &str =
    "<enip_firmware::shared::SharedAdapter<D,_,_,_,_> as enip_firmware::link::io_port::IoPort>::receive";
/// The function called once per explicit request read from TCP: the request counter.
const REQUEST_MARKER: &str =
    "enip_stack::tcp::app::<impl enip_stack::tcp::TcpApp for enip_stack::adapter::Adapter<D,_,_,_,_>>::receive";
/// The device's Class 1 write (the generic profile's): where O->T data reaches it, and where
/// it marks its input changed.
const WRITE_ASSEMBLY: &str = "as enip_stack::device::Device>::write_assembly";
/// The LAN9118 driver taking a whole frame into its transmit FIFO.
const PUSH_FRAME: &str = "enip_qemu_mps2::lan9118::push_frame";
/// One wake-up of the link task (its loop's body, never inlined).
const LINK_WAKE_UP: &str = "enip_firmware::link::pump::Pump<_>::poll";
/// The traced runs: connections and RPI. The log slows the emulation many-fold, so the
/// 10-connection run uses a 20 ms RPI (at a shorter one more datagrams share a wake-up).
pub(crate) const TRACED: [(u32, u32); 2] = [(1, 10_000), (10, 20_000)];
/// The scanner's watchdog multiplier code for the traced runs: 7 is x512, as the traced
/// board may stall for long.
const TRACED_MULTIPLIER: &str = "7";
/// Longest a traced run may take, in seconds.
const TRACED_SECONDS: u32 = 120;
/// The timing runs on the untraced board: 10 connections at each RPI (us).
const TIMING_RPIS_US: [u32; 2] = [1_000, 2_000];
const TIMING_CONNECTIONS: u32 = 10;
/// Their watchdog: code 3 is x32, as in the host board's TAP benchmark.
const TIMING_MULTIPLIER: &str = "3";
/// The TAP the board runs on (in a namespace of its own per run).
const TAP: &str = "enipmcub0";
/// The machine of the main measurements (the Cortex-M4).
pub(crate) const M4: &str = "mps2-an386";

/// Runs the traced and the timing runs at `scale`; returns their JSON for the bench report.
/// The traced runs per configuration (three in the benchmark) give their median: how many
/// datagrams one wake-up of the board finds depends on the phase between the scanner's and
/// the board's clocks, which differs from run to run.
pub fn run_all(scale: Scale) -> Result<serde_json::Value> {
    qemu::require_root("the QEMU benchmark")?;
    qemu::ensure_installed()?;
    let elf = match std::env::var_os(ELF_VAR) {
        Some(elf) => std::path::PathBuf::from(elf),
        None => boards::build(boards::QEMU, boards::DEFAULT_PROFILE)?,
    };
    run(util::cargo().args([
        "build",
        "--release",
        "-p",
        "host-tests",
        "--bin",
        "scanner",
        "--bin",
        "request_rate",
    ]))?;
    let dir = scale.dir().join("qemu");
    fs::create_dir_all(&dir)?;
    let symbols = Symbols::read(&elf)?;
    let mut traced = Vec::new();
    let mut latency = serde_json::Value::Null;
    let quick = std::env::var(QUICK_VAR).ok();
    if quick.as_deref() == Some("explicit") {
        let explicit = crate::bench_qemu_paths::explicit(&elf, &symbols, &dir, scale, true)?;
        return Ok(serde_json::json!({ "explicit": explicit }));
    }
    // `=10` (a number of connections): that traced run alone.
    let only = quick.as_deref().and_then(|q| q.parse::<u32>().ok());
    let quick = quick.is_some();
    for (connections, rpi_us) in TRACED {
        if only.is_some_and(|n| n != connections) {
            continue;
        }
        let load = Load::Class1 {
            connections,
            rpi_us,
            trigger: "cyclic",
        };
        let runs = traced_runs(M4, &elf, &symbols, &dir, load, scale, quick)?;
        let all: Vec<f64> = runs.iter().map(|c| c.per_cycle(c.total())).collect();
        let median = &runs[runs.len() / 2];
        print_cost(&load.title(), median);
        println!("  runs: {all:?}");
        let mut json = median.to_json(connections, rpi_us);
        json["runs"] = all.into();
        traced.push(json);
        if quick {
            return Ok(serde_json::json!({ "instructions_per_cycle": traced }));
        }
        if connections == 1 {
            latency = crate::bench_qemu_paths::latency(&elf, &symbols, &dir, scale, &runs)?;
        }
    }
    let explicit = crate::bench_qemu_paths::explicit(&elf, &symbols, &dir, scale, false)?;
    let mut timing = Vec::new();
    for rpi_us in TIMING_RPIS_US {
        let seconds = scale.qemu_timing_seconds();
        let report = timing_run(&elf, &dir, rpi_us, seconds)?;
        println!(
            "QEMU board, {TIMING_CONNECTIONS} x {rpi_us} us for {seconds} s: {}",
            peers::scanner_figures(&report)
        );
        timing.push(report);
    }
    let cores = crate::qemu_cores::bench(scale, &dir, &traced)?;
    Ok(serde_json::json!({
        "instructions_per_cycle": traced,
        "latency": latency,
        "explicit": explicit,
        "timing": timing,
        "cores": cores,
    }))
}

/// What a traced board is given to do.
#[derive(Debug, Clone, Copy)]
pub enum Load {
    /// The scanner's connections at an RPI (µs), their trigger (`cyclic`, `cos`, `app`).
    Class1 {
        connections: u32,
        rpi_us: u32,
        trigger: &'static str,
    },
    /// Get_Attribute_Single requests back to back on one session (`request_rate`).
    Requests,
}

impl Load {
    /// Names the run's files.
    fn tag(self) -> String {
        match self {
            Load::Class1 {
                connections,
                trigger: "cyclic",
                ..
            } => connections.to_string(),
            Load::Class1 {
                connections,
                trigger,
                ..
            } => format!("{trigger}-{connections}"),
            Load::Requests => "requests".into(),
        }
    }

    /// Heads its table.
    pub fn title(self) -> String {
        match self {
            Load::Class1 {
                connections,
                rpi_us,
                trigger,
            } => format!(
                "{connections} connection(s) at {rpi_us} us ({trigger}): instructions per Class 1 cycle"
            ),
            Load::Requests => "one session: instructions per Get_Attribute_Single (UCMM)".into(),
        }
    }

    /// The function called once per cycle: an O->T datagram consumed or a request fed.
    fn marker(self) -> &'static str {
        match self {
            Load::Class1 { .. } => MARKER,
            Load::Requests => REQUEST_MARKER,
        }
    }
}

/// The traced runs of `load` on QEMU's `machine` at `scale` (one if `once`), the cheapest
/// first. The trace stalls the emulation whenever its reader falls behind (a busy host): a
/// stall past the board's watchdog (2 s) resets it, so a failed run is tried once more.
pub fn traced_runs(
    machine: &str,
    elf: &Path,
    symbols: &Symbols,
    dir: &Path,
    load: Load,
    scale: Scale,
    once: bool,
) -> Result<Vec<Cost>> {
    let (runs, warmup, cycles) = scale.qemu_traced();
    let runs = if once { 1 } else { runs };
    let mut runs = (0..runs)
        .map(|_| {
            let counting = (warmup, cycles);
            traced_run(machine, elf, symbols, dir, load, counting).or_else(|e| {
                loud(&format!("{machine}: traced run failed ({e}); once more"));
                traced_run(machine, elf, symbols, dir, load, counting)
            })
        })
        .collect::<Result<Vec<Cost>>>()?;
    runs.sort_by(|a, b| a.per_cycle(a.total()).total_cmp(&b.per_cycle(b.total())));
    Ok(runs)
}

/// The traced runs of `elf` on QEMU's `machine` with `connections` at `rpi_us` (cyclic) at
/// `scale`; prints the median under the machine's name and returns its JSON with every
/// run's figure. Files go to `dir`.
pub(crate) fn traced_median(
    machine: &str,
    elf: &Path,
    dir: &Path,
    (connections, rpi_us): (u32, u32),
    scale: Scale,
) -> Result<serde_json::Value> {
    let symbols = Symbols::read(elf)?;
    let load = Load::Class1 {
        connections,
        rpi_us,
        trigger: "cyclic",
    };
    let runs = traced_runs(machine, elf, &symbols, dir, load, scale, false)?;
    let all: Vec<f64> = runs.iter().map(|c| c.per_cycle(c.total())).collect();
    let median = &runs[runs.len() / 2];
    print_cost(&format!("{machine}, {}", load.title()), median);
    println!("  runs: {all:?}");
    let mut json = median.to_json(connections, rpi_us);
    json["runs"] = all.into();
    Ok(json)
}

/// `cargo xtask bench --qemu`: this part alone, written to `target/bench/qemu.json`.
pub fn run_alone() -> Result {
    let report = run_all(Scale::Full)?;
    let path = Scale::Full.dir().join("qemu.json");
    fs::write(&path, report.to_string())?;
    println!("report: {}", path.display());
    Ok(())
}

/// Prints `cost` under `title`: the total, the parts, the costliest functions.
pub fn print_cost(title: &str, cost: &Cost) {
    println!(
        "\nQEMU board, {title}: {:.1} ({} counted)",
        cost.per_cycle(cost.total()),
        cost.cycles
    );
    println!(
        "  {:<34} {:>8.2}",
        "link task wake-ups",
        cost.wake_ups_per_cycle()
    );
    for (part, n) in cost.by_part() {
        println!("  {part:<34} {:>8.1}", cost.per_cycle(n));
    }
    println!("  top functions:");
    for (name, n) in cost.names.iter().take(12) {
        let short: String = name.chars().take(90).collect();
        println!("    {:>8.1}  {short}", cost.per_cycle(*n));
    }
}

/// Boots the board traced on QEMU's `machine`, gives it `load`, and counts the cycles
/// (calls of the load's marker) `counted.1` after the first `counted.0` (per connection for
/// Class 1).
fn traced_run(
    machine: &str,
    elf: &Path,
    symbols: &Symbols,
    dir: &Path,
    load: Load,
    counted: (u64, u64),
) -> Result<Cost> {
    let name = load.marker();
    let marker = symbols
        .start_of(name)
        .ok_or_else(|| util::Error(format!("{name} is not in {}", elf.display())))?;
    let marks = Marks {
        marker,
        write_assembly: symbols.starts_ending(WRITE_ASSEMBLY),
        push_frame: symbols.start_of(PUSH_FRAME),
    };
    let fifo = dir.join("trace.fifo");
    let _ = fs::remove_file(&fifo);
    run(Command::new("mkfifo").arg(&fifo))?;
    // Created by the trace reader once it has counted its cycles: the load ends there.
    let stop = dir.join("trace.stop");
    let _ = fs::remove_file(&stop);
    let per = match load {
        Load::Class1 { connections, .. } => u64::from(connections),
        Load::Requests => 1,
    };
    let wanted = (counted.0 * per, counted.1 * per);
    let tag = load.tag();
    let result = thread::scope(|s| {
        let counter = s.spawn(|| count(&fifo, symbols, &marks, wanted, &stop));
        let fifo_arg = fifo.to_string_lossy();
        let log = dir.join(format!("board-traced-{tag}.log"));
        let trace = ["-d", "in_asm,exec,nochain", "-D", &fifo_arg];
        let board = Board::QemuMachine {
            machine,
            elf,
            extra: &trace,
        };
        let board = Rig::launch(board, &options(&log));
        if board.is_err() {
            // Unblock the reader if QEMU never opened the log.
            let _ = fs::OpenOptions::new().write(true).open(&fifo);
        }
        let loaded = board.map_err(util::Error::from).and_then(|mut rig| {
            let r = match load {
                Load::Class1 {
                    connections,
                    rpi_us,
                    trigger,
                } => {
                    let json = dir.join(format!("scanner-traced-{tag}.json"));
                    let seconds = scanner_seconds(connections, rpi_us, wanted.0 + wanted.1);
                    let class1 = (connections, rpi_us, trigger);
                    let stopping = Some(stop.as_path());
                    scan(
                        rig.ns(),
                        class1,
                        seconds,
                        TRACED_MULTIPLIER,
                        &json,
                        stopping,
                    )
                    .map(|_| ())
                }
                Load::Requests => requests(rig.ns(), dir, &stop),
            };
            rig.check_alive()?;
            r
        });
        // The board is stopped (dropped) by now, which ends the log.
        let counted = counter
            .join()
            .unwrap_or_else(|_| err("the trace reader panicked"));
        loaded.and(counted)
    });
    let _ = fs::remove_file(&fifo);
    let _ = fs::remove_file(&stop);
    let mut cost = result?;
    cost.wake_ups = cost.calls_into(&symbols.starts_ending(LINK_WAKE_UP));
    fs::write(dir.join(format!("blocks-{tag}.txt")), cost.blocks(symbols))?;
    if cost.cycles < wanted.1 {
        return err(format!(
            "the traced board served only {} of {} {} in time",
            cost.cycles, wanted.1, name
        ));
    }
    Ok(cost)
}

/// Seconds of `request_rate` against the traced board at most: enough for the counted
/// requests at the slowest rate seen under tracing (tens per second).
const REQUEST_SECONDS: &str = "20";

/// `request_rate` with one session in `ns` for [`REQUEST_SECONDS`], or until the file `stop`
/// exists.
fn requests(ns: &Namespace, dir: &Path, stop: &Path) -> Result {
    let bin = util::target_dir().join("release/request_rate");
    let mut cmd = ns.command(&bin);
    cmd.args(["--target", &enip_lab::netns::BOARD_IP.to_string()])
        .args(["--sessions", "1", "--seconds", REQUEST_SECONDS])
        .arg("--stop-file")
        .arg(stop);
    let out = cmd.output()?;
    fs::write(dir.join("request_rate.json"), &out.stdout)?;
    if !out.status.success() {
        return err(format!(
            "request_rate failed ({}): {}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    Ok(())
}

/// Seconds of scanner run that bring `datagrams` O->T datagrams under tracing, which slows
/// the board many-fold: three times their time at the RPI, and twenty seconds more (at most:
/// the run ends once the trace reader has counted them).
fn scanner_seconds(connections: u32, rpi_us: u32, datagrams: u64) -> u32 {
    let nominal = datagrams * u64::from(rpi_us) / u64::from(connections) / 1_000_000;
    (3 * nominal as u32 + 20).min(TRACED_SECONDS)
}

/// The untraced board with [`TIMING_CONNECTIONS`] at `rpi_us`; returns the scanner's report.
fn timing_run(elf: &Path, dir: &Path, rpi_us: u32, seconds: u32) -> Result<serde_json::Value> {
    let log = dir.join(format!("board-{rpi_us}us.log"));
    let mut rig = Rig::launch(Board::Qemu { elf, extra: &[] }, &options(&log))?;
    let json = dir.join(format!("scanner-{rpi_us}us.json"));
    let class1 = (TIMING_CONNECTIONS, rpi_us, "cyclic");
    let report = scan(rig.ns(), class1, seconds, TIMING_MULTIPLIER, &json, None)?;
    rig.check_alive()?;
    Ok(report)
}

/// Where the board runs, its output copied to `log`.
fn options(log: &Path) -> Options<'_> {
    Options::logged(TAP, log)
}

/// The project's scanner (release build) in `ns`: `connections` at `rpi_us` with their
/// `trigger`, for `seconds` (or until the file `stop` exists) with watchdog `multiplier`;
/// prints its table and returns its report, written to `json`.
fn scan(
    ns: &Namespace,
    (connections, rpi_us, trigger): (u32, u32, &str),
    seconds: u32,
    multiplier: &str,
    json: &Path,
    stop: Option<&Path>,
) -> Result<serde_json::Value> {
    let bin = util::target_dir().join("release/scanner");
    let run = ScannerRun {
        bin: &bin,
        connections,
        rpi_us,
        seconds,
        multiplier,
        json,
    };
    let stop = stop.map(|p| p.to_string_lossy().into_owned());
    let mut extra = vec!["--trigger", trigger];
    if let Some(stop) = &stop {
        extra.extend(["--stop-file", stop.as_str()]);
    }
    let (table, report) = scanner_run::run_with(ns, &run, &extra)?;
    print!("{table}");
    Ok(report)
}
