//! `cargo xtask bench --host`: the whole host adapter process per Class 1 cycle, on the TAP
//! (`enip-host --tap`, its own TCP/IP stack) and on kernel sockets (`enip-host --bind`, over
//! a veth pair), and OpENer's POSIX build beside them when `ENIP_OPENER_BIN` names one.
//!
//! For each board, in namespaces of its own (198.18.0.1 the peers, 198.18.0.2 the board):
//! - instructions per cycle: the board under `valgrind --tool=callgrind` (user space, every
//!   thread), its counters zeroed once it answers (`callgrind_control -z`: how many probes
//!   its start took under valgrind varies), the project's scanner holding one exclusive
//!   owner at 10 ms for 5 s and then 15 s ([`Scale::host_seconds`]); per cycle = difference
//!   of the two totals / difference of the T->O datagrams received, so the scanner's
//!   connection set-up and the board's shut-down cancel out;
//! - context switches per cycle: the same two runs natively, summing `voluntary_ctxt_switches`
//!   and `nonvoluntary_ctxt_switches` of every thread from `/proc/PID/task/*/status`;
//! - explicit messaging: back-to-back Get_Attribute_Single on 1 and on 3 sessions for
//!   3 s (`request_rate`), requests per second, the boards taking turns for
//!   [`Scale::rate_rounds`] rounds and each board's median reported, with the board's CPU
//!   time (user and system, `/proc/PID/stat`) per request on 3 sessions; then the same CPU
//!   time with every board at one common rate ([`common_rate`]: half the slowest board's
//!   median, so each keeps up), the same number of rounds; and the instructions per request
//!   on 3 sessions, under callgrind, from a 3 s and a 9 s run the same way.
//!
//! Needs root (namespaces), valgrind, and the release builds of `enip-host`, `scanner` and
//! `request_rate`, which [`run_all`] makes.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Child, Stdio};
use std::thread::sleep;
use std::time::{Duration, Instant};

use enip_lab::netns::{Lab, BOARD_VETH};
use enip_lab::process::{signal, SIGINT};
use enip_lab::scanner::{self as scanner_run, ScannerRun};
use enip_lab::usage::{context_switches, ticks_per_second, usage};
use serde_json::{json, Value};

use crate::bench_scale::Scale;
use crate::util::{self, cargo, err, run, Error, Result};

/// The connection measured: one exclusive owner at this RPI.
const RPI_US: u32 = 10_000;
/// Its watchdog multiplier code: 2 (x16), the scanner's default.
const SCANNER_MULTIPLIER: &str = "2";
/// The link device on the peers' side.
const LINK: &str = "enipbench0";
/// The board's address.
const BOARD_IP: &str = "198.18.0.2";
/// Bound for a board to start answering (valgrind makes start-up slow).
const START: Duration = Duration::from_secs(60);

/// The adapters measured.
#[derive(Clone)]
enum Board {
    /// `enip-host --tap`: the adapter's own TCP/IP stack on a TAP in the peers' namespace.
    Tap(PathBuf),
    /// `enip-host --bind`: kernel sockets, in its own namespace over a veth pair.
    Bind(PathBuf),
    /// OpENer's POSIX sample application, the same way.
    Opener(PathBuf),
}

impl Board {
    fn name(&self) -> &'static str {
        match self {
            Board::Tap(_) => "enip-host --tap",
            Board::Bind(_) => "enip-host --bind",
            Board::Opener(_) => "OpENer",
        }
    }

    /// The lab the board runs in: a TAP in the peers' namespace, or a veth pair to a
    /// namespace of the board's own.
    fn lab(&self) -> Result<Lab> {
        Ok(match self {
            Board::Tap(_) => Lab::create_unique(LINK)?,
            Board::Bind(_) | Board::Opener(_) => Lab::create_veth(LINK)?,
        })
    }

    /// The board's program and arguments in `lab`.
    fn argv(&self, lab: &Lab) -> Vec<String> {
        let s = |p: &Path| p.display().to_string();
        match self {
            Board::Tap(bin) => vec![
                s(bin),
                "--tap".into(),
                lab.tap.clone(),
                "--ip".into(),
                format!("{BOARD_IP}/24"),
                // The start-up's conflict probing is not what this measures.
                "--acd".into(),
                "off".into(),
            ],
            Board::Bind(bin) => vec![s(bin), "--bind".into(), BOARD_IP.into()],
            Board::Opener(bin) => vec![s(bin), BOARD_VETH.into()],
        }
    }
}

