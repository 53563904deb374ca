//! Issue 25 item 3 on the wire (`--profile ametek-pls`): the reset to preset inputs (average
//! and whole-group mask) and the input offsets driven by soft input 9 of the PyPI
//! `ethernetip` exclusive owner, the network status LED's timed-out state (board log), and
//! the resolver fault of `--pls-resolver-fault on` seen by pycomm3 and in the I/O data
//! (scripts `host-tests/peers/ametek_pls_inputs.py`, `ametek_pls_fault.py`).

use serde_json::json;

use super::ametek_pls::{peer, start, MULTIPLIER, RPI_MS};
use crate::common;
use host_tests::rig::BOARD_IP;

/// The NS LED transitions the board logged, in order ("green", "flashing green", ...).
fn network_status(log: &str) -> Vec<&str> {
    log.lines()
        .filter_map(|l| l.split_once("PLS: NS LED ").map(|(_, s)| s))
        .map(|s| s.split(" (").next().unwrap_or(s))
        .collect()
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn ametek_pls_inputs_and_network_status() {
    let rig = start("ametek_pls_inputs", &[]);
    let r = peer(
        &rig,
        "inputs",
        json!({"host": BOARD_IP.to_string(), "rpi_ms": RPI_MS, "multiplier": MULTIPLIER}),
    );
    assert_eq!(r["writes"], json!([0, 0, 0]), "{r}");
    assert_eq!(r["forward_open"], 0, "{r}");
    // Average of the last 2 input positions: it settles where the inputs come.
    assert_eq!(r["average_write"], 0, "{r}");
    assert_eq!(r["average"], json!([100, 105, 115, 120, 120]), "{r}");
    // No mask: the whole group is reset to the preset (2.6), from 250 to 55.
    assert_eq!(r["no_mask_write"], 0, "{r}");
    assert_eq!(r["no_mask"], 55, "{r}");
    // A mask with every output of the group: the group position becomes the preset (55:
    // output 1 off, output 17 on).
    assert_eq!(r["whole_write"], 0, "{r}");
    assert_eq!(r["whole"], json!([55, 0, 1]), "{r}");
    assert_eq!(r["offset_before"], 55, "{r}");
    assert_eq!(r["enable_write"], 0, "{r}");
    assert_eq!(r["offset_after"], 0, "{r}");
    assert_eq!(r["class3_get"], 0, "{r}");
    assert_eq!(r["reopen"], 0, "{r}");
    assert_eq!(r["identity_reset"], 0, "{r}");
    // NS: green with the owner; red flashing after its timeout, through the Class 3
    // connection's life; green when the owner is back; red flashing after the second
    // timeout until the Identity Reset, then flashing green (no connection).
    let log = rig.board_log();
    assert_eq!(
        network_status(&log),
        [
            "green",
            "flashing red",
            "green",
            "flashing red",
            "flashing green"
        ],
        "{log}"
    );
    common::finish(rig);
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn ametek_pls_resolver_fault() {
    let rig = start("ametek_pls_fault", &["--pls-resolver-fault", "on"]);
    let r = peer(
        &rig,
        "fault",
        json!({"host": BOARD_IP.to_string(), "rpi_ms": RPI_MS, "multiplier": MULTIPLIER}),
    );
    assert_eq!(r["writes"], json!([0, 0, 0]), "{r}");
    // Identity status bit 10: major recoverable fault.
    assert_eq!(r["identity_status"][0], 0, "{r}");
    assert_ne!(r["identity_status"][1].as_u64().unwrap() & 0x0400, 0, "{r}");
    assert_eq!(r["forward_open"], 0, "{r}");
    // Input words 9-10 (RPM 0, resolver fault 1).
    let w = &r["words_at_open"];
    assert_eq!((&w[8], &w[9]), (&json!(0), &json!(1)), "{r}");
    // An offset during the fault: 0x10 and error code 3 in words 15-17.
    assert_eq!(r["home"], 0x10, "{r}");
    let w = &r["words_after_home"];
    assert_eq!(w.as_array().unwrap()[14..17], [3, 36, 1], "{r}");
    assert_eq!(r["forward_close"], 0, "{r}");
    let log = rig.board_log();
    assert!(
        log.contains("PLS: MS LED flashing red (resolver fault)"),
        "{log}"
    );
    common::finish(rig);
}
