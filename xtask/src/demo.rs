//! `cargo xtask demo`: the emulated board (QEMU mps2-an386, or with `--host` the Linux host
//! board) in a private network namespace, its identity, and a live view of Class 1 I/O.
//!
//! Layout: namespace `enip-demo` holds TAP `enipdemo0` with 198.18.0.1/24 (the scanners'
//! side); the board is 198.18.0.2/24 on it. The demo shows:
//!
//! 1. the Identity object, read by pycomm3;
//! 2. Class 1 data: an `ethernetip` exclusive owner changes its output once a second and
//!    prints the input the board produces (the generic profile echoes it);
//! 3. Class 1 timing: the project's `scanner` CLI, one connection per second-long round,
//!    printing packets sent and received and the T->O intervals of each round.
//!
//! Nothing leaves the namespace; everything is torn down on success, failure and Ctrl-C,
//! and the whole demo is bounded in time.

use std::fs;
use std::process::{Command, Stdio};
use std::thread::sleep;
use std::time::{Duration, Instant};

use enip_lab::peers;
use enip_lab::rig::{self, Options, Rig, BOARD_CIDR, BOARD_IP};

use crate::boards;
use crate::qemu;
use crate::setup;
use crate::util::{self, err, interrupted, run, Result};

/// Which board the demo runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Board {
    /// The emulated Cortex-M (the default).
    Qemu,
    /// The Linux host board.
    Host,
}

/// The device profile the board runs.
const PROFILE: &str = "generic";
/// The demo's namespace and TAP.
const NAMESPACE: &str = "enip-demo";
const TAP: &str = "enipdemo0";
/// Live data: RPI in ms and seconds.
const DATA_RPI_MS: u32 = 10;
const DATA_SECONDS: u32 = 5;
/// Live timing: rounds of the scanner, each one connection for one second at this RPI.
const TIMING_ROUNDS: u32 = 5;
const TIMING_RPI_US: u32 = 2_000;
/// The longest any one scanner step may take.
const STEP_TIMEOUT: Duration = Duration::from_secs(60);
/// Lines of the board's log shown when the demo fails.
const LOG_TAIL: usize = 30;

/// Runs the demo; the namespace and every child are gone when it returns.
pub fn run_demo(board: Board) -> Result {
    qemu::require_root("demo")?;
    util::catch_interrupts();
    if !util::have("ip") {
        setup::apt_install(&["iproute2"])?;
    }
    setup::python_peers()?;
    let log_dir = util::target_dir().join("demo");
    fs::create_dir_all(&log_dir)?;
    let (image, log) = match board {
        Board::Qemu => {
            setup::rust_target()?;
            qemu::ensure_installed()?;
            let elf = boards::build(boards::QEMU, PROFILE)?;
            (elf, log_dir.join("board.log"))
        }
        Board::Host => {
            run(util::cargo().args(["build", "-p", "enip-host"]))?;
            let bin = util::target_dir().join("debug/enip-host");
            (bin, log_dir.join("enip-host.log"))
        }
    };
    run(util::cargo().args(["build", "--release", "-p", "host-tests", "--bin", "scanner"]))?;

    let launched = match board {
        Board::Qemu => rig::Board::Qemu {
            elf: &image,
            extra: &[],
        },
        Board::Host => rig::Board::Host {
            bin: &image,
            profile: PROFILE,
            extra: &[],
            answers_at: BOARD_IP,
        },
    };
    println!(
        "demo: starting {} (log: {})",
        image.display(),
        log.display()
    );
    let mut rig = Rig::launch(launched, &Options::named(NAMESPACE, TAP, &log))?;
    println!("demo: the board runs profile {PROFILE} at {BOARD_CIDR} in namespace {NAMESPACE}\n");
    let result = show(&mut rig);
    if result.is_err() {
        qemu::print_log_tail(&rig, &log, LOG_TAIL);
    }
    drop(rig);
    println!("demo: torn down (board stopped, namespace {NAMESPACE} deleted)");
    result
}

/// The three parts of the demo, each watched for Ctrl-C and the board's health.
fn show(rig: &mut Rig) -> Result {
    let python = peers::venv_python();
    let board = BOARD_IP.to_string();
    let mut identity = rig.ns().command(&python);
    identity.arg(peers::script("demo_identity.py")).arg(&board);
    supervise(&mut identity, rig)?;
    println!();
    let mut live = rig.ns().command(&python);
    live.arg(peers::script("demo_live_data.py")).args([
        board.clone(),
        DATA_RPI_MS.to_string(),
        DATA_SECONDS.to_string(),
    ]);
    supervise(&mut live, rig)?;
    println!(
        "\nClass 1 timing (the project's scanner, one connection per 1 s round, RPI {} ms):",
        f64::from(TIMING_RPI_US) / 1000.0
    );
    let scanner = util::target_dir().join("release/scanner");
    let json_path = util::target_dir().join("demo/scanner.json");
    for round in 1..=TIMING_ROUNDS {
        let mut cmd = rig.ns().command(&scanner);
        cmd.args(["--target", &board, "--connections", "1"])
            .args(["--rpi-us", &TIMING_RPI_US.to_string(), "--seconds", "1"])
            .arg("--json")
            .arg(&json_path)
            .stdout(Stdio::null())
            .stderr(Stdio::null());
        supervise(&mut cmd, rig)?;
        let report = serde_json::from_str(&fs::read_to_string(&json_path)?)
            .map_err(|e| util::Error(format!("{}: {e}", json_path.display())))?;
        println!("  round {round}: {}", peers::scanner_figures(&report));
    }
    Ok(())
}

/// Runs `cmd` to completion, bounded in time, while the board stays up; Ctrl-C stops it.
fn supervise(cmd: &mut Command, rig: &mut Rig) -> Result {
    let mut child = cmd.stdin(Stdio::null()).spawn()?;
    let start = Instant::now();
    let result = loop {
        if let Some(status) = child.try_wait()? {
            break if status.success() {
                Ok(())
            } else {
                err(format!("`{}` failed ({status})", util::show(cmd)))
            };
        }
        if let Err(e) = rig.check_alive() {
            break Err(e.into());
        }
        if interrupted() {
            break err("interrupted");
        }
        if start.elapsed() > STEP_TIMEOUT {
            break err(format!(
                "`{}` still running after {STEP_TIMEOUT:?}",
                util::show(cmd)
            ));
        }
        sleep(Duration::from_millis(50));
    };
    if child.try_wait().ok().flatten().is_none() {
        let _ = child.kill();
        let _ = child.wait();
    }
    result
}
