//! What the fault tests (issue 13) share: short or long runs chosen by environment variables,
//! and the one-line figures report `cargo xtask faults` collects (the board's CPU time and
//! resident memory are the lab's [`crate::usage`]).
//!
//! `ENIP_FAULTS_LONG=1` selects the long versions; single figures can be overridden by their
//! own variables (e.g. `ENIP_FAULTS_CHURN_CYCLES`), see each test.

use std::io;
use std::process::Command;
use std::time::Duration;

use crate::netns::Namespace;
use crate::process::run_bounded;

/// Prefix of a figures line on a test's standard output: `FAULT-REPORT {json}`.
pub const REPORT_PREFIX: &str = "FAULT-REPORT ";

/// True when the long versions are asked for (`ENIP_FAULTS_LONG=1`).
pub fn long() -> bool {
    std::env::var("ENIP_FAULTS_LONG").is_ok_and(|v| v == "1")
}

/// The number in environment variable `name`, else `long_value` in a long run and
/// `short_value` otherwise.
pub fn count(name: &str, short_value: u64, long_value: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(if long() { long_value } else { short_value })
}

/// Prints `figures` (a JSON object) for scenario `name` as one `FAULT-REPORT` line, with the
/// run's kind (`short` or `long`) added.
pub fn report(name: &str, mut figures: serde_json::Value) {
    if let Some(o) = figures.as_object_mut() {
        o.insert("scenario".into(), name.into());
        o.insert("run".into(), if long() { "long" } else { "short" }.into());
    }
    println!("{REPORT_PREFIX}{figures}");
}

/// The largest of number figure `key` over `rounds` (`None` if no round has it).
pub fn most(rounds: &[serde_json::Value], key: &str) -> Option<f64> {
    rounds
        .iter()
        .filter_map(|r| r[key].as_f64())
        .reduce(f64::max)
}

/// The smallest of number figure `key` over `rounds` (`None` if no round has it).
pub fn least(rounds: &[serde_json::Value], key: &str) -> Option<f64> {
    rounds
        .iter()
        .filter_map(|r| r[key].as_f64())
        .reduce(f64::min)
}

/// Milliseconds of `d`, rounded to 0.1 ms, for reports.
pub fn ms(d: Duration) -> f64 {
    (d.as_secs_f64() * 1e4).round() / 10.0
}

/// The process id of the program `comm` (its first 15 bytes, as `/proc/PID/comm` has it)
/// running inside `ns`.
pub fn pid_in(ns: &Namespace, comm: &str) -> io::Result<u32> {
    let mut c = Command::new("ip");
    c.args(["netns", "pids", ns.name()]);
    let out = run_bounded(c, None, Duration::from_secs(10))?;
    let short: String = comm.chars().take(15).collect();
    String::from_utf8_lossy(&out.stdout)
        .split_whitespace()
        .filter_map(|p| p.parse::<u32>().ok())
        .find(|pid| {
            std::fs::read_to_string(format!("/proc/{pid}/comm")).is_ok_and(|c| c.trim() == short)
        })
        .ok_or_else(|| io::Error::other(format!("no {comm} in namespace {}", ns.name())))
}

/// Puts the calling thread under the real-time policy SCHED_FIFO at `priority` (threads it
/// creates afterwards inherit it).
pub fn real_time_thread(priority: i32) -> io::Result<()> {
    set_fifo(rustix::thread::gettid().as_raw_nonzero().get(), priority)
}

/// Puts every thread of process `pid` under SCHED_FIFO at `priority`.
pub fn real_time_process(pid: u32, priority: i32) -> io::Result<()> {
    for tid in threads(pid)? {
        set_fifo(tid, priority)?;
    }
    Ok(())
}

/// Gives every thread of process `pid` the highest normal (not real-time) priority, nice
/// -20: it then takes all but a few per cent of a core others want too, in slices of a few
/// milliseconds. A SCHED_FIFO process that saturates its core is instead stopped for some
/// 50 ms once a second while the kernel runs the normal tasks it starved (its fair server,
/// Linux 6.12 on; before, RT throttling), longer than a 1 ms x32 connection's timeout.
pub fn high_priority_process(pid: u32) -> io::Result<()> {
    for tid in threads(pid)? {
        let status = std::process::Command::new("renice")
            .args(["-n", "-20", "-p", &tid.to_string()])
            .stdout(std::process::Stdio::null())
            .status()?;
        if !status.success() {
            return Err(io::Error::other(format!("renice -20 {tid}: {status}")));
        }
    }
    Ok(())
}

/// The thread IDs of process `pid`.
fn threads(pid: u32) -> io::Result<Vec<u32>> {
    let mut tids = Vec::new();
    for task in std::fs::read_dir(format!("/proc/{pid}/task"))? {
        if let Some(tid) = task?
            .file_name()
            .to_str()
            .and_then(|t| t.parse::<u32>().ok())
        {
            tids.push(tid);
        }
    }
    Ok(tids)
}

/// SCHED_FIFO at `priority` for thread `tid`, set by util-linux's `chrt`.
fn set_fifo(tid: impl std::fmt::Display, priority: i32) -> io::Result<()> {
    let status = std::process::Command::new("chrt")
        .args(["--fifo", "--pid", &priority.to_string(), &tid.to_string()])
        .status()?;
    if !status.success() {
        return Err(io::Error::other(format!("chrt --fifo {tid}: {status}")));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn most_and_least_of_rounds() {
        let rounds = [
            serde_json::json!({"a": 2.5}),
            serde_json::json!({"a": -1}),
            serde_json::json!({}),
        ];
        assert_eq!(most(&rounds, "a"), Some(2.5));
        assert_eq!(least(&rounds, "a"), Some(-1.0));
        assert_eq!(most(&rounds, "b"), None);
    }
}
