//! `cargo xtask smoke`, and the last step of `cargo xtask test`: builds what the QEMU smoke
//! run needs and runs it, the test `qemu_smoke` in host-tests (`host-tests/tests/qemu_smoke.rs`
//! says what it checks), with its figures printed. Its report goes to
//! `target/qemu-smoke/report.json`, the board's log next to it.

use enip_lab::{peers, rig};

use crate::boards;
use crate::qemu;
use crate::setup;
use crate::util::{self, loud, run, Outcome, Result};

/// Runs the smoke run (skipped, loudly, without root).
pub fn run_smoke() -> Result<Outcome> {
    if !util::is_root() {
        loud("QEMU smoke run: SKIPPED: network namespaces need root");
        return Ok(Outcome::Skipped);
    }
    qemu::ensure_installed()?;
    setup::python_peers()?;
    let elf = boards::build(boards::QEMU, boards::DEFAULT_PROFILE)?;
    // The 1 ms timing wants the optimised scanner.
    run(util::cargo().args(["build", "--release", "-p", "host-tests", "--bin", "scanner"]))?;
    run(util::cargo()
        .args(["test", "-p", "host-tests", "--test", "qemu_smoke"])
        .args(["--", "--ignored", "--nocapture"])
        .env(rig::qemu_elf_var(boards::DEFAULT_PROFILE), elf)
        .env(
            "ENIP_SCANNER_BIN",
            util::target_dir().join("release/scanner"),
        )
        .env("ENIP_PEER_PYTHON", peers::venv_python()))?;
    Ok(Outcome::Passed)
}
