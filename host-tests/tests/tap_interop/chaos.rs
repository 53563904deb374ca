//! Chaos soak (issue 28 item 4): for `CHAOS_MINUTES` minutes, a seeded random interleaving
//! (`CHAOS_SEED`, printed; the same seed gives the same schedule) of reconnect churn,
//! hostile requests, link flaps, Identity Resets, non-volatile writes, explicit bursts and
//! Class 1 bursts, over a steady load of 4 Class 1 connections at 1 ms (x32) and an
//! explicit read every 10 ms. Invariants: the board's process lives through it (same PID,
//! never gone), every T->O gap longer than 20 ms falls in the window of a link flap or a
//! Reset (the faults that end I/O) or in a stall of the host's own 1 ms timer loop measured
//! beside the scanner (this shared machine, not the adapter), every failed explicit read in
//! the window of a link flap or a Reset, every fault's own check
//! passes, all sessions and connection slots are free at the end (3 sessions and 10
//! connections open at once), and the board's resident memory and CPU per period
//! (a minute; 10 s in runs under 3 minutes) stay level. One `FAULT-REPORT` line carries the
//! figures; `cargo xtask faults --chaos MINUTES [--seed S]` runs it and writes the report.
//! Without `CHAOS_MINUTES` the test returns at once (it is not part of `cargo xtask test`).

use std::collections::BTreeMap;
use std::io;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use crate::chaos_faults::{self as fault, Control, STEADY};
use crate::chaos_io::{self, Gap, Load, GAP};
use crate::chaos_plan::{Kind, Plan, Step};
use crate::common;
use crate::fault_io::board_real_time;
use crate::faults::cm_counter;
use host_tests::faults::{pid_in, report};
use host_tests::netns::Namespace;
use host_tests::rig::{Rig, BOARD_IP};
use host_tests::scanner::open_generic;
use host_tests::usage::{ticks_per_second, usage};

/// A window in which a fault may end I/O: from its start to the steady connections' first
/// T->O after their replacement.
#[derive(Debug, Clone, Copy)]
struct Window {
    start: Instant,
    end: Instant,
}

/// A gap may start this much before its fault (the last T->O came just before it).
const GAP_LEAD: Duration = Duration::from_millis(50);
/// An explicit read may fail this long after a window (its reply timeout, a reconnect).
const EXPLICIT_TAIL: Duration = Duration::from_secs(5);
/// Resident memory the board may gain from the first period to the last, KiB.
const RSS_SLACK_KIB: u64 = 256;
/// CPU of the last third of the periods against the first (as the fault soak's long run).
const CPU_GROWTH: f64 = 1.5;

