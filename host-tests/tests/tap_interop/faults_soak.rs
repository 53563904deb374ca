//! Soak (issue 13 item 2): 10 connections at a 1 ms RPI with a x32 timeout multiplier on the
//! TAP for 10 s (long: 600 s, `ENIP_FAULTS_SOAK_SECONDS`): no T->O lost, no connection timed
//! out, the T->O intervals shown beside the host's own 1 ms timer floor measured at the same
//! time (the `timer_baseline` program), and the board's CPU time and resident memory per
//! period (a fifth of the run; long: a minute) the same from first to last: resident memory
//! within 256 KiB, CPU in the last third of the periods not above the first third's by more
//! than load noise explains.
//! Nothing is captured: tshark would hold some 12 million frames.
//!
//! The short run (`cargo xtask test`) holds timeouts against the adapter only when the
//! host's timer floor kept within the watchdog: a CI machine whose own 1 ms loop stalls
//! past 32 ms cannot show a x32 watchdog holding. The long run always does.
//!
//! The board, the scanner's threads and the timer floor run under SCHED_FIFO priority
//! [`PRIORITY`], as a device on its own CPU and a dedicated originator would: on this shared
//! 2-core VM a plain thread's 1 ms sleep loop stalls for up to 200 ms when other work runs
//! (130 ms even at nice -15), and a stall of either side longer than 32 ms is a silent
//! originator or a deaf adapter, which a x32 watchdog rightly times out. Under SCHED_FIFO
//! the board's CPU time is much higher than at normal priority (about 90 % of a core against
//! some 5-15 %): it is measured as it is, for its constancy.

use std::io;
use std::process::Command;
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use crate::common::{self, REPLY};
use crate::fault_io::{board_real_time, SCANNER_PRIORITY};
use crate::faults::cm_counter;
use host_tests::faults::{count, long, pid_in, real_time_thread, report};
use host_tests::process::run_bounded;
use host_tests::rig::{Rig, BOARD_IP};
use host_tests::scanner::{exchange, open_generic, Session};
use host_tests::usage::{ticks_per_second, usage, Usage};

