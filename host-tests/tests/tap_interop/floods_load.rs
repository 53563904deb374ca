//! The running load every flood test (issue 28 item 1) measures against, and the phases it
//! is cut into: 10 Class 1 connections at a 1 ms RPI with a x32 timeout multiplier, one
//! pycomm3 session reading the Identity product name every 100 ms (`peers/steady_reader.py`)
//! and a fresh client trying to register and read every 250 ms, over one run whose phases
//! are "no flood" and each flood in turn, so that every flood is compared with the same load
//! without it on the same board in the same run.
//!
//! The board is pinned to CPU 0 (`taskset`) at the highest normal priority (nice -20);
//! flooders run on CPU 1 at normal priority. On this 2-core machine an unpinned flooder takes
//! the board's core and every connection times out, which would measure the machine, not the
//! adapter. Not SCHED_FIFO as elsewhere: a line-rate flood can keep the board busy for whole
//! seconds, and the kernel then stops a real-time task for some 50 ms a second to run the
//! normal tasks of its core (`high_priority_process`), which times out every connection.

use std::io;
use std::process::Command;
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use serde_json::{json, Value};

use crate::common::{self, REPLY};
use crate::fault_io::SCANNER_PRIORITY;
use crate::faults::cm_counter;
use host_tests::enip::{mr_request, path, Client};
use host_tests::faults::{high_priority_process, ms, pid_in, real_time_thread};
use host_tests::netns::Namespace;
use host_tests::peers;
use host_tests::rig::{Rig, BOARD_IP};
use host_tests::scanner::stats::connection_stats;
use host_tests::scanner::{exchange, open_generic, Opened, Record, Session};
use host_tests::usage::{ticks_per_second, usage};

/// Connections, RPI and timeout multiplier code (3: x32) of the load; the emulated board,
/// which delivers some 3 000 T->O datagrams a second on this machine, runs its load at
/// [`QEMU_RPI`].
pub const CONNECTIONS: usize = 10;
pub const RPI: Duration = Duration::from_millis(1);
pub const QEMU_RPI: Duration = Duration::from_millis(10);
const MULTIPLIER: u8 = 3;
/// The pycomm3 session's read period.
const READ_PERIOD_MS: u64 = 100;
/// How often a fresh client tries to be served, and its bound.
const PROBE_EVERY: Duration = Duration::from_millis(250);
/// Load before the first phase, so that every phase sees the load settled and the pycomm3
/// session (Python takes a while to start on a busy machine) reading.
const LEAD_IN: Duration = Duration::from_millis(1500);
/// Bound on being served again after a flood ends (issue 28).
pub const SERVED_AFTER: Duration = Duration::from_secs(1);

/// What a flood is handed: its namespace, the load's connections, and when it must end.
pub struct Flood<'a> {
    pub ns: &'a Namespace,
    pub opened: &'a [Opened],
    pub until: Instant,
}

/// A flood: runs until `Flood::until` (bounded by it), returns its own figures.
pub type FloodFn<'a> = &'a (dyn Fn(&Flood<'_>) -> Value + Sync);

/// One phase of the run: no flood, or a flood.
pub struct Phase<'a> {
    pub name: String,
    pub length: Duration,
    pub flood: Option<FloodFn<'a>>,
}

/// Which CPU the board and the flooders run on.
pub const BOARD_CPU: u32 = 0;
pub const FLOOD_CPU: u32 = 1;

/// Pins the board `program` (as `/proc/PID/comm` has it: `enip-host` or QEMU) to
/// [`BOARD_CPU`], `enip-host` at nice -20 too; returns its pid.
pub fn pin_board(rig: &Rig, program: &str) -> u32 {
    let pid = pid_in(rig.ns(), program).expect("board pid");
    let status = Command::new("taskset")
        .args(["-a", "-p", "-c", &BOARD_CPU.to_string(), &pid.to_string()])
        .output()
        .expect("taskset");
    assert!(status.status.success(), "taskset: {status:?}");
    // QEMU's threads share the CPU (its vCPU thread runs flat out and would starve the one
    // that moves frames to and from the TAP at a higher priority): pinned only.
    if program == "enip-host" {
        high_priority_process(pid).expect("nice -20 for the board");
    }
    pid
}

/// Pins the calling thread to [`FLOOD_CPU`] (a flooder's thread).
pub fn pin_flooder_thread() {
    let tid = rustix::thread::gettid().as_raw_nonzero().get();
    let _ = Command::new("taskset")
        .args(["-p", "-c", &FLOOD_CPU.to_string(), &tid.to_string()])
        .output();
}

fn unix_now() -> f64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64())
}

