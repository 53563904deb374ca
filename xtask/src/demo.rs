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
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::thread::sleep;
use std::time::{Duration, Instant};

use crate::boards;
use crate::json;
use crate::netns::{Lab, BOARD_CIDR, BOARD_IP};
use crate::qemu::{self, Qemu};
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
/// The pycomm3 identity reader.
const IDENTITY: &str = concat!(
    include_str!("../scripts/identity.py"),
    include_str!("../scripts/demo_identity.py")
);
/// The `ethernetip` live data view.
const LIVE_DATA: &str = include_str!("../scripts/demo_live_data.py");
/// Live data: RPI in ms and seconds.
const DATA_RPI_MS: u32 = 10;
const DATA_SECONDS: u32 = 5;
/// Live timing: rounds of the scanner, each one connection for one second at this RPI.
const TIMING_ROUNDS: u32 = 5;
const TIMING_RPI_US: u32 = 2_000;
/// The longest any one scanner step may take.
const STEP_TIMEOUT: Duration = Duration::from_secs(60);
/// The longest the host board may take to listen.
const HOST_BOOT_TIMEOUT: Duration = Duration::from_secs(15);

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
    let image = match board {
        Board::Qemu => {
            setup::rust_target()?;
            qemu::ensure_installed()?;
            boards::build(boards::QEMU, PROFILE)?
        }
        Board::Host => {
            run(util::cargo().args(["build", "-p", "enip-host"]))?;
            util::target_dir().join("debug/enip-host")
        }
    };
    run(util::cargo().args(["build", "--release", "-p", "host-tests", "--bin", "scanner"]))?;

    let lab = Lab::create("enip-demo", "enipdemo0")?;
    let mut running = match board {
        Board::Qemu => Running::Qemu(Qemu::boot(&lab, &image, &log_dir.join("board.log"))?),
        Board::Host => Running::Host(HostBoard::start(
            &lab,
            &image,
            &log_dir.join("enip-host.log"),
        )?),
    };
    println!(
        "demo: the board runs profile {PROFILE} at {BOARD_CIDR} in namespace {}\n",
        lab.name
    );
    let result = show(&lab, &mut running);
    if result.is_err() {
        running.print_log_tail();
    }
    drop(running);
    drop(lab);
    println!("demo: torn down (board stopped, namespace enip-demo deleted)");
    result
}

/// The three parts of the demo, each watched for Ctrl-C and the board's health.
fn show(lab: &Lab, board: &mut Running) -> Result {
    let python = setup::venv_python();
    let python = python.to_string_lossy();
    supervise(lab.command(&python).args(["-c", IDENTITY, BOARD_IP]), board)?;
    println!();
    supervise(
        lab.command(&python).args([
            "-c",
            LIVE_DATA,
            BOARD_IP,
            &DATA_RPI_MS.to_string(),
            &DATA_SECONDS.to_string(),
        ]),
        board,
    )?;
    println!(
        "\nClass 1 timing (the project's scanner, one connection per 1 s round, RPI {} ms):",
        f64::from(TIMING_RPI_US) / 1000.0
    );
    let scanner = util::target_dir().join("release/scanner");
    let json_path = util::target_dir().join("demo/scanner.json");
    for round in 1..=TIMING_ROUNDS {
        let mut cmd = lab.command(&scanner.to_string_lossy());
        cmd.args(["--target", BOARD_IP, "--connections", "1"])
            .args(["--rpi-us", &TIMING_RPI_US.to_string(), "--seconds", "1"])
            .args(["--json", &json_path.to_string_lossy()])
            .stdout(Stdio::null())
            .stderr(Stdio::null());
        supervise(&mut cmd, board)?;
        let out = fs::read_to_string(&json_path)?;
        println!("  round {round}: {}", json::scanner_figures(&out));
    }
    Ok(())
}

/// Runs `cmd` to completion, bounded in time, while the board stays up; Ctrl-C stops it.
fn supervise(cmd: &mut Command, board: &mut Running) -> Result {
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
        if let Err(e) = board.check_alive() {
            break Err(e);
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

/// The board the demo started.
enum Running {
    Qemu(Qemu),
    Host(HostBoard),
}

impl Running {
    fn check_alive(&mut self) -> Result {
        match self {
            Running::Qemu(q) => q.check_alive(),
            Running::Host(h) => h.check_alive(),
        }
    }

    fn print_log_tail(&self) {
        match self {
            Running::Qemu(q) => q.print_log_tail(30),
            Running::Host(h) => h.print_log_tail(),
        }
    }
}

/// `enip-host` inside the lab; stopped when dropped.
struct HostBoard {
    child: Child,
    log: std::path::PathBuf,
}

impl HostBoard {
    /// Starts `bin` on the lab's TAP and waits until it listens.
    fn start(lab: &Lab, bin: &Path, log: &Path) -> Result<HostBoard> {
        let file = fs::File::create(log)?;
        let mut cmd = lab.command(&bin.to_string_lossy());
        cmd.args(["--tap", &lab.tap, "--ip", BOARD_CIDR, "--profile", PROFILE])
            .stdin(Stdio::null())
            .stdout(file.try_clone()?)
            .stderr(file);
        println!("$ {}  (log: {})", util::show(&cmd), log.display());
        let mut host = HostBoard {
            child: cmd.spawn()?,
            log: log.to_path_buf(),
        };
        let start = Instant::now();
        while !fs::read_to_string(log)
            .unwrap_or_default()
            .contains("listening on")
        {
            host.check_alive()?;
            if start.elapsed() > HOST_BOOT_TIMEOUT || interrupted() {
                return err("enip-host did not come up");
            }
            sleep(Duration::from_millis(100));
        }
        Ok(host)
    }

    fn check_alive(&mut self) -> Result {
        match self.child.try_wait()? {
            Some(status) => err(format!("enip-host exited ({status})")),
            None => Ok(()),
        }
    }

    fn print_log_tail(&self) {
        let text = fs::read_to_string(&self.log).unwrap_or_default();
        let lines: Vec<&str> = text.lines().collect();
        println!("--- last lines of {} ---", self.log.display());
        for l in lines.iter().skip(lines.len().saturating_sub(30)) {
            println!("  | {l}");
        }
    }
}

impl Drop for HostBoard {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
