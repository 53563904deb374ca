//! TCP/IP settings that survive a restart (`enip-host --nv-file`): pycomm3 sets a static
//! interface configuration (attribute 5), host name (6), multicast TTL (8) and configuration
//! (9) and inactivity timeout (13); the board
//! restarted with the same file comes up at the address set and reads them back (script
//! `host-tests/peers/tcpip_nv.py`).
//!
//! Every run is captured and checked by tshark ([`common::finish`]).

use std::net::Ipv4Addr;
use std::path::PathBuf;
use std::time::Duration;

use serde_json::{json, Value};

use crate::common;
use host_tests::peers;
use host_tests::rig::{Rig, BOARD_IP};

/// Bound for one peer program run.
const PEER_TIMEOUT: Duration = Duration::from_secs(60);
/// The address set through attribute 5.
const NEW_IP: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 9);

/// Starts the generic board for test `name` with `extra` arguments, answering at `at`.
pub fn start(name: &str, extra: &[&str], at: Ipv4Addr) -> Rig {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let bin = std::env::var_os("ENIP_HOST_BIN").unwrap_or("target/debug/enip-host".into());
    let pcap = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("tap_interop")
        .join(format!("{name}.pcapng"));
    Rig::start_at(&root.join(bin), "generic", extra, Some(&pcap), at)
        .unwrap_or_else(|e| panic!("rig for {name}: {e}"))
}

fn peer(rig: &Rig, host: Ipv4Addr, phase: &str) -> Value {
    let input = json!({"host": host.to_string(), "phase": phase, "ip": NEW_IP.to_string(),
        "mask": "255.255.255.0", "gateway": "198.18.0.1", "domain": "plant.example"});
    let out = peers::run(rig.ns(), "tcpip_nv.py", &input, PEER_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}\nboard log:\n{}", rig.board_log()));
    println!("tcpip_nv.py {phase}: {out}");
    out
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn tcpip_interface_configuration_survives_a_restart() {
    let file = common::fresh_nv_file("tcpip_nv.bin");
    let nv = file.to_str().unwrap();
    let rig = start("tcpip_nv_set", &["--nv-file", nv], BOARD_IP);
    let r = peer(&rig, BOARD_IP, "set");
    assert_eq!(r["set_bad_5"], 0x09, "{r}");
    for a in ["set_5", "set_6", "set_8", "set_9", "set_13"] {
        assert_eq!(r[a], json!(0), "{a}: {r}");
    }
    // Capability: settable, change requires reset, ACD capable (the TAP board runs it,
    // skipped in this run by the rig's `--acd off`), no DHCP client on the host board;
    // status: configured, interface change pending, multicast change pending.
    assert_eq!(r["read"]["2"]["value"], "d0000000", "{r}");
    assert_eq!(r["read"]["1"]["value"], "31000000", "{r}");
    assert_eq!(r["read"]["5"]["value"], r["expected_5"], "{r}");
    common::finish(rig);
    // The same file, the old --ip: the board comes up at the address set.
    let rig = start("tcpip_nv_restart", &["--nv-file", nv], NEW_IP);
    let log = rig.board_log();
    assert!(
        log.contains("from the stored TCP/IP configuration"),
        "{log}"
    );
    assert!(log.contains(&format!("listening on {NEW_IP}")), "{log}");
    let r = peer(&rig, NEW_IP, "check");
    assert_eq!(r["read"]["1"]["value"], "01000000", "{r}");
    assert_eq!(r["read"]["5"]["value"], r["expected_5"], "{r}");
    assert_eq!(r["read"]["6"]["value"], "070070726573732d3400", "{r}");
    assert_eq!(r["read"]["8"]["value"], "05", "{r}");
    assert_eq!(r["read"]["9"]["value"], "010004000003c0ef", "{r}");
    assert_eq!(r["read"]["13"]["value"], "1e00", "{r}");
    common::finish(rig);
}
