//! The QEMU smoke run of `cargo xtask test`: the emulated board in a namespace, checked by
//! peers nobody here wrote and by the project's scanner.
//!
//! 1. pycomm3 reads the Identity object and finds the board with a ListIdentity broadcast
//!    to the subnet;
//! 2. the PyPI `ethernetip` package runs an exclusive-owner Class 1 connection (input 100,
//!    output 150, config 151) at a 10 ms RPI for 10 s: it must open, see its output echoed,
//!    and close cleanly (a connection that timed out is gone and cannot be closed), and the
//!    board must log no timeout;
//! 3. the scanner runs one connection at a 1 ms RPI for 10 s; its figures (packets sent and
//!    received, intervals) are reported as measured under emulation; the connection must
//!    stay up (with a watchdog wide enough for QEMU's scheduling stalls) and at least half
//!    the packets must arrive.
//!
//! Figures go to `target/qemu-smoke/report.json`, the board's log next to it.

use std::fs;
use std::io::Write;
use std::path::Path;
use std::process::Stdio;

use crate::boards;
use crate::json;
use crate::netns::{Lab, BOARD_IP};
use crate::qemu::{self, Qemu};
use crate::setup;
use crate::util::{self, err, loud, run, Outcome, Result};

/// The subnet broadcast address of the lab.
const BROADCAST: &str = "198.18.0.255";
/// The `ethernetip` peer script (written for the host TAP interop tests, reused here).
const ETHERNETIP_PEER: &str = "host-tests/peers/ethernetip_class1.py";
/// The explicit-messaging part, run with the peers' Python.
const EXPLICIT: &str = concat!(
    include_str!("../scripts/identity.py"),
    include_str!("../scripts/explicit_smoke.py")
);
/// Class 1 with `ethernetip`: RPI in ms and duration in s.
const ETHERNETIP_RPI_MS: u32 = 10;
const ETHERNETIP_SECONDS: u32 = 10;
/// The scanner's run: RPI in µs and duration in s.
const SCANNER_RPI_US: u32 = 1_000;
const SCANNER_SECONDS: u32 = 10;
/// Its timeout multiplier code: 5 is x128, a 128 ms watchdog at 1 ms. An emulated board on a
/// shared host can stall for tens of milliseconds when QEMU is not scheduled; that is the
/// host, not the stack, and the figures show it.
const SCANNER_MULTIPLIER: &str = "5";
/// Of the T->O packets a 1 ms RPI should bring, the share the run must see (percent).
const SCANNER_MIN_RECEIVED_PERCENT: u64 = 50;
/// Extra seconds a peer may take beyond its run before it is killed.
const PEER_SLACK_SECONDS: u32 = 30;

/// Runs the smoke run (skipped, loudly, without root).
pub fn run_smoke() -> Result<Outcome> {
    if !util::is_root() {
        loud("QEMU smoke run: SKIPPED: network namespaces need root");
        return Ok(Outcome::Skipped);
    }
    qemu::ensure_installed()?;
    setup::python_peers()?;
    let elf = boards::build(boards::QEMU, boards::DEFAULT_PROFILE)?;
    run(util::cargo().args(["build", "--release", "-p", "host-tests", "--bin", "scanner"]))?;
    let dir = util::target_dir().join("qemu-smoke");
    fs::create_dir_all(&dir)?;
    let lab = Lab::create("enip-smoke", "enipsmoke0")?;
    let mut board = Qemu::boot(&lab, &elf, &dir.join("board.log"))?;
    let result = checks(&lab, &mut board, &dir);
    if result.is_err() {
        board.print_log_tail(30);
    }
    result.map(|()| Outcome::Passed)
}

fn checks(lab: &Lab, board: &mut Qemu, dir: &Path) -> Result {
    let explicit = explicit(lab)?;
    board.check_alive()?;
    let log_before = board.log_text().len();
    let class1 = ethernetip(lab)?;
    board.check_alive()?;
    if board.log_text()[log_before..].contains("timed out") {
        return err("the board logged a connection timeout during the ethernetip run");
    }
    let scanner = scanner(lab, dir)?;
    board.check_alive()?;
    let report =
        format!("{{\"explicit\":{explicit},\"ethernetip\":{class1},\"scanner_1ms\":{scanner}}}");
    let path = dir.join("report.json");
    fs::write(&path, report)?;
    println!("QEMU smoke: report in {}", path.display());
    Ok(())
}

