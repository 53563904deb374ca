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

use std::collections::{BTreeMap, HashMap};
use std::fs;
use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::Command;
use std::thread;

use enip_lab::netns::Namespace;
use enip_lab::peers;
use enip_lab::rig::{Board, Options, Rig};
use enip_lab::scanner::{self as scanner_run, ScannerRun};

use crate::bench_scale::Scale;
use crate::boards;
use crate::qemu;
use crate::util::{self, err, loud, output, run, Result};

/// Names an `enip-qemu-mps2` ELF to measure instead of building one (e.g. an older
/// commit's, for a before/after comparison).
const ELF_VAR: &str = "ENIP_QEMU_BENCH_ELF";
/// The function called once per O->T datagram: the cycle counter.
pub const MARKER: &str = "enip_firmware::link::pump::consume";
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
/// The TAP the board runs on.
const TAP: &str = "enipmcub0";

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
    run(util::cargo().args(["build", "--release", "-p", "host-tests", "--bin", "scanner"]))?;
    let dir = scale.dir().join("qemu");
    let (runs, warmup, cycles) = scale.qemu_traced();
    fs::create_dir_all(&dir)?;
    let mut traced = Vec::new();
    for config in TRACED {
        traced.push(traced_median(
            M4,
            &elf,
            &dir,
            config,
            (runs, warmup, cycles),
        )?);
    }
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
    Ok(serde_json::json!({ "instructions_per_cycle": traced, "timing": timing, "cores": cores }))
}

/// The machine of the main measurements (the Cortex-M4).
const M4: &str = "mps2-an386";

/// The traced runs of `elf` on QEMU's `machine` with `connections` at `rpi_us`:
/// `counting.0` runs, each counting `counting.2` O->T datagrams per connection after
/// `counting.1`; prints the median and returns its JSON with every run's figure. Files go
/// to `dir`.
pub(crate) fn traced_median(
    machine: &str,
    elf: &Path,
    dir: &Path,
    (connections, rpi_us): (u32, u32),
    (runs, warmup, cycles): (usize, u64, u64),
) -> Result<serde_json::Value> {
    let symbols = Symbols::read(elf)?;
    let mut runs = (0..runs)
        .map(|_| {
            let config = (connections, rpi_us);
            let counting = (warmup, cycles);
            // The trace stalls the emulation whenever its reader falls behind (a busy
            // host): a stall past the board's watchdog (2 s) resets it. One retry.
            traced_run(machine, elf, &symbols, dir, config, counting).or_else(|e| {
                loud(&format!("{machine}: traced run failed ({e}); once more"));
                traced_run(machine, elf, &symbols, dir, config, counting)
            })
        })
        .collect::<Result<Vec<Cost>>>()?;
    runs.sort_by(|a, b| a.per_cycle(a.total()).total_cmp(&b.per_cycle(b.total())));
    let all: Vec<f64> = runs.iter().map(|c| c.per_cycle(c.total())).collect();
    let median = &runs[runs.len() / 2];
    println!("\n{machine}:");
    print_cost(connections, rpi_us, median);
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

/// The firmware's functions: start address, end address, demangled name; sorted.
struct Symbols(Vec<(u32, u32, String)>);

impl Symbols {
    fn read(elf: &Path) -> Result<Symbols> {
        let elf = elf.to_string_lossy();
        let text = output(Command::new("arm-none-eabi-nm").args(["-C", "-S", "-n", &elf]))
            .ok_or_else(|| util::Error(format!("arm-none-eabi-nm {elf} failed")))?;
        let mut all = Vec::new();
        for line in text.lines() {
            let mut cols = line.splitn(4, ' ');
            let (Some(addr), Some(size), Some("t" | "T" | "W"), Some(name)) =
                (cols.next(), cols.next(), cols.next(), cols.next())
            else {
                continue;
            };
            let (Ok(addr), Ok(size)) =
                (u32::from_str_radix(addr, 16), u32::from_str_radix(size, 16))
            else {
                continue;
            };
            // Thumb functions have bit 0 set in their symbol value.
            let start = addr & !1;
            all.push((start, start + size, name.to_string()));
        }
        all.sort();
        Ok(Symbols(all))
    }

    /// Index of the function holding `pc`, if any.
    fn find(&self, pc: u32) -> Option<usize> {
        let i = self.0.partition_point(|(start, _, _)| *start <= pc);
        let i = i.checked_sub(1)?;
        (pc < self.0[i].1).then_some(i)
    }

    fn name(&self, i: Option<usize>) -> &str {
        i.map_or("?", |i| self.0[i].2.as_str())
    }

    /// True if a function starts at `pc`.
    fn starts(&self, pc: u32) -> bool {
        self.find(pc).is_some_and(|i| self.0[i].0 == pc)
    }

    /// Start address of the function called `name`.
    fn start_of(&self, name: &str) -> Option<u32> {
        self.0.iter().find(|s| s.2 == name).map(|s| s.0)
    }
}

/// What a traced run counted over its cycles.
#[derive(Default)]
struct Cost {
    cycles: u64,
    /// Instructions by function index (`None`: outside every symbol).
    by_function: HashMap<Option<usize>, u64>,
    /// Instructions by translation block (its first address): the finer attribution
    /// written to `blocks-N.txt` beside the logs.
    by_block: HashMap<u32, u64>,
    /// Entries of a function (its start) from a block (the one run before): the callers.
    calls: HashMap<(u32, u32), u64>,
    /// Function names, resolved.
    names: Vec<(String, u64)>,
}

impl Cost {
    fn total(&self) -> u64 {
        self.names.iter().map(|(_, n)| n).sum()
    }

    fn per_cycle(&self, n: u64) -> f64 {
        (n as f64 / self.cycles.max(1) as f64 * 10.0).round() / 10.0
    }

    /// One line per translation block, the costliest first: its address, instructions per
    /// cycle and function (for `addr2line` on the image).
    fn blocks(&self, symbols: &Symbols) -> String {
        let mut blocks: Vec<_> = self.by_block.iter().collect();
        blocks.sort_by(|a, b| b.1.cmp(a.1).then(a.0.cmp(b.0)));
        blocks
            .into_iter()
            .map(|(pc, n)| {
                let name = symbols.name(symbols.find(*pc));
                format!("{pc:08x} {:>8.1} {name}\n", self.per_cycle(*n))
            })
            .chain(self.calls.iter().map(|((from, to), n)| {
                let (caller, callee) = (symbols.find(*from), symbols.find(*to));
                format!(
                    "call {from:08x} {:>6.2} {} -> {}\n",
                    self.per_cycle(*n),
                    symbols.name(caller),
                    symbols.name(callee)
                )
            }))
            .collect()
    }

    /// Instructions by part of the firmware.
    fn by_part(&self) -> BTreeMap<&'static str, u64> {
        let mut parts = BTreeMap::new();
        for (name, n) in &self.names {
            *parts.entry(part(name)).or_default() += n;
        }
        parts
    }

    fn to_json(&self, connections: u32, rpi_us: u32) -> serde_json::Value {
        let parts: serde_json::Map<_, _> = self
            .by_part()
            .into_iter()
            .map(|(k, v)| (k.to_string(), self.per_cycle(v).into()))
            .collect();
        let top: Vec<_> = self
            .names
            .iter()
            .take(15)
            .map(|(name, n)| serde_json::json!([name, self.per_cycle(*n)]))
            .collect();
        serde_json::json!({
            "connections": connections,
            "rpi_us": rpi_us,
            "cycles": self.cycles,
            "per_cycle": self.per_cycle(self.total()),
            "by_part": parts,
            "top_functions": top,
        })
    }
}