/// One run of a board with Class 1 traffic.
struct Sample {
    /// T->O datagrams the scanner received.
    cycles: u64,
    /// Instructions of the whole process (callgrind runs only).
    instructions: Option<u64>,
    /// Context switches of every thread of the process while the scanner ran.
    switches: u64,
}

/// The release binaries the benchmark runs, where its files go and how long it measures.
struct Bins {
    scanner: PathBuf,
    request_rate: PathBuf,
    dir: PathBuf,
    /// Seconds of the short and long Class 1 runs and of each request-rate run.
    seconds: (u64, u64, u64),
    /// Rounds of request-rate runs, the boards taking turns.
    rate_rounds: usize,
}

/// Builds what the benchmark runs, measures every board and prints the table; writes
/// `target/bench/host.json`.
pub fn run_all() -> Result {
    let report = measure(Scale::Full)?;
    let path = Scale::Full.dir().join("host.json");
    fs::write(&path, report.to_string()).map_err(|e| Error(format!("{}: {e}", path.display())))?;
    println!("report: {}", path.display());
    Ok(())
}

/// Measures every board at `scale`; returns the JSON report (also printed as a table).
pub fn measure(scale: Scale) -> Result<Value> {
    if !util::is_root() {
        return err("the host runtime benchmark needs root (network namespaces)");
    }
    // Two builds, as the main benchmark's: together, cargo would unify the stack's features
    // of both and build everything once more (40 s in CI) for the same binaries.
    let host = scale.enip_host()?;
    run(cargo().args(["build", "--release", "-p", "host-tests", "--bins"]))?;
    let dir = util::target_dir().join("release");
    let bins = Bins {
        scanner: dir.join("scanner"),
        request_rate: dir.join("request_rate"),
        dir: scale.dir(),
        seconds: scale.host_seconds(),
        rate_rounds: scale.rate_rounds(),
    };
    let mut boards = vec![Board::Tap(host.clone()), Board::Bind(host)];
    match std::env::var_os("ENIP_OPENER_BIN") {
        Some(p) => boards.push(Board::Opener(PathBuf::from(p))),
        None => println!("OpENer: not measured (set ENIP_OPENER_BIN to its POSIX build)"),
    }
    let _ = fs::create_dir_all(&bins.dir);
    let mut report = serde_json::Map::new();
    println!(
        "{:<18} {:>14} {:>14} {:>12} {:>12} {:>12} {:>12} {:>16}",
        "board",
        "instr/cycle",
        "ctx sw/cycle",
        "1 sess rq/s",
        "3 sess rq/s",
        "instr/rq",
        "CPU us/rq",
        "CPU us/rq common"
    );
    let mut measured = Vec::new();
    for board in &boards {
        measured.push(measure_board(board, &bins)?);
    }
    // The request rates are wall-clock figures on a shared machine: the boards take turns,
    // round after round (every other round in reverse order, so none always goes first),
    // and each board's median is reported.
    let rounds = in_turns(boards.len(), bins.rate_rounds, |i| rates(&boards[i], &bins))?;
    let threes: Vec<f64> = rounds
        .iter()
        .map(|runs| median(runs, |r| r.three.per_second))
        .collect();
    let common = common_rate(&threes);
    let paced = in_turns(boards.len(), bins.rate_rounds, |i| {
        paced(&boards[i], &bins, common)
    })?;
    for (((board, mut r), runs), at_common) in boards.iter().zip(measured).zip(rounds).zip(paced) {
        r["requests_per_second_1_session"] = median(&runs, |r| r.one).into();
        r["requests_per_second_3_sessions"] = median(&runs, |r| r.three.per_second).into();
        r["cpu_us_per_request_3_sessions"] = median(&runs, |r| r.three.cpu_us_per_request).into();
        r["request_rate_rounds"] = json!(runs
            .iter()
            .map(|r| json!([r.one, r.three.per_second, r.three.cpu_us_per_request]))
            .collect::<Vec<_>>());
        r["common_rate_requests_per_second"] = common.into();
        r["requests_per_second_at_common_rate"] = median(&at_common, |r| r.per_second).into();
        r["cpu_us_per_request_at_common_rate"] =
            median(&at_common, |r| r.cpu_us_per_request).into();
        r["common_rate_rounds"] = json!(at_common
            .iter()
            .map(|r| json!([r.per_second, r.cpu_us_per_request]))
            .collect::<Vec<_>>());
        let cell = |k: &str, digits: usize| {
            r[k].as_f64()
                .map_or("?".into(), |v| format!("{v:.digits$}"))
        };
        println!(
            "{:<18} {:>14} {:>14} {:>12} {:>12} {:>12} {:>12} {:>16}",
            board.name(),
            cell("instructions_per_cycle", 1),
            cell("context_switches_per_cycle", 1),
            cell("requests_per_second_1_session", 1),
            cell("requests_per_second_3_sessions", 1),
            cell("instructions_per_request_3_sessions", 1),
            cell("cpu_us_per_request_3_sessions", 2),
            cell("cpu_us_per_request_at_common_rate", 2),
        );
        report.insert(board.name().into(), r);
    }
    println!("common rate: {common} requests/s on 3 sessions");
    Ok(Value::Object(report))
}

