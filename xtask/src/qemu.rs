//! `cargo xtask qemu`: the emulated board (`qemu-system-arm -M mps2-an386`, launched by the
//! lab's [`Rig`]) in a network namespace until Ctrl-C, and what every QEMU command needs
//! first (QEMU installed, root).

use std::fs;
use std::thread::sleep;
use std::time::{Duration, Instant};

use enip_lab::peers;
use enip_lab::rig::{Board, Options, Rig, BOARD_CIDR};

use crate::boards;
use crate::setup;
use crate::util::{self, err, interrupted, Result};

/// `cargo xtask qemu` stops the board after this long at the latest.
const INTERACTIVE_LIMIT: Duration = Duration::from_secs(3600);
/// The namespace and TAP of `cargo xtask qemu`.
const NAMESPACE: &str = "enip-qemu";
const TAP: &str = "enipqemu0";

/// Installs QEMU if it is missing (Debian package `qemu-system-arm`).
pub fn ensure_installed() -> Result {
    if util::have("qemu-system-arm") {
        return Ok(());
    }
    setup::apt_install(&["qemu-system-arm"])
}

/// Fails unless running as root (network namespaces and TAP devices need it).
pub fn require_root(what: &str) -> Result {
    if util::is_root() {
        Ok(())
    } else {
        err(format!(
            "{what}: network namespaces need root; run it as root (or with sudo)"
        ))
    }
}

/// Prints the last `n` lines the rig's board logged, under the name of its log file.
pub fn print_log_tail(rig: &Rig, log: &std::path::Path, n: usize) {
    println!("--- last lines of {} ---", log.display());
    for l in rig.board_log_tail(n).lines() {
        println!("  | {l}");
    }
}

/// `cargo xtask qemu [--profile NAME] [--machine NAME]`: builds the board (for `machine`, one
/// of [`crate::qemu_cores::CORES`] by feature or QEMU name, else mps2-an386), boots it in
/// namespace `enip-qemu` (TAP `enipqemu0`, the board at 198.18.0.2/24) and keeps it running
/// until Ctrl-C.
pub fn run_interactive(profile: &str, machine: Option<&str>) -> Result {
    require_root("qemu")?;
    util::catch_interrupts();
    setup::rust_target()?;
    ensure_installed()?;
    let (machine, elf) = match machine {
        None => ("mps2-an386", boards::build(boards::QEMU, profile)?),
        Some(name) => {
            let core = crate::qemu_cores::CORES
                .into_iter()
                .find(|c| c.feature == name || c.machine == name)
                .ok_or_else(|| util::Error(format!("--machine {name}: not an385, an500, an505")))?;
            (core.machine, core.build_with(profile, &[])?)
        }
    };
    let dir = util::target_dir().join("qemu");
    fs::create_dir_all(&dir)?;
    let log = dir.join("board.log");
    println!(
        "qemu: booting {} on {machine} (log: {})",
        elf.display(),
        log.display()
    );
    let board = Board::QemuMachine {
        machine,
        elf: &elf,
        extra: &[],
    };
    let mut rig = Rig::launch(board, &Options::named(NAMESPACE, TAP, &log))?;
    print_log_tail(&rig, &log, 5);
    println!(
        "\nThe emulated board runs profile {profile} at {BOARD_CIDR} in namespace {NAMESPACE}. \
         Talk to it from there, e.g.\n  ip netns exec {NAMESPACE} {python} -c \
         \"from pycomm3 import CIPDriver; print(CIPDriver.list_identity('198.18.0.2'))\"\n\
         Ctrl-C stops it (it stops by itself after {limit} min).",
        python = peers::venv_python().display(),
        limit = INTERACTIVE_LIMIT.as_secs() / 60,
    );
    let start = Instant::now();
    while !interrupted() && start.elapsed() < INTERACTIVE_LIMIT {
        rig.check_alive()?;
        sleep(Duration::from_millis(200));
    }
    print_log_tail(&rig, &log, 10);
    drop(rig);
    println!("qemu: board stopped, namespace {NAMESPACE} deleted");
    Ok(())
}