/// Where each phase lies, in seconds since the load started and in unix time.
struct Window {
    from: Duration,
    to: Duration,
    unix: (f64, f64),
}

/// What one fresh client saw: when it started (unix), and the time to be served (or none).
type Probe = (f64, Option<Duration>);

/// How long one probe of [`served_after`] waits for its TCP handshake. A SYN sent as the
/// flood ends can be lost with the flood's last frames (the TAP's ring, a MAC's, or the
/// stack's queue still full): the probe then tries again after this, not after the kernel's
/// 1 s SYN retransmission, so it measures when the adapter serves again, not the client's
/// timer.
const AFTER_CONNECT: Duration = Duration::from_millis(300);

/// Connects (waiting `connect` for the handshake), registers, reads the Identity product
/// name; how long it took, or `None`.
fn probe_once(ns: &Namespace, connect: Duration) -> Option<Duration> {
    let t = Instant::now();
    let r = (|| {
        let mut c = Client::connect(ns, connect)?;
        c.register(common::SERVING_BOUND)?;
        c.request(
            &mr_request(0x0E, &path(1, 1, Some(7)), &[]),
            common::SERVING_BOUND,
        )
    })();
    r.ok().filter(|r| r.general == 0).map(|_| t.elapsed())
}

/// Time until a fresh client is served, trying again every 10 ms for up to 3 s.
fn served_after(ns: &Namespace) -> Option<Duration> {
    let t = Instant::now();
    while t.elapsed() < Duration::from_secs(3) {
        if probe_once(ns, AFTER_CONNECT).is_some() {
            return Some(t.elapsed());
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    None
}

/// Runs the load (its connections at `rpi`) through `phases` on `rig` (whose board process is `program`) and returns
/// each phase's figures, with the board's CPU time per phase and the connection timeouts the
/// Connection Manager counted over the whole run. Every phase after a flood also gets the
/// time a fresh client took to be served once the flood ended.
fn run_phases(rig: &Rig, program: &str, rpi: Duration, phases: &[Phase<'_>]) -> Value {
    let pid = pin_board(rig, program);
    let ns = rig.ns();
    let total: Duration = LEAD_IN + phases.iter().map(|p| p.length).sum::<Duration>();
    let outcome = ns.inside(|| -> io::Result<Value> {
        let mut s = Session::connect(BOARD_IP, REPLY)?;
        let timeouts_before = cm_counter(&mut s, 8)?;
        let opened = open_generic(&mut s, CONNECTIONS, rpi.as_micros() as u32, MULTIPLIER)?;
        let start = Instant::now();
        let unix_start = unix_now();
        let mut windows = Vec::new();
        let mut at = LEAD_IN;
        for p in phases {
            let to = at + p.length;
            windows.push(Window {
                from: at,
                to,
                unix: (unix_start + at.as_secs_f64(), unix_start + to.as_secs_f64()),
            });
            at = to;
        }
        let run = std::thread::scope(|sc| {
            let reader = sc.spawn(|| {
                let input = json!({
                    "host": BOARD_IP.to_string(),
                    "seconds": total.as_secs_f64(),
                    "period_ms": READ_PERIOD_MS,
                });
                peers::run(
                    ns,
                    "steady_reader.py",
                    &input,
                    total + Duration::from_secs(20),
                )
            });
            let prober = sc.spawn(|| {
                let mut seen: Vec<Probe> = Vec::new();
                let mut next = start;
                while start.elapsed() < total {
                    std::thread::sleep(next.saturating_duration_since(Instant::now()));
                    next += PROBE_EVERY;
                    seen.push((unix_now(), probe_once(ns, common::SERVING_BOUND)));
                }
                seen
            });
            let driver = sc.spawn(|| {
                phases
                    .iter()
                    .zip(&windows)
                    .map(|(p, w)| {
                        std::thread::sleep(
                            (start + w.from).saturating_duration_since(Instant::now()),
                        );
                        let cpu0 = usage(pid).map(|u| u.cpu_ticks).unwrap_or(0);
                        let until = start + w.to;
                        let mut figures = json!({});
                        if let Some(flood) = p.flood {
                            figures["flood"] = flood(&Flood {
                                ns,
                                opened: &opened,
                                until,
                            });
                            let after = served_after(ns);
                            figures["served_after_flood_ms"] = json!(after.map(ms));
                        }
                        std::thread::sleep(until.saturating_duration_since(Instant::now()));
                        let cpu1 = usage(pid).map(|u| u.cpu_ticks).unwrap_or(0);
                        let cpu = cpu1.saturating_sub(cpu0) as f64 / ticks_per_second() as f64;
                        figures["board_cpu_percent"] =
                            json!((cpu / p.length.as_secs_f64() * 1000.0).round() / 10.0);
                        figures
                    })
                    .collect::<Vec<Value>>()
            });
            // The I/O threads exchange() starts inherit it; the threads above do not.
            let record = real_time_thread(SCANNER_PRIORITY)
                .and_then(|()| exchange(BOARD_IP, &opened, rpi, total, |k| [k as u8; 32]));
            // Counted and closed at once: without O->T they time out after 32 ms.
            let timeouts = cm_counter(&mut s, 8)?.wrapping_sub(timeouts_before);
            let mut still_open = 0;
            for c in &opened {
                if s.forward_close(c.triad)?.general == 0 {
                    still_open += 1;
                }
            }
            let join = |e| io::Error::other(format!("{e:?}"));
            Ok::<_, io::Error>((
                (record?, timeouts, still_open),
                reader.join().map_err(|_| join("reader"))??,
                prober.join().map_err(|_| join("prober"))?,
                driver.join().map_err(|_| join("phases"))?,
            ))
        })?;
        let ((record, timeouts, still_open), reads, probes, phase_figures) = run;
        let summary = record.summary(total.as_micros() as u64, 100_000);
        let per_phase: Vec<Value> = phases
            .iter()
            .zip(&windows)
            .zip(phase_figures)
            .map(|((p, w), mut f)| {
                f["phase"] = json!(p.name);
                f["seconds"] = json!(p.length.as_secs_f64());
                f["class1"] = class1(&record, w, rpi);
                f["pycomm3"] = pycomm3(&reads, w);
                f["new_sessions"] = fresh_clients(&probes, w);
                f
            })
            .collect();
        let by_phase: serde_json::Map<String, Value> = per_phase
            .iter()
            .map(|f| (f["phase"].as_str().unwrap_or("").to_string(), line(f)))
            .collect();
        Ok(json!({
            "by_phase": by_phase,
            "connections": CONNECTIONS,
            "rpi_us": rpi.as_micros() as u64,
            "multiplier": 32,
            "connections_timed_out": timeouts,
            "connections_silent_at_the_end": summary.timeouts,
            "connections_open_at_the_end": still_open,
            "phases": per_phase,
        }))
    });
    outcome
        .expect("namespace")
        .unwrap_or_else(|e| panic!("{e}\n{}", rig.board_log_tail(40)))
}

/// One phase's figures on one line, for `cargo xtask faults`' table.
fn line(f: &Value) -> Value {
    let (c, p, n) = (&f["class1"], &f["pycomm3"], &f["new_sessions"]);
    let mut text = format!(
        "T->O {}% missing, {} lost, max {} us; pycomm3 {}/{} max {} ms; new {}/{}; CPU {}%",
        c["t_o_missing_percent"],
        c["t_o_lost"],
        c["t_o_max_us_worst"],
        p["reads"].as_u64().unwrap_or(0) - p["failed"].as_u64().unwrap_or(0),
        p["reads"],
        p["max_ms"],
        n["served"],
        n["tried"],
        f["board_cpu_percent"],
    );
    if let Some(after) = f.get("served_after_flood_ms") {
        text.push_str(&format!("; served {after} ms after"));
    }
    json!(text)
}

/// Class 1 in window `w`: T->O received against expected, sequence gaps, worst interval.
fn class1(record: &Record, w: &Window, rpi: Duration) -> Value {
    let (from, to) = (w.from.as_micros() as u64, w.to.as_micros() as u64);
    let stats: Vec<_> = record
        .packets
        .iter()
        .map(|(id, p)| {
            let inside: Vec<(u64, u32)> = p
                .iter()
                .filter(|(t, _, _)| (from..to).contains(t))
                .map(|(t, s, _)| (*t, *s))
                .collect();
            connection_stats(*id, &inside)
        })
        .collect();
    let received: usize = stats.iter().map(|c| c.received).sum();
    let expected = CONNECTIONS as f64 * (w.to - w.from).as_secs_f64() / rpi.as_secs_f64();
    let lost: u64 = stats.iter().map(|c| c.lost).sum();
    json!({
        "t_o_received": received,
        "t_o_lost": lost,
        "t_o_missing_percent": ((1.0 - received as f64 / expected) * 1e4).round() / 100.0,
        "t_o_p99_us_worst": stats.iter().map(|c| c.p99_us).max(),
        "t_o_max_us_worst": stats.iter().map(|c| c.max_us).max(),
    })
}

/// The pycomm3 session's reads in window `w`: answered, failed, worst latency.
fn pycomm3(reads: &Value, w: &Window) -> Value {
    let inside: Vec<Option<f64>> = reads["reads"]
        .as_array()
        .into_iter()
        .flatten()
        .filter(|r| r[0].as_f64().is_some_and(|t| t >= w.unix.0 && t < w.unix.1))
        .map(|r| r[1].as_f64())
        .collect();
    let answered: Vec<f64> = inside.iter().flatten().copied().collect();
    json!({
        "reads": inside.len(),
        "failed": inside.len() - answered.len(),
        "max_ms": answered.iter().copied().reduce(f64::max).map(|m| (m * 10.0).round() / 10.0),
    })
}

/// The fresh clients of window `w`: tried, served, slowest served.
fn fresh_clients(probes: &[Probe], w: &Window) -> Value {
    let inside: Vec<Option<Duration>> = probes
        .iter()
        .filter(|(t, _)| *t >= w.unix.0 && *t < w.unix.1)
        .map(|(_, d)| *d)
        .collect();
    let served: Vec<Duration> = inside.iter().flatten().copied().collect();
    json!({
        "tried": inside.len(),
        "served": served.len(),
        "slowest_ms": served.iter().max().copied().map(ms),
    })
}

/// A flood of a [`flood_run`]: its name, its length and the flood.
pub type Named<'a> = (&'static str, Duration, FloodFn<'a>);

/// Runs the load (at `rpi`) on `rig`'s board `program` without a flood for `len`, then each
/// of `floods` followed by 1 s without; reports the figures as `scenario`, prints the
/// board's last log lines, and checks what holds under every flood: the load
/// ([`assert_load_held`]) and a fresh client served within [`SERVED_AFTER`] after each.
pub fn flood_run(
    rig: &Rig,
    program: &str,
    rpi: Duration,
    scenario: &str,
    len: Duration,
    floods: &[Named<'_>],
) -> Value {
    let mut phases = vec![Phase {
        name: "no flood".into(),
        length: len,
        flood: None,
    }];
    for (name, length, flood) in floods {
        phases.push(Phase {
            name: (*name).into(),
            length: *length,
            flood: Some(*flood),
        });
        phases.push(Phase {
            name: format!("after {name}"),
            length: Duration::from_secs(1),
            flood: None,
        });
    }
    let run = run_phases(rig, program, rpi, &phases);
    host_tests::faults::report(scenario, run.clone());
    // The connections' closes (a timeout names its reason), which the sessions' lines of the
    // fresh clients would push out of a plain tail.
    let log = rig.board_log();
    let closes: Vec<&str> = log
        .lines()
        .filter(|l| l.contains("] connection "))
        .collect();
    println!(
        "board log, connections closed ({}, the last 20):\n{}\nboard log (last lines):\n{}",
        closes.len(),
        closes[closes.len().saturating_sub(20)..].join("\n"),
        rig.board_log_tail(30)
    );
    assert_load_held(&run);
    for (name, _, _) in floods {
        assert_served_after(&run, name);
    }
    run
}

/// The figures of phase `name` in a [`run_phases`] result.
pub fn phase<'v>(run: &'v Value, name: &str) -> &'v Value {
    run["phases"]
        .as_array()
        .and_then(|p| p.iter().find(|f| f["phase"] == name))
        .unwrap_or_else(|| panic!("no phase {name} in {run}"))
}

/// What holds under every flood: no connection timed out and all are open at the end, the
/// pycomm3 session answered every read in every phase.
fn assert_load_held(run: &Value) {
    assert_eq!(
        (
            &run["connections_timed_out"],
            &run["connections_open_at_the_end"]
        ),
        (&json!(0), &json!(CONNECTIONS)),
        "Class 1 connections timed out: {run}"
    );
    for p in run["phases"].as_array().into_iter().flatten() {
        assert_eq!(
            p["pycomm3"]["failed"], 0,
            "the established pycomm3 session missed reads in {}: {run}",
            p["phase"]
        );
        assert!(
            p["pycomm3"]["reads"].as_u64().unwrap_or(0) > 0,
            "no pycomm3 read in {}: {run}",
            p["phase"]
        );
    }
}

/// A flood phase's fresh client was served within [`SERVED_AFTER`] once the flood ended.
fn assert_served_after(run: &Value, name: &str) {
    let after = phase(run, name)["served_after_flood_ms"].as_f64();
    assert!(
        after.is_some_and(|a| a <= ms(SERVED_AFTER)),
        "{name}: a new session {after:?} ms after the flood ended: {run}"
    );
}