#[test]
#[ignore = "needs root: network namespace and TAP; `cargo xtask faults --chaos MINUTES`"]
fn chaos_soak() {
    let Some(minutes) = std::env::var("CHAOS_MINUTES")
        .ok()
        .and_then(|m| m.parse::<u64>().ok())
        .filter(|&m| m > 0)
    else {
        println!("chaos_soak: CHAOS_MINUTES not set, nothing run");
        return;
    };
    let seed = std::env::var("CHAOS_SEED")
        .ok()
        .and_then(|s| s.parse::<u64>().ok())
        .unwrap_or_else(|| {
            std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(1, |d| d.as_nanos() as u64)
        });
    println!("chaos: seed {seed}, {minutes} minutes");
    let nv = common::fresh_nv_file("chaos.nv");
    let args = ["--nv-file", nv.to_str().expect("a UTF-8 path")];
    let rig = Rig::start_at(&common::host_bin(), "generic", &args, None, BOARD_IP).expect("rig");
    let pid = pid_in(rig.ns(), "enip-host").expect("board pid");
    board_real_time(&rig);
    let load = Load::default();
    let ns = rig.ns();
    let run = ns
        .inside(|| {
            std::thread::scope(|s| {
                let io = s.spawn(|| chaos_io::run(&load));
                let run = drive(ns, &load, pid, minutes, seed);
                load.stop.store(true, Ordering::Relaxed);
                let io = io
                    .join()
                    .map_err(|_| io::Error::other("I/O thread panicked"));
                let mut run = run?;
                io??;
                // The load's sessions are closed now.
                run.end_check = end_check(std::mem::take(&mut run.steady_close_errors))?;
                Ok::<_, io::Error>(run)
            })
        })
        .expect("namespace")
        .unwrap_or_else(|e| panic!("{e}\n{}", rig.board_log_tail(40)));
    let pid_after = pid_in(rig.ns(), "enip-host").ok();
    let log = rig.board_log();
    let log_file = common::scratch("chaos-board.log");
    std::fs::write(&log_file, &log).expect("board log saved");
    println!("chaos: board log in {}", log_file.display());
    let panics = log.matches("panicked").count();
    rig.finish().expect("the board ran to the end");
    let figures = judge(&load, run, seed, minutes, pid, pid_after, panics);
    let failed: Vec<String> = figures["invariants"]
        .as_object()
        .map(|o| {
            o.iter()
                .filter(|(_, v)| v.as_bool() != Some(true))
                .map(|(k, _)| k.clone())
                .collect()
        })
        .unwrap_or_default();
    report("chaos", figures);
    assert!(
        failed.is_empty(),
        "chaos seed {seed}: invariants failed: {failed:?}"
    );
}