/// pycomm3: Identity attributes 1-7 and a broadcast ListIdentity; returns its JSON.
fn explicit(lab: &Lab) -> Result<String> {
    let python = setup::venv_python();
    let out = peer(
        lab,
        &python.to_string_lossy(),
        &["-c", EXPLICIT, BOARD_IP, BROADCAST],
        None,
        60,
    )?;
    let name = json::string(&out, "product_name").unwrap_or_default();
    println!("pycomm3: Identity of {BOARD_IP}: {out}");
    if name.is_empty() {
        return err("pycomm3 read no product name");
    }
    if !out.contains(&format!("\"ip_address\": \"{BOARD_IP}\"")) {
        return err(format!(
            "the ListIdentity broadcast to {BROADCAST} found no {BOARD_IP}"
        ));
    }
    println!("pycomm3: ListIdentity to {BROADCAST} answered by {BOARD_IP} ({name})");
    Ok(out)
}

/// `ethernetip`: exclusive owner at 10 ms for 10 s; returns its JSON.
fn ethernetip(lab: &Lab) -> Result<String> {
    let script = util::root().join(ETHERNETIP_PEER);
    let python = setup::venv_python();
    let request = format!(
        "{{\"host\": \"{BOARD_IP}\", \"rpi_ms\": {ETHERNETIP_RPI_MS}, \"seconds\": {ETHERNETIP_SECONDS}, \"multicast\": false}}"
    );
    let out = peer(
        lab,
        &python.to_string_lossy(),
        &[&script.to_string_lossy()],
        Some(&request),
        ETHERNETIP_SECONDS + PEER_SLACK_SECONDS,
    )?;
    println!(
        "ethernetip: exclusive owner 100/150/151 at {ETHERNETIP_RPI_MS} ms for {ETHERNETIP_SECONDS} s: {out}"
    );
    let zero = |k| json::number(&out, k) == Some(0);
    if !(zero("forward_open") && zero("forward_close") && zero("reopen")) {
        return err("ethernetip: Forward_Open, Forward_Close or the reopen failed");
    }
    if json::find(&out, "echoed") != Some(serde_json::Value::Bool(true)) {
        return err("ethernetip: its output data never came back in the input");
    }
    Ok(out)
}

/// The scanner: one connection at 1 ms for 10 s; returns its JSON.
fn scanner(lab: &Lab, dir: &Path) -> Result<String> {
    let json_path = dir.join("scanner-1ms.json");
    let out = run_scanner(
        lab,
        1,
        SCANNER_RPI_US,
        SCANNER_SECONDS,
        SCANNER_MULTIPLIER,
        &json_path,
    )?;
    println!(
        "scanner at {SCANNER_RPI_US} us under emulation: {}",
        json::scanner_figures(&out)
    );
    let n = |k| json::number(&out, k).unwrap_or(0);
    if n("timeouts") != 0 {
        return err("the scanner's 1 ms connection did not stay up");
    }
    if n("received") * 100 < n("expected_per_connection") * SCANNER_MIN_RECEIVED_PERCENT {
        return err(format!(
            "the scanner received under {SCANNER_MIN_RECEIVED_PERCENT}% of the T->O packets"
        ));
    }
    Ok(out)
}

/// Runs the project's scanner (release build) inside the lab against the board: `connections`
/// at `rpi_us` for `seconds`, watchdog `multiplier` code; prints its table and returns the
/// JSON report it wrote to `json`.
pub(crate) fn run_scanner(
    lab: &Lab,
    connections: u32,
    rpi_us: u32,
    seconds: u32,
    multiplier: &str,
    json: &Path,
) -> Result<String> {
    let bin = util::target_dir().join("release/scanner");
    let args = [
        "--target".to_string(),
        BOARD_IP.to_string(),
        "--connections".into(),
        connections.to_string(),
        "--rpi-us".into(),
        rpi_us.to_string(),
        "--seconds".into(),
        seconds.to_string(),
        "--multiplier".into(),
        multiplier.into(),
        "--json".into(),
        json.to_string_lossy().into_owned(),
    ];
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let table = peer(
        lab,
        &bin.to_string_lossy(),
        &args,
        None,
        seconds + PEER_SLACK_SECONDS,
    )?;
    print!("{table}");
    Ok(fs::read_to_string(json)?)
}

/// Runs `program args` inside the lab, killed after `seconds`, with `input` on its standard
/// input; returns its standard output (failing if it fails).
fn peer(
    lab: &Lab,
    program: &str,
    args: &[&str],
    input: Option<&str>,
    seconds: u32,
) -> Result<String> {
    let mut cmd = lab.command("timeout");
    cmd.arg(seconds.to_string())
        .arg(program)
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit());
    let mut child = cmd.spawn()?;
    if let Some(mut stdin) = child.stdin.take() {
        stdin.write_all(input.unwrap_or("").as_bytes())?;
    }
    let out = child.wait_with_output()?;
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    if !out.status.success() {
        return err(format!("{program} failed ({}): {stdout}", out.status));
    }
    Ok(stdout)
}
