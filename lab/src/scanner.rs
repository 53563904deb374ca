//! The project's scanner (`host-tests/src/bin/scanner.rs`) run against the board of a
//! namespace: its options, a run bounded in time, and the JSON report it writes.

use std::io;
use std::path::Path;
use std::time::Duration;

use serde_json::Value;

use crate::netns::{Namespace, BOARD_IP};
use crate::process::run_bounded;

/// Seconds a run may take beyond its own length (start-up, Forward_Opens and closes).
const SLACK_SECONDS: u32 = 60;

/// One run of the scanner.
#[derive(Debug, Clone, Copy)]
pub struct ScannerRun<'a> {
    /// The scanner binary (the release build for 1 ms timing).
    pub bin: &'a Path,
    /// Connections to open (one exclusive owner, the others input-only).
    pub connections: u32,
    /// Their RPI, µs.
    pub rpi_us: u32,
    /// How long to run them, s.
    pub seconds: u32,
    /// The watchdog's timeout multiplier code (0-7).
    pub multiplier: &'a str,
    /// Where the scanner writes its JSON report.
    pub json: &'a Path,
}

/// Runs `run` inside `ns` against the board at [`BOARD_IP`]; returns the table the scanner
/// printed and its report. Fails if the scanner fails or writes no report.
pub fn run(ns: &Namespace, run: &ScannerRun<'_>) -> io::Result<(String, Value)> {
    run_with(ns, run, &[])
}

/// [`run`] with `extra` arguments for the scanner, e.g. `["--trigger", "cos"]`.
pub fn run_with(
    ns: &Namespace,
    run: &ScannerRun<'_>,
    extra: &[&str],
) -> io::Result<(String, Value)> {
    let mut cmd = ns.command(run.bin);
    cmd.args(extra);
    cmd.args(["--target", &BOARD_IP.to_string()])
        .args(["--connections", &run.connections.to_string()])
        .args(["--rpi-us", &run.rpi_us.to_string()])
        .args(["--seconds", &run.seconds.to_string()])
        .args(["--multiplier", run.multiplier, "--json"])
        .arg(run.json);
    let timeout = Duration::from_secs(u64::from(run.seconds + SLACK_SECONDS));
    let out = run_bounded(cmd, None, timeout)?;
    let table = String::from_utf8_lossy(&out.stdout).into_owned();
    if !out.status.success() {
        return Err(io::Error::other(format!(
            "the scanner failed ({}): {}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        )));
    }
    let text = std::fs::read_to_string(run.json)
        .map_err(|e| io::Error::other(format!("{}: {e}", run.json.display())))?;
    let report = serde_json::from_str(&text)
        .map_err(|e| io::Error::other(format!("{}: {e}", run.json.display())))?;
    Ok((table, report))
}
