//! The QEMU smoke run (`cargo xtask smoke`, and the last step of `cargo xtask test`): the
//! emulated board in a namespace of its own, checked by peers nobody here wrote and by the
//! project's scanner.
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
//! Figures go to `target/qemu-smoke/report.json`, the board's log next to it; run with
//! `--nocapture` to see them. Needs root, `qemu-system-arm`, the Python peers
//! (`ENIP_PEER_PYTHON`), `ENIP_QEMU_GENERIC_ELF` (an `enip-qemu-mps2` ELF with the generic
//! profile) and `ENIP_SCANNER_BIN` (the scanner, built in release for the 1 ms timing; else
//! the one built with this test):
//!
//! ```text
//! cargo xtask smoke
//! ```

use std::path::Path;
use std::time::Duration;

use enip_lab::scanner::{self as scanner_run, ScannerRun};
use host_tests::netns::{BOARD_IP, BROADCAST_IP};
use host_tests::paths;
use host_tests::peers;
use host_tests::rig::{Board, Options, Rig};
use serde_json::{json, Value};

/// Class 1 with `ethernetip`: RPI in ms and duration in s.
const ETHERNETIP_RPI_MS: u32 = 10;
const ETHERNETIP_SECONDS: u64 = 10;
/// The scanner's run: RPI in µs and duration in s.
const SCANNER_RPI_US: u32 = 1_000;
const SCANNER_SECONDS: u32 = 10;
/// Its timeout multiplier code: 5 is x128, a 128 ms watchdog at 1 ms. An emulated board on a
/// shared host can stall for tens of milliseconds when QEMU is not scheduled; that is the
/// host, not the stack, and the figures show it.
const SCANNER_MULTIPLIER: &str = "5";
/// Of the T->O packets a 1 ms RPI should bring, the share the run must see (percent).
const SCANNER_MIN_RECEIVED_PERCENT: u64 = 50;
/// Seconds the explicit part may take.
const EXPLICIT_SECONDS: u64 = 60;
/// Extra seconds a peer may take beyond its run before it is killed.
const PEER_SLACK_SECONDS: u64 = 30;
/// Lines of the board's log shown when a check fails.
const LOG_TAIL: usize = 30;

/// What a failed check says.
type Checked<T> = Result<T, String>;

#[test]
#[ignore = "needs root, QEMU, the Python peers and ENIP_QEMU_GENERIC_ELF"]
fn qemu_smoke() {
    let Some(elf) = host_tests::rig::qemu_elf("generic") else {
        return;
    };
    let dir = paths::target_dir().join("qemu-smoke");
    std::fs::create_dir_all(&dir).expect("create the report directory");
    let log = dir.join("board.log");
    let board = Board::Qemu {
        elf: &elf,
        extra: &[],
    };
    let mut rig = Rig::launch(board, &Options::logged("enipsmoke0", &log))
        .unwrap_or_else(|e| panic!("boot {}: {e}", elf.display()));
    if let Err(e) = checks(&mut rig, &dir) {
        panic!(
            "{e}\n--- last lines of {} ---\n{}",
            log.display(),
            rig.board_log_tail(LOG_TAIL)
        );
    }
    rig.finish().unwrap_or_else(|e| panic!("{e}"));
}

fn checks(rig: &mut Rig, dir: &Path) -> Checked<()> {
    let explicit = explicit(rig)?;
    alive(rig)?;
    let log_before = rig.board_log().len();
    let class1 = ethernetip(rig)?;
    alive(rig)?;
    if rig
        .board_log()
        .get(log_before..)
        .unwrap_or_default()
        .contains("timed out")
    {
        return Err("the board logged a connection timeout during the ethernetip run".into());
    }
    let scanner = scanner(rig, dir)?;
    alive(rig)?;
    let report = json!({"explicit": explicit, "ethernetip": class1, "scanner_1ms": scanner});
    let path = dir.join("report.json");
    std::fs::write(&path, report.to_string()).map_err(|e| format!("{}: {e}", path.display()))?;
    println!("QEMU smoke: report in {}", path.display());
    Ok(())
}