/// Connections, RPI and timeout multiplier code (3: x32).
const CONNECTIONS: usize = 10;
const RPI: Duration = Duration::from_millis(1);
const MULTIPLIER: u8 = 3;
/// SCHED_FIFO priority of the board, the scanner and the timer floor.
const PRIORITY: i32 = SCANNER_PRIORITY;
/// Resident memory the board may gain from the first period to the last, KiB.
const RSS_SLACK_KIB: u64 = 256;
/// How much more CPU the board may use in the last third of the periods than in the first.
/// A process's CPU time on this 2-core VM shared with other work swings with the load (4 s
/// periods measured 51-88 % on one run); a cost that grows with time shows as a steady rise,
/// which minute-long periods (long run) separate from that noise better than 2 s ones.
const CPU_GROWTH_LONG: f64 = 1.5;
const CPU_GROWTH_SHORT: f64 = 2.0;

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn faults_soak() {
    let seconds = count("ENIP_FAULTS_SOAK_SECONDS", 10, 600).max(2);
    let periods = if long() { (seconds / 60).max(2) } else { 5 };
    let period = Duration::from_secs(seconds) / periods as u32;
    let rig = Rig::start(&common::host_bin(), "generic", None).expect("rig");
    let pid = pid_in(rig.ns(), "enip-host").expect("board pid");
    board_real_time(&rig);
    let floor = std::thread::spawn(move || {
        let mut c = Command::new("chrt");
        c.args([
            "-f",
            &PRIORITY.to_string(),
            env!("CARGO_BIN_EXE_timer_baseline"),
        ])
        .arg(seconds.to_string());
        run_bounded(c, None, Duration::from_secs(seconds + 60))
    });
    let outcome = rig.ns().inside(|| -> io::Result<_> {
        // The I/O threads exchange() starts inherit it.
        real_time_thread(PRIORITY)?;
        let mut s = Session::connect(BOARD_IP, REPLY)?;
        let timeouts_before = cm_counter(&mut s, 8)?;
        let opened = open_generic(&mut s, CONNECTIONS, RPI.as_micros() as u32, MULTIPLIER)?;
        let duration = Duration::from_secs(seconds);
        let (record, samples) = std::thread::scope(|sc| {
            let sampler = sc.spawn(|| sample(pid, &mut s, periods, period, timeouts_before));
            let record = exchange(BOARD_IP, &opened, RPI, duration, |k| [k as u8; 32]);
            (record, sampler.join())
        });
        let record = record?;
        let samples = samples.map_err(|_| io::Error::other("sampler panicked"))??;
        let mut still_open = 0;
        for c in &opened {
            if s.forward_close(c.triad)?.general == 0 {
                still_open += 1;
            }
        }
        let timeouts = cm_counter(&mut s, 8)?.wrapping_sub(timeouts_before);
        Ok((record, samples, timeouts, still_open))
    });
    let (record, samples, timeouts, still_open) = outcome
        .expect("namespace")
        .unwrap_or_else(|e| panic!("{e}\n{}", rig.board_log()));
    let floor = floor
        .join()
        .expect("timer baseline thread")
        .expect("timer_baseline");
    let floor: Value = String::from_utf8_lossy(&floor.stdout)
        .lines()
        .rev()
        .find_map(|l| serde_json::from_str(l).ok())
        .expect("timer_baseline JSON");
    rig.finish().expect("the board ran to the end");

    let end_us = seconds * 1_000_000;
    let summary = record.summary(end_us, 100_000);
    let lost: u64 = summary.connections.iter().map(|c| c.lost).sum();
    let received: usize = summary.connections.iter().map(|c| c.received).sum();
    let worst = |f: fn(&host_tests::scanner::ConnectionStats) -> u64| {
        summary.connections.iter().map(f).max().unwrap_or(0)
    };
    let tps = ticks_per_second() as f64;
    let per_period: Vec<Value> = samples
        .windows(2)
        .map(|w| {
            let cpu = (w[1].0.cpu_ticks - w[0].0.cpu_ticks) as f64 / tps;
            json!({
                "cpu_percent": (cpu / period.as_secs_f64() * 1000.0).round() / 10.0,
                "rss_kib": w[1].0.rss_kib,
                "timeouts_so_far": w[1].1,
            })
        })
        .collect();
    let cpu = |i: usize| per_period[i]["cpu_percent"].as_f64().unwrap_or(0.0);
    let (first, last) = (0, per_period.len() - 1);
    let third = per_period.len().div_ceil(3);
    let mean_cpu = |r: std::ops::Range<usize>| r.clone().map(cpu).sum::<f64>() / r.len() as f64;
    let cpu_first = mean_cpu(0..third);
    let cpu_last = mean_cpu(per_period.len() - third..per_period.len());
    let growth = if long() {
        CPU_GROWTH_LONG
    } else {
        CPU_GROWTH_SHORT
    };
    let rss = |i: usize| per_period[i]["rss_kib"].as_u64().unwrap_or(0);
    report(
        "soak",
        json!({
            "seconds": seconds,
            "connections": CONNECTIONS,
            "rpi_us": RPI.as_micros() as u64,
            "multiplier": 32,
            "o_t_sent": record.sent,
            "t_o_received": received,
            "t_o_lost": lost,
            "connections_timed_out": timeouts,
            "connections_open_at_the_end": still_open,
            "t_o_p50_us_worst": worst(|c| c.p50_us),
            "t_o_p99_us_worst": worst(|c| c.p99_us),
            "t_o_max_us_worst": worst(|c| c.max_us),
            "host_timer_floor": floor,
            "sched_fifo_priority": PRIORITY,
            "period_seconds": period.as_secs_f64(),
            "board_per_period": per_period,
            "board_cpu_percent_first_third": (cpu_first * 10.0).round() / 10.0,
            "board_cpu_percent_last_third": (cpu_last * 10.0).round() / 10.0,
            "board_rss_kib_first_last": [rss(first), rss(last)],
        }),
    );
    assert_eq!(summary.connections.len(), CONNECTIONS, "{summary:?}");
    assert_eq!(lost, 0, "T->O lost");
    let watchdog_us = RPI.as_micros() as u64 * 32;
    let floor_max_us = floor["max_us"].as_u64().unwrap_or(0);
    if !long() && floor_max_us > watchdog_us && timeouts > 0 {
        // The host's own 1 ms timer, beside the adapter at the same priority, stalled
        // longer than the watchdog: on this run the host, not the adapter, decided whether
        // the connections outlived it. What still must hold is that every connection that
        // timed out was closed and counted once.
        eprintln!(
            "soak: the host's timer floor stalled {floor_max_us} us (watchdog {watchdog_us} \
             us): {timeouts} timeouts not held against the adapter on this run"
        );
        assert_eq!(
            usize::from(timeouts) + still_open,
            CONNECTIONS,
            "connections neither open nor counted as timed out"
        );
    } else {
        assert_eq!(
            (timeouts, summary.timeouts, still_open),
            (0, 0, CONNECTIONS),
            "spurious timeouts (the host's timer floor stalled at most {floor_max_us} us)"
        );
    }
    assert!(
        rss(last) <= rss(first) + RSS_SLACK_KIB,
        "board memory grew from {} to {} KiB",
        rss(first),
        rss(last)
    );
    assert!(
        cpu_last <= cpu_first * growth + 2.0,
        "board CPU grew from {cpu_first:.1} % to {cpu_last:.1} % (first and last third)"
    );
}

/// The board's usage at the start and after each of `periods` periods, with the Connection
/// Manager's timeout count since `timeouts_before` read on `s` each time (which also keeps
/// the session from idling out).
fn sample(
    pid: u32,
    s: &mut Session,
    periods: u64,
    period: Duration,
    timeouts_before: u16,
) -> io::Result<Vec<(Usage, u16)>> {
    let start = Instant::now();
    let mut samples = vec![(usage(pid)?, 0)];
    for i in 1..=periods {
        if let Some(wait) = (start + period * i as u32).checked_duration_since(Instant::now()) {
            std::thread::sleep(wait);
        }
        let timeouts = cm_counter(s, 8)?.wrapping_sub(timeouts_before);
        samples.push((usage(pid)?, timeouts));
    }
    Ok(samples)
}