/// What the scheduler saw.
struct Run {
    /// Faults injected, by kind.
    counts: BTreeMap<&'static str, u64>,
    /// Faults whose own check failed: (seconds into the run, kind, what).
    failures: Vec<(f64, &'static str, String)>,
    windows: Vec<Window>,
    /// Every step: (start, end, kind).
    steps: Vec<(Instant, Instant, &'static str)>,
    /// Times a steady connection was found silent for 500 ms between steps (ended, its gap
    /// open) and the steady connections replaced.
    silent_reopens: u64,
    /// Per period: (usage, T->O, explicit reads, faults so far).
    samples: Vec<Value>,
    start: Instant,
    /// Close statuses other than 0 of the steady connections at the end.
    steady_close_errors: Vec<u8>,
    /// The end check: sessions and connections opened at once, their close statuses.
    end_check: Value,
    schedule_head: Vec<String>,
}

/// Runs the schedule for `minutes` over the steady load; then the end check.
fn drive(ns: &Namespace, load: &Load, pid: u32, minutes: u64, seed: u64) -> io::Result<Run> {
    let mut ctl = Control::new();
    ctl.reopen_steady(load)?;
    let start = Instant::now();
    settle(load, start);
    let end = start + Duration::from_secs(60 * minutes);
    let period = Duration::from_secs(if minutes >= 3 { 60 } else { 10 });
    let injected = AtomicU64::new(0);
    let mut run = Run {
        counts: BTreeMap::new(),
        failures: Vec::new(),
        windows: Vec::new(),
        steps: Vec::new(),
        silent_reopens: 0,
        samples: Vec::new(),
        start,
        steady_close_errors: Vec::new(),
        end_check: Value::Null,
        schedule_head: Plan::new(seed).take(8).map(|s| s.to_string()).collect(),
    };
    println!("chaos: schedule starts {:?}", run.schedule_head);
    let samples = std::thread::scope(|s| -> io::Result<_> {
        let sampler = s.spawn(|| sample(load, pid, start, end, period, &injected));
        for step in Plan::new(seed) {
            let pause = step
                .pause
                .min(end.saturating_duration_since(Instant::now()));
            std::thread::sleep(pause);
            if Instant::now() >= end {
                break;
            }
            if let Some(stale) = stale_steady(load) {
                // Its gap is recorded and judged like any other.
                println!(
                    "chaos: {:.1} s: steady slot {stale} silent, reopened",
                    secs(start)
                );
                run.silent_reopens += 1;
                ctl.reopen_steady(load)?;
            }
            let at = Instant::now();
            let outcome = inject(ns, load, &mut ctl, &step);
            injected.fetch_add(1, Ordering::Relaxed);
            run.steps.push((at, Instant::now(), step.kind.name()));
            *run.counts.entry(step.kind.name()).or_default() += 1;
            match outcome {
                Ok(Some(window_end)) => run.windows.push(Window {
                    start: at,
                    end: window_end,
                }),
                Ok(None) => {}
                Err(e) => {
                    println!("chaos: {step} failed: {e}");
                    run.failures.push((secs(start), step.kind.name(), e));
                    if matches!(step.kind, Kind::LinkFlap | Kind::Reset) {
                        run.windows.push(Window {
                            start: at,
                            end: Instant::now(),
                        });
                    }
                }
            }
        }
        sampler
            .join()
            .map_err(|_| io::Error::other("sampler panicked"))?
    })?;
    run.samples = samples;
    load.close_gaps(Instant::now());
    run.steady_close_errors = ctl.close_all(load)?;
    Ok(run)
}

/// Runs one step; for a link flap or a Reset, the end of its window.
fn inject(
    ns: &Namespace,
    load: &Load,
    ctl: &mut Control,
    step: &Step,
) -> Result<Option<Instant>, String> {
    let p = step.param;
    match step.kind {
        Kind::Churn => fault::churn(ctl, 5 + p % 26).map(|()| None),
        Kind::Hostile => fault::hostile(p).map(|()| None),
        Kind::NvWrite => fault::nv_write(p).map(|()| None),
        Kind::ExplicitBurst => fault::explicit_burst(50 + p % 251).map(|()| None),
        Kind::Class1Burst => {
            fault::class1_burst(ctl, load, Duration::from_millis(500 + p % 2500)).map(|()| None)
        }
        Kind::LinkFlap => {
            fault::link_flap(ns, Duration::from_millis(100 + p % 1900))?;
            ctl.reopen_steady(load).map_err(|e| e.to_string())?;
            Ok(Some(settle(load, Instant::now())))
        }
        Kind::Reset => {
            fault::identity_reset(u8::from(p.is_multiple_of(4)))?;
            ctl.reopen_steady(load).map_err(|e| e.to_string())?;
            Ok(Some(settle(load, Instant::now())))
        }
    }
}

/// Waits (at most 2 s) until every steady connection has produced since `since`; returns
/// when it did, plus [`GAP`].
fn settle(load: &Load, since: Instant) -> Instant {
    let bound = Instant::now() + Duration::from_secs(2);
    while Instant::now() < bound
        && (0..STEADY).any(|i| load.last_arrival(i).is_none_or(|at| at < since))
    {
        std::thread::sleep(Duration::from_millis(2));
    }
    Instant::now() + GAP
}

/// A steady slot silent for 500 ms (ended outside any fault), if any.
fn stale_steady(load: &Load) -> Option<usize> {
    (0..STEADY).find(|&i| {
        load.last_arrival(i)
            .is_none_or(|at| at.elapsed() > Duration::from_millis(500))
    })
}

fn secs(start: Instant) -> f64 {
    (start.elapsed().as_secs_f64() * 10.0).round() / 10.0
}

/// The board's usage and the load's counters at the start and each `period` until `end`.
fn sample(
    load: &Load,
    pid: u32,
    start: Instant,
    end: Instant,
    period: Duration,
    injected: &AtomicU64,
) -> io::Result<Vec<Value>> {
    let tps = ticks_per_second() as f64;
    let read = || {
        (
            Instant::now(),
            usage(pid),
            load.t_o.load(Ordering::Relaxed),
            load.explicit_ok.load(Ordering::Relaxed),
            injected.load(Ordering::Relaxed),
            load.gaps.lock().map_or(0, |g| g.len()),
        )
    };
    let mut prev = read();
    let first = prev
        .1
        .as_ref()
        .map_err(|e| io::Error::other(e.to_string()))?;
    let mut prev_cpu = first.cpu_ticks;
    let mut out = Vec::new();
    for i in 1u32.. {
        let at = start + period * i;
        if at > end + Duration::from_secs(1) {
            break;
        }
        std::thread::sleep(at.saturating_duration_since(Instant::now()));
        let now = read();
        let elapsed = now.0.duration_since(prev.0).as_secs_f64();
        let (alive, rss, cpu) = match &now.1 {
            Ok(u) => {
                let cpu = (u.cpu_ticks - prev_cpu) as f64 / tps / elapsed * 100.0;
                prev_cpu = u.cpu_ticks;
                (true, u.rss_kib, (cpu * 10.0).round() / 10.0)
            }
            Err(_) => (false, 0, 0.0),
        };
        out.push(json!({
            "period": i,
            "board_alive": alive,
            "cpu_percent": cpu,
            "rss_kib": rss,
            "t_o": now.2 - prev.2,
            "explicit_reads": now.3 - prev.3,
            "faults": now.4 - prev.4,
            "gaps": now.5 - prev.5,
        }));
        prev = now;
    }
    Ok(out)
}

/// With everything of the run closed: 3 sessions at once, and 10 connections (an owner and
/// 9 input-only) on them, each closed with status 0.
fn end_check(steady_closed: Vec<u8>) -> io::Result<Value> {
    let mut sessions = Vec::new();
    for _ in 0..3 {
        sessions.push(crate::faults::session()?);
    }
    let [first, second, _] = &mut sessions[..] else {
        return Err(io::Error::other("three sessions"));
    };
    let counters: Vec<u16> = [1, 3, 5, 8]
        .iter()
        .map(|a| cm_counter(second, *a))
        .collect::<io::Result<_>>()?;
    let opened = open_generic(first, 10, 100_000, 0)?;
    let mut closed_ok = 0;
    for c in &opened {
        if first.forward_close(c.triad)?.general == 0 {
            closed_ok += 1;
        }
    }
    Ok(json!({
        "sessions_opened": sessions.len(),
        "connections_opened": opened.len(),
        "connections_closed_ok": closed_ok,
        "steady_close_errors": steady_closed,
        "cm_open_requests_resource_rejects_closes_timeouts": counters,
    }))
}

/// The figures and the invariants of a finished run.
fn judge(
    load: &Load,
    run: Run,
    seed: u64,
    minutes: u64,
    pid: u32,
    pid_after: Option<u32>,
    panics: usize,
) -> Value {
    let in_window = |at: Instant, lead: Duration, tail: Duration| {
        run.windows
            .iter()
            .any(|w| at + lead >= w.start && at <= w.end + tail)
    };
    let gaps = load.gaps.lock().map(|g| g.clone()).unwrap_or_default();
    let at =
        |t: Instant| (t.saturating_duration_since(run.start).as_secs_f64() * 10.0).round() / 10.0;
    let stalls = load
        .host_stalls
        .lock()
        .map(|s| s.clone())
        .unwrap_or_default();
    let overlaps =
        |from: Instant, to: Instant| move |(a, b): &(Instant, Instant)| *a <= to && *b >= from;
    let (in_faults, others): (Vec<&Gap>, Vec<&Gap>) = gaps
        .iter()
        .partition(|g| in_window(g.from, GAP_LEAD, Duration::ZERO));
    let (in_stalls, unexplained): (Vec<&Gap>, Vec<&Gap>) = others
        .into_iter()
        .partition(|g| stalls.iter().any(overlaps(g.from, g.to)));
    let unexplained: Vec<Value> = unexplained
        .iter()
        .map(|g| {
            let during = run
                .steps
                .iter()
                .find(|(a, b, _)| overlaps(g.from, g.to)(&(*a, *b)))
                .map_or("between steps", |s| s.2);
            json!({"slot": g.slot, "at_s": at(g.from),
                "ms": g.to.duration_since(g.from).as_millis() as u64, "during": during})
        })
        .collect();
    let stall_max_ms = stalls
        .iter()
        .map(|(a, b)| b.duration_since(*a).as_millis() as u64)
        .max();
    let failures = load
        .explicit_failures
        .lock()
        .map(|f| f.clone())
        .unwrap_or_default();
    let explicit_unexplained: Vec<f64> = failures
        .iter()
        .filter(|t| !in_window(**t, Duration::ZERO, EXPLICIT_TAIL))
        .map(|t| at(*t))
        .collect();
    let fig = |k: &str| -> Vec<f64> { run.samples.iter().filter_map(|s| s[k].as_f64()).collect() };
    let (cpu, rss) = (fig("cpu_percent"), fig("rss_kib"));
    let third = cpu.len().div_ceil(3).max(1);
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let cpu_first = mean(&cpu[..third.min(cpu.len())]);
    let cpu_last = mean(&cpu[cpu.len().saturating_sub(third)..]);
    let (rss_first, rss_last) = (
        rss.first().copied().unwrap_or(0.0),
        rss.last().copied().unwrap_or(0.0),
    );
    let end = &run.end_check;
    let invariants = json!({
        "board_same_pid_never_gone": pid_after == Some(pid)
            && run.samples.iter().all(|s| s["board_alive"] == true) && panics == 0,
        "every_t_o_gap_in_a_fault_window_or_host_stall": unexplained.is_empty(),
        "every_explicit_failure_in_a_fault_window": explicit_unexplained.is_empty(),
        "every_fault_check_passed": run.failures.is_empty(),
        "sessions_and_connections_free_at_end": end["sessions_opened"] == 3
            && end["connections_opened"] == 10 && end["connections_closed_ok"] == 10
            && end["steady_close_errors"] == json!([]),
        "rss_level": rss_last <= rss_first + RSS_SLACK_KIB as f64,
        "cpu_level": cpu_last <= cpu_first * CPU_GROWTH + 2.0,
    });
    let window_ms: Vec<u64> = run
        .windows
        .iter()
        .map(|w| w.end.duration_since(w.start).as_millis() as u64)
        .collect();
    json!({
        "seed": seed,
        "minutes": minutes,
        "schedule_head": run.schedule_head,
        "faults": run.counts,
        "faults_total": run.counts.values().sum::<u64>(),
        "invariants": invariants,
        "t_o_received": load.t_o.load(Ordering::Relaxed),
        "o_t_sent": load.o_t.load(Ordering::Relaxed),
        "o_t_send_errors": load.send_errors.load(Ordering::Relaxed),
        "t_o_gaps_over_20ms": gaps.len(),
        "t_o_gaps_in_fault_windows": in_faults.len(),
        "t_o_gaps_in_host_stalls": in_stalls.len(),
        "host_timer_stalls_over_10ms": stalls.len(),
        "host_timer_stall_max_ms": stall_max_ms,
        "t_o_gaps_unexplained": unexplained,
        "fault_windows": run.windows.len(),
        "fault_window_ms_max": window_ms.iter().max(),
        "explicit_reads_ok": load.explicit_ok.load(Ordering::Relaxed),
        "explicit_failures": failures.len(),
        "explicit_failures_unexplained_at_s": explicit_unexplained,
        "fault_check_failures": run.failures.iter().map(|(t, k, e)| json!({"at_s": t, "kind": k, "error": e})).collect::<Vec<_>>(),
        "steady_reopened_after_500ms_silence": run.silent_reopens,
        "end_check": run.end_check,
        "board_panics_logged": panics,
        "board_cpu_percent_first_last_third": [(cpu_first * 10.0).round() / 10.0, (cpu_last * 10.0).round() / 10.0],
        "board_rss_kib_first_last": [rss_first, rss_last],
        "per_period": run.samples,
    })
}