/// The part of the firmware a function belongs to, by the crate in its demangled name.
fn part(name: &str) -> &'static str {
    if name.contains("TaskStorage<F>::poll") || name.contains("embassy_futures::") {
        return "tasks (inlined futures)";
    }
    let path = name.trim_start_matches(['<', '&', '_']);
    match path.split("::").next().unwrap_or("") {
        "enip_stack" => "enip-stack",
        "enip_firmware" => "firmware runtime",
        "enip_profiles" => "device profile",
        "smoltcp" => "smoltcp",
        "embassy_net" => "embassy-net",
        "enip_qemu_mps2" => "board: LAN9118, timers",
        k if k.starts_with("embassy_") || k == "critical_section" || k == "cortex_m" => {
            "executor, time queue"
        }
        "core" | "compiler_builtins" => "builtins (memcpy, division)",
        k if k.starts_with("mem") || k.starts_with("aeabi") => "builtins (memcpy, division)",
        _ => "other",
    }
}

fn print_cost(connections: u32, rpi_us: u32, cost: &Cost) {
    println!(
        "\nQEMU board, {connections} connection(s) at {rpi_us} us: {:.1} instructions per Class 1 cycle ({} cycles)",
        cost.per_cycle(cost.total()),
        cost.cycles
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

/// Boots the board traced on `machine`, runs the scanner with `connections` at `rpi_us`,
/// and counts the O->T datagrams per connection `counted.1` after the first `counted.0`.
fn traced_run(
    machine: &str,
    elf: &Path,
    symbols: &Symbols,
    dir: &Path,
    (connections, rpi_us): (u32, u32),
    counted: (u64, u64),
) -> Result<Cost> {
    let marker = symbols
        .start_of(MARKER)
        .ok_or_else(|| util::Error(format!("{MARKER} is not in {}", elf.display())))?;
    let fifo = dir.join("trace.fifo");
    let _ = fs::remove_file(&fifo);
    run(Command::new("mkfifo").arg(&fifo))?;
    let wanted = (
        counted.0 * u64::from(connections),
        counted.1 * u64::from(connections),
    );
    let result = thread::scope(|s| {
        let counter = s.spawn(|| count(&fifo, symbols, marker, wanted));
        let fifo_arg = fifo.to_string_lossy();
        let log = dir.join(format!("board-traced-{connections}.log"));
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
        let scanned = board.map_err(util::Error::from).and_then(|mut rig| {
            let json = dir.join(format!("scanner-traced-{connections}.json"));
            let seconds = scanner_seconds(connections, rpi_us, wanted.0 + wanted.1);
            let r = scan(
                rig.ns(),
                connections,
                rpi_us,
                seconds,
                TRACED_MULTIPLIER,
                &json,
            );
            rig.check_alive()?;
            r
        });
        // The board is stopped (dropped) by now, which ends the log.
        let counted = counter
            .join()
            .unwrap_or_else(|_| err("the trace reader panicked"));
        scanned.and(counted)
    });
    let _ = fs::remove_file(&fifo);
    let cost = result?;
    fs::write(
        dir.join(format!("blocks-{connections}.txt")),
        cost.blocks(symbols),
    )?;
    if cost.cycles < wanted.1 {
        return err(format!(
            "the traced board handled only {} of {} O->T datagrams in time",
            cost.cycles, wanted.1
        ));
    }
    Ok(cost)
}

/// Seconds of scanner run that bring `datagrams` O->T datagrams under tracing, which slows
/// the board many-fold: three times their time at the RPI, and twenty seconds more.
fn scanner_seconds(connections: u32, rpi_us: u32, datagrams: u64) -> u32 {
    let nominal = datagrams * u64::from(rpi_us) / u64::from(connections) / 1_000_000;
    (3 * nominal as u32 + 20).min(TRACED_SECONDS)
}

/// The untraced board with [`TIMING_CONNECTIONS`] at `rpi_us`; returns the scanner's report.
fn timing_run(elf: &Path, dir: &Path, rpi_us: u32, seconds: u32) -> Result<serde_json::Value> {
    let log = dir.join(format!("board-{rpi_us}us.log"));
    let mut rig = Rig::launch(Board::Qemu { elf, extra: &[] }, &options(&log))?;
    let json = dir.join(format!("scanner-{rpi_us}us.json"));
    let report = scan(
        rig.ns(),
        TIMING_CONNECTIONS,
        rpi_us,
        seconds,
        TIMING_MULTIPLIER,
        &json,
    )?;
    rig.check_alive()?;
    Ok(report)
}

/// Where the board runs, its output copied to `log`: a namespace with a name of its own, so
/// that two benchmarks on one machine (two checkouts) do not replace each other's.
fn options(log: &Path) -> Options<'_> {
    Options {
        namespace: None,
        tap: Some(TAP),
        capture: None,
        log_file: Some(log),
    }
}

/// The project's scanner (release build) in `ns`: `connections` at `rpi_us` for `seconds`
/// with watchdog `multiplier`; prints its table and returns its report, written to `json`.
fn scan(
    ns: &Namespace,
    connections: u32,
    rpi_us: u32,
    seconds: u32,
    multiplier: &str,
    json: &Path,
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
    let (table, report) = scanner_run::run(ns, &run)?;
    print!("{table}");
    Ok(report)
}

/// A translation block: its function and instruction count, and whether it holds the WFE.
#[derive(Clone, Copy)]
struct Block {
    function: Option<usize>,
    instructions: u32,
    wfe: bool,
}

/// Reads QEMU's log from `fifo` until QEMU stops; counts the instructions of the `wanted.1`
/// calls of `marker` after the first `wanted.0` (idle loop excluded).
fn count(fifo: &Path, symbols: &Symbols, marker: u32, wanted: (u64, u64)) -> Result<Cost> {
    let file = fs::File::open(fifo)?;
    let mut reader = BufReader::with_capacity(1 << 20, file);
    let mut blocks: HashMap<u32, Block> = HashMap::new();
    let mut line = Vec::with_capacity(256);
    let mut translating: Option<(u32, u32, bool)> = None;
    // Blocks run since the last WFE, and whether any ran outside the idle loop's function.
    let mut segment: Vec<u32> = Vec::new();
    let mut busy = false;
    let mut idle_function: Option<Option<usize>> = None;
    let mut markers = 0u64;
    let mut cost = Cost::default();
    loop {
        line.clear();
        if reader.read_until(b'\n', &mut line)? == 0 {
            break;
        }
        if let Some(rest) = line.strip_prefix(b"Trace ") {
            let Some(pc) = trace_pc(rest) else { continue };
            let Some(block) = blocks.get(&pc).copied() else {
                continue;
            };
            if pc == marker {
                markers += 1;
            }
            if block.wfe {
                idle_function.get_or_insert(block.function);
                let counting = markers > wanted.0 && markers <= wanted.0 + wanted.1;
                if busy && counting {
                    let mut previous = None;
                    for pc in segment.drain(..).chain([pc]) {
                        if let Some(b) = blocks.get(&pc) {
                            *cost.by_function.entry(b.function).or_default() +=
                                u64::from(b.instructions);
                            *cost.by_block.entry(pc).or_default() += u64::from(b.instructions);
                            if let Some(from) = previous.filter(|_| symbols.starts(pc)) {
                                *cost.calls.entry((from, pc)).or_default() += 1;
                            }
                        }
                        previous = Some(pc);
                    }
                }
                segment.clear();
                busy = false;
                continue;
            }
            busy |= Some(block.function) != idle_function;
            segment.push(pc);
        } else if line.starts_with(b"IN:") {
            translating = Some((0, 0, false));
        } else if let Some((start, n, wfe)) = translating.as_mut() {
            if let Some(pc) = asm_pc(&line) {
                if *n == 0 {
                    *start = pc;
                }
                *n += 1;
                *wfe |= line.windows(5).any(|w| w == b" wfe ");
            } else if line.iter().all(u8::is_ascii_whitespace) && *n > 0 {
                let (start, n, wfe) = (*start, *n, *wfe);
                blocks.insert(
                    start,
                    Block {
                        function: symbols.find(start),
                        instructions: n,
                        wfe,
                    },
                );
                translating = None;
            }
        }
    }
    cost.cycles = markers.saturating_sub(wanted.0).min(wanted.1);
    let mut names: Vec<(String, u64)> = cost
        .by_function
        .iter()
        .map(|(f, n)| (symbols.name(*f).to_string(), *n))
        .collect();
    names.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    cost.names = names;
    Ok(cost)
}

/// The guest address of an `exec` log line (after `Trace `):
/// `0: 0x7f... [00800408/0000ad3e/00000010/ff000200] symbol`.
fn trace_pc(rest: &[u8]) -> Option<u32> {
    let open = rest.iter().position(|&b| b == b'[')?;
    let fields = rest.get(open + 1..)?;
    let slash = fields.iter().position(|&b| b == b'/')?;
    let pc = fields.get(slash + 1..slash + 9)?;
    u32::from_str_radix(std::str::from_utf8(pc).ok()?, 16).ok()
}

/// The address of an `in_asm` instruction line: `0x0000ad64:  bf20       wfe`.
fn asm_pc(line: &[u8]) -> Option<u32> {
    let hex = line.strip_prefix(b"0x")?;
    let colon = hex.iter().position(|&b| b == b':')?;
    u32::from_str_radix(std::str::from_utf8(hex.get(..colon)?).ok()?, 16).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_lines_give_guest_addresses() {
        assert_eq!(
            trace_pc(b"0: 0x7f1150074f80 [00800408/0000ad3e/00000010/ff000200] run\n"),
            Some(0xad3e)
        );
        assert_eq!(trace_pc(b"0: garbage\n"), None);
        assert_eq!(asm_pc(b"0x0000ad64:  bf20       wfe      \n"), Some(0xad64));
        assert_eq!(asm_pc(b"IN: Reset\n"), None);
    }

    #[test]
    fn functions_fall_into_parts() {
        assert_eq!(
            part("smoltcp::iface::interface::Interface::poll"),
            "smoltcp"
        );
        assert_eq!(
            part("<embassy_net::tcp::TcpSocket as core::ops::Drop>::drop"),
            "embassy-net"
        );
        assert_eq!(
            part("enip_qemu_mps2::lan9118::on_interrupt"),
            "board: LAN9118, timers"
        );
        assert_eq!(part("memcpy"), "builtins (memcpy, division)");
        assert_eq!(part("__aeabi_uldivmod"), "builtins (memcpy, division)");
        assert_eq!(
            part("embassy_executor::raw::SyncExecutor::poll"),
            "executor, time queue"
        );
        assert_eq!(part("enip_stack::io::ConnectionTable::close"), "enip-stack");
    }
}
