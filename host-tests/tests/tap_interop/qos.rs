//! DSCP marking by the QoS object (class 0x48), checked with tshark on the capture: the T->O
//! packets of a scheduled-priority connection (the PyPI `ethernetip` package's default)
//! carry QoS attribute 5, explicit messaging (TCP and UDP 44818) attribute 8. pycomm3 sets
//! new values (script `host-tests/peers/qos.py`); as documented in `stack/src/objects/qos.rs`
//! they are read back at once but marked from the next start, so the packets keep the
//! defaults until the board restarts on the same `--nv-file`, then carry the new values.
//!
//! On the TAP board the link task marks the frames; with `ENIP_HOST_LINK=bind` the same test
//! runs on kernel sockets over a veth pair, where the sockets' `IP_TOS` does. The emulated
//! board (QEMU, the same firmware) is checked in one boot: its store is RAM that a restart
//! empties, so there the changed values are shown read back and not yet marked.

use std::path::Path;
use std::time::Duration;

use serde_json::{json, Value};

use crate::common;
use host_tests::capture;
use host_tests::peers;
use host_tests::rig::{Rig, BOARD_IP};

/// Bound for one peer program run.
const PEER_TIMEOUT: Duration = Duration::from_secs(60);
/// The scheduled DSCP (attribute 5) pycomm3 sets.
const NEW_SCHEDULED: u8 = 40;
/// The explicit DSCP (attribute 8) pycomm3 sets.
const NEW_EXPLICIT: u8 = 20;

/// The board with `--nv-file nv`, capturing into `<name>.pcapng`.
fn start(name: &str, nv: &Path) -> Rig {
    let pcap = common::scratch(&format!("{name}.pcapng"));
    let args = ["--nv-file", nv.to_str().expect("a UTF-8 path")];
    Rig::start_at(&common::host_bin(), "generic", &args, Some(&pcap), BOARD_IP)
        .unwrap_or_else(|e| panic!("rig for {name}: {e}"))
}

fn peer(rig: &Rig, phase: &str) -> Value {
    let input = json!({"host": BOARD_IP.to_string(), "phase": phase, "seconds": 1.0,
        "scheduled": NEW_SCHEDULED, "explicit": NEW_EXPLICIT});
    let out = peers::run(rig.ns(), "qos.py", &input, PEER_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}\nboard log:\n{}", rig.board_log()));
    println!("qos.py {phase}: {out}");
    assert_eq!(out["forward_open"], 0, "{out}");
    assert!(out["list_identity"].as_u64().is_some(), "{out}");
    out
}

/// Asserts that the board's packets matching `what` exist and all carry `dscp`.
fn assert_marked(pcap: &Path, what: &str, dscp: u8) {
    let from_board = format!("ip.src == {BOARD_IP} && {what}");
    let all = capture::count(pcap, &from_board).expect("read capture");
    let other = format!("{from_board} && ip.dsfield.dscp != {dscp}");
    let wrong = capture::count(pcap, &other).expect("read capture");
    println!(
        "{}: {all} packets of {what}, {wrong} not DSCP {dscp}",
        pcap.display()
    );
    assert!(all > 0, "no packet of {what} in {}", pcap.display());
    assert_eq!(
        wrong,
        0,
        "{what}: not all DSCP {dscp} in {}",
        pcap.display()
    );
}

/// Every kind of packet the adapter sends, with the DSCP each must carry.
fn assert_all_marked(pcap: &Path, scheduled: u8, explicit: u8) {
    assert_marked(pcap, "udp.srcport == 2222", scheduled);
    assert_marked(pcap, "tcp.srcport == 44818", explicit);
    assert_marked(pcap, "udp.srcport == 44818", explicit);
}

/// The QEMU board with the generic profile: the defaults marked, and a Set read back while
/// the packets keep the values the board started with (skipped, loudly, without the ELF).
#[test]
#[ignore = "needs root, QEMU and ENIP_QEMU_GENERIC_ELF"]
fn dscp_marking_on_qemu_and_set_values_wait_for_the_next_start() {
    let Some(elf) = host_tests::rig::qemu_elf("generic") else {
        return;
    };
    let pcap = common::scratch("qos_qemu.pcapng");
    let rig = Rig::start_qemu(&elf, Some(&pcap)).unwrap_or_else(|e| panic!("{e}"));
    let r = peer(&rig, "set");
    assert_set(&r);
    let log = rig.board_log();
    assert!(!log.contains("PANIC"), "the board panicked:\n{log}");
    let pcap = common::finish_keeping_capture(rig);
    assert_all_marked(&pcap, 47, 27);
}

/// Asserts the "set" phase's answers: the defaults, 64 refused with 0x09, the new values
/// accepted and read back.
fn assert_set(r: &Value) {
    let defaults = json!({"1": 0, "2": 59, "3": 47, "4": 55, "5": 47, "6": 43, "7": 31, "8": 27});
    assert_eq!(r["before"], defaults, "{r}");
    assert_eq!(
        (&r["set_64"], &r["set_5"], &r["set_8"]),
        (&json!(9), &json!(0), &json!(0))
    );
    assert_eq!(r["after"]["5"], NEW_SCHEDULED, "{r}");
    assert_eq!(r["after"]["8"], NEW_EXPLICIT, "{r}");
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn dscp_marking_follows_the_qos_object_from_the_next_start() {
    let nv = common::fresh_nv_file("qos_nv.bin");
    let rig = start("qos_set", &nv);
    let r = peer(&rig, "set");
    assert_set(&r);
    // Set, read back, but not in use before the next start.
    let pcap = common::finish_keeping_capture(rig);
    assert_all_marked(&pcap, 47, 27);
    // The power cycle: the same file, the new values on every packet.
    let rig = start("qos_restart", &nv);
    let r = peer(&rig, "check");
    assert_eq!(r["before"]["5"], NEW_SCHEDULED, "{r}");
    assert_eq!(r["before"]["8"], NEW_EXPLICIT, "{r}");
    let pcap = common::finish_keeping_capture(rig);
    assert_all_marked(&pcap, NEW_SCHEDULED, NEW_EXPLICIT);
}
