//! The emulated board on QEMU's other cores with the LAN9118 (a step of `cargo xtask test`):
//! the same `enip-qemu-mps2` firmware built for `mps2-an385` (Cortex-M3), `mps2-an500`
//! (Cortex-M7) and `mps2-an505` (Cortex-M33, Secure state), one test each, in a namespace of
//! its own:
//!
//! 1. it boots and answers a ListIdentity;
//! 2. pycomm3 reads its Identity object and finds it with a broadcast ListIdentity;
//! 3. the PyPI `ethernetip` package runs an exclusive owner (input 100, output 150, config
//!    151) at a 10 ms RPI for 5 s: it opens, sees its output echoed and closes cleanly, and
//!    the board logs no connection timeout.
//!
//! Needs root, `qemu-system-arm`, the Python peers (`ENIP_PEER_PYTHON`) and the images,
//! `ENIP_QEMU_AN385_ELF`, `ENIP_QEMU_AN500_ELF`, `ENIP_QEMU_AN505_ELF` (the generic profile,
//! built by `cargo xtask test`; a test whose variable is unset is skipped, loudly).

use std::path::PathBuf;
use std::time::Duration;

use host_tests::netns::{BOARD_IP, BROADCAST_IP};
use host_tests::peers;
use host_tests::rig::{Board, Options, Rig};
use serde_json::json;

/// Class 1 with `ethernetip`: RPI in ms and duration in s.
const RPI_MS: u32 = 10;
const SECONDS: u64 = 5;
/// Seconds the pycomm3 part may take, and a peer beyond its run.
const EXPLICIT_SECONDS: u64 = 30;
const PEER_SLACK_SECONDS: u64 = 20;
/// Lines of the board's log shown when a check fails.
const LOG_TAIL: usize = 30;

#[test]
#[ignore = "needs root, QEMU, the Python peers and ENIP_QEMU_AN385_ELF"]
fn an385_cortex_m3() {
    core_serves("mps2-an385", "ENIP_QEMU_AN385_ELF");
}

#[test]
#[ignore = "needs root, QEMU, the Python peers and ENIP_QEMU_AN500_ELF"]
fn an500_cortex_m7() {
    core_serves("mps2-an500", "ENIP_QEMU_AN500_ELF");
}

#[test]
#[ignore = "needs root, QEMU, the Python peers and ENIP_QEMU_AN505_ELF"]
fn an505_cortex_m33() {
    core_serves("mps2-an505", "ENIP_QEMU_AN505_ELF");
}

/// Boots the ELF named by `var` on `machine` and runs the checks.
fn core_serves(machine: &str, var: &str) {
    let Some(elf) = std::env::var_os(var).map(PathBuf::from) else {
        eprintln!("SKIPPED: set {var} to an enip-qemu-mps2 ELF built for {machine}");
        return;
    };
    let board = Board::QemuMachine {
        machine,
        elf: &elf,
        extra: &[],
    };
    let mut rig = Rig::launch(board, &Options::default())
        .unwrap_or_else(|e| panic!("boot {} on {machine}: {e}", elf.display()));
    let booted = format!("booting on {machine}");
    if let Err(e) = checks(&mut rig).and_then(|()| {
        rig.board_log()
            .contains(&booted)
            .then_some(())
            .ok_or_else(|| format!("the board did not log {booted:?}"))
    }) {
        panic!(
            "{machine}: {e}\n--- last lines of its log ---\n{}",
            rig.board_log_tail(LOG_TAIL)
        );
    }
    rig.finish().unwrap_or_else(|e| panic!("{e}"));
}

/// pycomm3's Identity and ListIdentity, then the `ethernetip` owner without a timeout.
fn checks(rig: &mut Rig) -> Result<(), String> {
    let (board, broadcast) = (BOARD_IP.to_string(), BROADCAST_IP.to_string());
    let out = peers::run_with_args(
        rig.ns(),
        "smoke_explicit.py",
        &[&board, &broadcast],
        Duration::from_secs(EXPLICIT_SECONDS),
    )
    .map_err(|e| format!("pycomm3: {e}"))?;
    let name = out["identity"]["product_name"].as_str().unwrap_or_default();
    if name.is_empty() {
        return Err(format!("pycomm3 read no product name: {out}"));
    }
    let found = out["discovered"]
        .as_array()
        .is_some_and(|d| d.iter().any(|d| d["ip_address"] == board.as_str()));
    if !found {
        return Err(format!("the ListIdentity broadcast found no {BOARD_IP}"));
    }
    println!("pycomm3: Identity of {BOARD_IP}: {name}");
    rig.check_alive().map_err(|e| e.to_string())?;
    let log_before = rig.board_log().len();
    let request = json!({
        "host": board,
        "rpi_ms": RPI_MS,
        "seconds": SECONDS,
        "multicast": false,
    });
    let timeout = Duration::from_secs(SECONDS + PEER_SLACK_SECONDS);
    let out = peers::run(rig.ns(), "ethernetip_class1.py", &request, timeout)
        .map_err(|e| format!("ethernetip: {e}"))?;
    println!("ethernetip: exclusive owner at {RPI_MS} ms for {SECONDS} s: {out}");
    if ["forward_open", "forward_close", "reopen"]
        .iter()
        .any(|k| out[k] != 0)
    {
        return Err(format!(
            "ethernetip: Forward_Open, Forward_Close or the reopen failed: {out}"
        ));
    }
    if out["echoed"] != true {
        return Err("ethernetip: its output data never came back in the input".into());
    }
    rig.check_alive().map_err(|e| e.to_string())?;
    if rig
        .board_log()
        .get(log_before..)
        .unwrap_or_default()
        .contains("timed out")
    {
        return Err("the board logged a connection timeout during the ethernetip run".into());
    }
    Ok(())
}