/// Runs `measure(board)` for `boards` boards in turns, `rounds` times (every other round in
/// reverse order, so none always goes first); each board's results in round order.
fn in_turns<T>(
    boards: usize,
    rounds: usize,
    mut measure: impl FnMut(usize) -> Result<T>,
) -> Result<Vec<Vec<T>>> {
    let mut out: Vec<Vec<T>> = (0..boards).map(|_| Vec::new()).collect();
    for round in 0..rounds {
        for j in 0..boards {
            let i = if round % 2 == 1 { boards - 1 - j } else { j };
            out[i].push(measure(i)?);
        }
    }
    Ok(out)
}

/// The median of `pick` over `runs` (0 for none).
fn median<T>(runs: &[T], pick: fn(&T) -> f64) -> f64 {
    let mut v: Vec<f64> = runs.iter().map(pick).collect();
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(0.0)
}

/// The rate every board is measured at for the CPU time at one request rate: half the
/// slowest board's median on 3 sessions (so every board keeps up with it), in whole
/// thousands, at least 1 000.
fn common_rate(three_session_medians: &[f64]) -> u32 {
    let slowest = three_session_medians
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    let half = if slowest.is_finite() {
        slowest / 2.0
    } else {
        0.0
    };
    ((half / 1000.0).floor() as u32).max(1) * 1000
}

/// Every figure of one board.
fn measure_board(board: &Board, bins: &Bins) -> Result<Value> {
    let (short_seconds, long_seconds, _) = bins.seconds;
    let short = sample(board, bins, short_seconds, true)?;
    let long = sample(board, bins, long_seconds, true)?;
    let native_short = sample(board, bins, short_seconds, false)?;
    let native_long = sample(board, bins, long_seconds, false)?;
    let per = |a: u64, b: u64, ca: u64, cb: u64| {
        (b.saturating_sub(a)) as f64 / (cb.saturating_sub(ca)).max(1) as f64
    };
    let instructions = match (short.instructions, long.instructions) {
        (Some(a), Some(b)) => per(a, b, short.cycles, long.cycles),
        _ => return err(format!("{}: no instruction count", board.name())),
    };
    let switches = per(
        native_short.switches,
        native_long.switches,
        native_short.cycles,
        native_long.cycles,
    );
    let per_request = request_cost(board, bins)?;
    Ok(json!({
        "instructions_per_cycle": (instructions * 10.0).round() / 10.0,
        "callgrind_runs": [[short.cycles, short.instructions], [long.cycles, long.instructions]],
        "context_switches_per_cycle": (switches * 100.0).round() / 100.0,
        "native_runs": [[native_short.cycles, native_short.switches],
                        [native_long.cycles, native_long.switches]],
        "instructions_per_request_3_sessions": (per_request * 10.0).round() / 10.0,
    }))
}