fn alive(rig: &mut Rig) -> Checked<()> {
    rig.check_alive().map_err(|e| e.to_string())
}

/// pycomm3: Identity attributes 1-7 and a broadcast ListIdentity; returns its report.
fn explicit(rig: &Rig) -> Checked<Value> {
    let (board, broadcast) = (BOARD_IP.to_string(), BROADCAST_IP.to_string());
    let out = peers::run_with_args(
        rig.ns(),
        "smoke_explicit.py",
        &[&board, &broadcast],
        Duration::from_secs(EXPLICIT_SECONDS),
    )
    .map_err(|e| e.to_string())?;
    println!("pycomm3: Identity of {BOARD_IP}: {out}");
    let name = out["identity"]["product_name"].as_str().unwrap_or_default();
    if name.is_empty() {
        return Err("pycomm3 read no product name".into());
    }
    let found = out["discovered"]
        .as_array()
        .is_some_and(|d| d.iter().any(|d| d["ip_address"] == board.as_str()));
    if !found {
        return Err(format!(
            "the ListIdentity broadcast to {BROADCAST_IP} found no {BOARD_IP}"
        ));
    }
    println!("pycomm3: ListIdentity to {BROADCAST_IP} answered by {BOARD_IP} ({name})");
    Ok(out)
}

/// `ethernetip`: exclusive owner at 10 ms for 10 s; returns its report.
fn ethernetip(rig: &Rig) -> Checked<Value> {
    let request = json!({
        "host": BOARD_IP.to_string(),
        "rpi_ms": ETHERNETIP_RPI_MS,
        "seconds": ETHERNETIP_SECONDS,
        "multicast": false,
    });
    let timeout = Duration::from_secs(ETHERNETIP_SECONDS + PEER_SLACK_SECONDS);
    let out = peers::run(rig.ns(), "ethernetip_class1.py", &request, timeout)
        .map_err(|e| e.to_string())?;
    println!(
        "ethernetip: exclusive owner 100/150/151 at {ETHERNETIP_RPI_MS} ms for {ETHERNETIP_SECONDS} s: {out}"
    );
    if ["forward_open", "forward_close", "reopen"]
        .iter()
        .any(|k| out[k] != 0)
    {
        return Err("ethernetip: Forward_Open, Forward_Close or the reopen failed".into());
    }
    if out["echoed"] != true {
        return Err("ethernetip: its output data never came back in the input".into());
    }
    Ok(out)
}

/// The scanner: one connection at 1 ms for 10 s; returns its report.
fn scanner(rig: &Rig, dir: &Path) -> Checked<Value> {
    let bin = std::env::var_os("ENIP_SCANNER_BIN")
        .map(|b| paths::root().join(b))
        .unwrap_or_else(|| env!("CARGO_BIN_EXE_scanner").into());
    let json_path = dir.join("scanner-1ms.json");
    let run = ScannerRun {
        bin: &bin,
        connections: 1,
        rpi_us: SCANNER_RPI_US,
        seconds: SCANNER_SECONDS,
        multiplier: SCANNER_MULTIPLIER,
        json: &json_path,
    };
    let (table, report) = scanner_run::run(rig.ns(), &run).map_err(|e| format!("scanner: {e}"))?;
    print!("{table}");
    println!(
        "scanner at {SCANNER_RPI_US} us under emulation: {}",
        peers::scanner_figures(&report)
    );
    let n = |k: &str| report[k].as_u64().unwrap_or(0);
    let received = report["connections"][0]["received"].as_u64().unwrap_or(0);
    if n("timeouts") != 0 {
        return Err("the scanner's 1 ms connection did not stay up".into());
    }
    if received * 100 < n("expected_per_connection") * SCANNER_MIN_RECEIVED_PERCENT {
        return Err(format!(
            "the scanner received under {SCANNER_MIN_RECEIVED_PERCENT}% of the T->O packets"
        ));
    }
    Ok(report)
}