/// Starts `board`, holds one exclusive owner at 10 ms on it for `seconds`, stops it.
fn sample(board: &Board, bins: &Bins, seconds: u64, callgrind: bool) -> Result<Sample> {
    let lab = board.lab()?;
    let out = bins.dir.join(format!(
        "host-{}-{seconds}.callgrind",
        board.name().replace([' ', '-'], "_")
    ));
    let _ = fs::remove_file(&out);
    let mut child = start(board, &lab, bins, callgrind.then_some(out.as_path()))?;
    let pid = child.id();
    let before = context_switches(pid);
    let json = bins.dir.join("host-scanner.json");
    let run = ScannerRun {
        bin: &bins.scanner,
        connections: 1,
        rpi_us: RPI_US,
        seconds: seconds as u32,
        multiplier: SCANNER_MULTIPLIER,
        json: &json,
    };
    let scanned = scanner_run::run(lab.ns(), &run);
    let after = context_switches(pid);
    stop(&mut child);
    let (_, doc) = scanned.map_err(|e| Error(format!("{}: scanner failed: {e}", board.name())))?;
    let cycles = doc["connections"][0]["received"].as_u64().unwrap_or(0);
    let instructions = if callgrind {
        Some(crate::bench::callgrind_total(&out)?)
    } else {
        None
    };
    Ok(Sample {
        cycles,
        instructions,
        switches: after.saturating_sub(before),
    })
}

/// Starts `board` in `lab` (under callgrind writing `callgrind` if given) and waits until it
/// serves a session.
fn start(board: &Board, lab: &Lab, bins: &Bins, callgrind: Option<&Path>) -> Result<Child> {
    let argv = board.argv(lab);
    let mut cmd = match callgrind {
        Some(out) => {
            let mut cmd = lab.board_command("valgrind");
            cmd.arg("--tool=callgrind")
                .arg(format!("--callgrind-out-file={}", out.display()))
                .args(&argv);
            cmd
        }
        None => {
            let mut cmd = lab.board_command(&argv[0]);
            cmd.args(&argv[1..]);
            cmd
        }
    };
    // OpENer keeps its non-volatile data in the working directory.
    let work = bins.dir.join("board-cwd");
    let _ = fs::create_dir_all(&work);
    let log = fs::File::create(bins.dir.join("host-board.log"))
        .map_err(|e| Error(format!("board log: {e}")))?;
    let mut child = cmd
        .current_dir(&work)
        .stdout(Stdio::null())
        .stderr(log)
        .spawn()
        .map_err(|e| Error(format!("{}: {e}", board.name())))?;
    let deadline = Instant::now() + START;
    while Instant::now() < deadline {
        sleep(Duration::from_millis(500));
        let probe = lab
            .command(&bins.request_rate)
            .args(["--target", BOARD_IP, "--seconds", "0"])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status();
        if probe.is_ok_and(|s| s.success()) {
            if callgrind.is_some() {
                zero_counters(&mut child)?;
            }
            return Ok(child);
        }
    }
    stop(&mut child);
    err(format!("{} did not start within {START:?}", board.name()))
}

/// Zeroes the callgrind counters of the board `child` runs under valgrind: what it counts from
/// then on leaves out its start, whose cost varies with the probes it took.
fn zero_counters(child: &mut Child) -> Result {
    let pid = child.id().to_string();
    if let Err(e) = run(std::process::Command::new("callgrind_control").args(["-z", &pid])) {
        stop(child);
        return Err(e);
    }
    Ok(())
}

/// Stops a board with SIGINT (callgrind writes its profile at exit), waiting up to 30 s.
fn stop(child: &mut Child) {
    signal(child.id() as i32, SIGINT);
    let deadline = Instant::now() + Duration::from_secs(30);
    while Instant::now() < deadline {
        if let Ok(Some(_)) = child.try_wait() {
            return;
        }
        sleep(Duration::from_millis(100));
    }
    let _ = child.kill();
    let _ = child.wait();
}

/// One round of a board's request rates.
struct Rates {
    /// Requests per second on 1 session.
    one: f64,
    /// Requests per second on 3 sessions at once, and the board's CPU time then.
    three: Loaded,
}

/// One `request_rate` run on 3 sessions: requests per second and the board's CPU time.
struct Loaded {
    /// Requests per second reached.
    per_second: f64,
    /// The board's CPU time (user and system, every thread) per request, in microseconds:
    /// the work the adapter makes the machine do, which the rate shares with the client.
    cpu_us_per_request: f64,
}

/// Requests per second answered on 1 and on 3 sessions at once, back to back, and the
/// board's CPU time per request on 3.
fn rates(board: &Board, bins: &Bins) -> Result<Rates> {
    let lab = board.lab()?;
    let mut child = start(board, &lab, bins, None)?;
    let pid = child.id();
    let result = loaded(&lab, bins, pid, 1, 0).and_then(|one| {
        Ok(Rates {
            one: one.per_second,
            three: loaded(&lab, bins, pid, 3, 0)?,
        })
    });
    stop(&mut child);
    result
}

/// The board's CPU time per request on 3 sessions paced to `rate` requests per second in
/// all, and the rate reached.
fn paced(board: &Board, bins: &Bins, rate: u32) -> Result<Loaded> {
    let lab = board.lab()?;
    let mut child = start(board, &lab, bins, None)?;
    let result = loaded(&lab, bins, child.id(), 3, rate);
    stop(&mut child);
    result
}

/// `request_rate` on `sessions` sessions at `rate` (0: back to back) against the board
/// running as `pid`, with the board's CPU time meanwhile.
fn loaded(lab: &Lab, bins: &Bins, pid: u32, sessions: u32, rate: u32) -> Result<Loaded> {
    let cpu_ticks = || usage(pid).map_or(0, |u| u.cpu_ticks);
    let before = cpu_ticks();
    let report = request_rate(lab, bins, sessions, bins.seconds.2, rate)?;
    let ticks = cpu_ticks().saturating_sub(before);
    let number = |key: &str| {
        report[key]
            .as_f64()
            .ok_or_else(|| Error(format!("request_rate printed {report}")))
    };
    let requests = number("requests")?;
    Ok(Loaded {
        per_second: number("per_second")?,
        cpu_us_per_request: ticks as f64 * 1e6 / ticks_per_second() as f64 / requests.max(1.0),
    })
}

/// User-space instructions per Get_Attribute_Single on 3 sessions at once: the board under
/// callgrind answering `request_rate` for a short and a long run, the difference of the
/// totals over the difference of the requests answered (start-up and shut-down cancel out).
fn request_cost(board: &Board, bins: &Bins) -> Result<f64> {
    let seconds = bins.seconds.2;
    let mut runs = Vec::new();
    for (i, seconds) in [seconds, 3 * seconds].into_iter().enumerate() {
        let lab = board.lab()?;
        let out = bins.dir.join(format!(
            "host-{}-requests-{i}.callgrind",
            board.name().replace([' ', '-'], "_")
        ));
        let _ = fs::remove_file(&out);
        let mut child = start(board, &lab, bins, Some(out.as_path()))?;
        let report = request_rate(&lab, bins, 3, seconds, 0);
        stop(&mut child);
        let requests = report?["requests"]
            .as_u64()
            .ok_or_else(|| Error(format!("{}: request_rate counted nothing", board.name())))?;
        runs.push((requests, crate::bench::callgrind_total(&out)?));
    }
    let [(r0, i0), (r1, i1)] = runs[..] else {
        return err("two runs expected");
    };
    Ok(i1.saturating_sub(i0) as f64 / r1.saturating_sub(r0).max(1) as f64)
}

/// `request_rate` in `lab`: Get_Attribute_Single on `sessions` sessions for `seconds`,
/// paced to `rate` requests per second in all (0: back to back); its JSON report.
fn request_rate(lab: &Lab, bins: &Bins, sessions: u32, seconds: u64, rate: u32) -> Result<Value> {
    let out = lab
        .command(&bins.request_rate)
        .args(["--target", BOARD_IP, "--sessions"])
        .arg(sessions.to_string())
        .arg("--seconds")
        .arg(seconds.to_string())
        .arg("--rate")
        .arg(rate.to_string())
        .output()
        .map_err(|e| Error(format!("request_rate: {e}")))?;
    serde_json::from_slice::<Value>(&out.stdout).map_err(|_| {
        Error(format!(
            "request_rate: {}",
            String::from_utf8_lossy(&out.stderr)
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_common_rate_is_half_the_slowest_in_thousands() {
        assert_eq!(common_rate(&[76_917.0, 79_545.0, 72_921.0]), 36_000);
        assert_eq!(common_rate(&[1_999.0]), 1_000);
        assert_eq!(common_rate(&[0.0]), 1_000);
        assert_eq!(common_rate(&[]), 1_000);
    }

    #[test]
    fn boards_take_turns_every_other_round_reversed() {
        let mut order = Vec::new();
        let out = in_turns(3, 2, |i| {
            order.push(i);
            Ok(i * 10)
        })
        .unwrap();
        assert_eq!(order, [0, 1, 2, 2, 1, 0]);
        assert_eq!(out, [vec![0, 0], vec![10, 10], vec![20, 20]]);
    }
}
