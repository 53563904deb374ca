//! The Lenze PositionServo profile (`--profile position-servo`) replaying its manual's
//! examples with peers nobody here wrote: pycomm3 for explicit messages, the PyPI
//! `ethernetip` package for Class 1 (scripts `host-tests/peers/position_servo_*.py`), the
//! project's scanner for the connection types and multicast, and `eds-pie` for the EDS.
//!
//! Each scenario runs against a `Target`: the host board (one fresh board per test), or
//! the QEMU board ([`position_servo_on_qemu`], every scenario on one boot, when
//! `ENIP_QEMU_POSITION_SERVO_ELF` names a `enip-qemu-mps2` ELF built with the
//! position-servo profile).

use std::path::PathBuf;
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use crate::common;
use crate::position_servo_connections::{connections_scenario, multicast_on_the_wire};
use crate::position_servo_qemu::QemuBoard;
use host_tests::netns::Namespace;
use host_tests::peers;
use host_tests::rig::{Rig, BOARD_IP};

/// Bound for one peer program run.
const PEER_TIMEOUT: Duration = Duration::from_secs(60);
/// The RPI of the manual's examples (4.4: "5.0 milliseconds or greater").
pub const RPI_MS: u32 = 5;
/// Forward_Open timeout multiplier code 2: the watchdog is 16 x RPI = 80 ms.
pub const MULTIPLIER: u32 = 2;
/// The profile's name.
const PROFILE: &str = "position-servo";

/// Where a scenario runs: a namespace holding the board, and the board's log.
pub trait Target {
    /// The namespace peers run in.
    fn ns(&self) -> &Namespace;
    /// What the board logged so far.
    fn log(&self) -> String;
    /// True if an Identity Reset restarts the board (its RAM-backed EPM starts empty).
    fn restarts_on_reset(&self) -> bool;
    /// Extra milliseconds a timing bound allows for this board being descheduled by the
    /// host (an emulated board on a shared host can stall for tens of milliseconds).
    fn slack_ms(&self) -> f64;
}

impl Target for Rig {
    fn ns(&self) -> &Namespace {
        Rig::ns(self)
    }
    fn log(&self) -> String {
        self.board_log()
    }
    fn restarts_on_reset(&self) -> bool {
        false
    }
    fn slack_ms(&self) -> f64 {
        10.0
    }
}

/// The capture file of test `name`.
pub fn pcap(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("tap_interop")
        .join(format!("{name}.pcapng"))
}

/// Starts the host board with the profile, capturing into [`pcap`]`(name)`.
pub fn start(name: &str) -> Rig {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let bin = std::env::var_os("ENIP_HOST_BIN").unwrap_or("target/debug/enip-host".into());
    Rig::start(&root.join(bin), PROFILE, Some(&pcap(name)))
        .unwrap_or_else(|e| panic!("rig for {name}: {e}"))
}

/// Runs the peer script `position_servo_<name>.py` with `input`; returns its JSON.
fn peer(t: &dyn Target, name: &str, input: Value) -> Value {
    let script = format!("position_servo_{name}.py");
    let out = peers::run(t.ns(), &script, &input, PEER_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}\nboard log:\n{}", t.log()));
    println!("{script}: {out}");
    out
}

fn class1_input(reference: f64) -> Value {
    json!({"host": BOARD_IP.to_string(), "rpi_ms": RPI_MS, "multiplier": MULTIPLIER,
           "reference": reference, "distance": 10.0})
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

/// Example 6.3 and the System940 object's statuses; Identity; multicast settings.
fn explicit(t: &dyn Target) {
    let r = peer(t, "explicit", json!({"host": BOARD_IP.to_string()}));
    let ok = |k: &str, data: &str| {
        assert_eq!(
            (r[k]["status"].as_u64(), r[k]["data"].as_str()),
            (Some(0), Some(data)),
            "{k}"
        );
    };
    ok("v0_set_real", "");
    ok("v0_real", &hex(&1234.5f32.to_le_bytes()));
    ok("v0_int", &hex(&1235u32.to_le_bytes()));
    ok("v0_text", &format!("06000000{}", hex(b"1234.5")));
    ok("v0_epm_reads_ram", &hex(&1234.5f32.to_le_bytes()));
    ok("v1_real", &hex(&(-2.25f32).to_le_bytes()));
    ok("v2_before_reset", &hex(&8.0f32.to_le_bytes()));
    // The EPM value comes back into RAM; a restarting board's RAM-backed EPM is empty.
    let after_reset = if t.restarts_on_reset() { 0.0f32 } else { 7.0 };
    ok("v2_after_reset", &hex(&after_reset.to_le_bytes()));
    for (k, status) in [
        ("unknown_variable", 0x16),
        ("unknown_attribute", 0x14),
        ("read_only", 0x0E),
        ("no_epm_copy", 0x0E),
        ("out_of_range", 0x09),
        ("short_data", 0x13),
        ("bad_text", 0x09),
        ("set_attr_9_two", 0x09),
    ] {
        assert_eq!(r[k]["status"].as_u64(), Some(status), "{k}: {}", r[k]);
    }
    ok("class_revision", "0100");
    ok("class_max_instance", &hex(&275u16.to_le_bytes()));
    // Count 2; attribute 0 status 0; attribute 2 status 0.
    ok("list_set", "02000000000002000000");
    // Count 2; attribute 0, status 0, 13 (12.5 rounded); attribute 2, status 0, 12.5.
    let list = format!(
        "020000000000{}02000000{}",
        hex(&13u32.to_le_bytes()),
        hex(&12.5f32.to_le_bytes())
    );
    ok("list_get", &list);
    // 7.3 lists Get_Attributes_All for the assembly instances: the data, as attribute 3.
    let data = r["assembly_106_data"]["data"].as_str().unwrap_or_default();
    assert_eq!(data.len(), 2 * 8, "{}", r["assembly_106_data"]);
    ok("assembly_106_data", data);
    ok("assembly_106_all", data);
    ok("product_name", &format!("0a{}", hex(b"EnetIP 940")));
    ok("ttl_default", "01");
    ok("mcast_default", "00000100200fc0ef");
    ok("var_275_default", "200fc0ef");
    ok("ttl_after_vars", "05");
    ok("mcast_after_vars", "010001000302c0ef");
    ok("var_273_after_attr", "07000000");
    ok("var_275_after_attr", "0909c0ef");
}

fn hex(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02x}")).collect()
}

/// Examples 8.3 then 8.1: configuration writes, then velocity control over Class 1.
fn velocity(t: &dyn Target) {
    let r = peer(t, "velocity", class1_input(100.0));
    assert_eq!(r["writes"], json!([0, 0, 0, 0, 0, 0]), "{r}");
    assert_eq!(r["readback"], json!([1, 1, 0, 1, 1000, 1000]), "{r}");
    assert_eq!(r["forward_open"], json!([0, 0]), "{r}");
    for phase in ["up", "down"] {
        // 100 units/s at 1000 units/s²: 100 ms, plus an RPI or two each way and the lag.
        let (slope, reached) = (f(&r[phase]["slope"]), f(&r[phase]["reached_ms"]));
        assert!(
            (800.0..=1200.0).contains(&slope),
            "{phase}: slope {slope}: {r}"
        );
        let bound = 95.0..=140.0 + t.slack_ms();
        assert!(
            bound.contains(&reached),
            "{phase}: at target after {reached} ms"
        );
    }
    assert_eq!(r["velocity_at_stop"], json!(0.0));
    assert_eq!(r["status2_before"].as_u64().map(|s| s & 1), Some(0));
    // Seen in the next 104 datagram: an RPI or two, plus the peer's own latency.
    let bit = 20.0 + t.slack_ms();
    assert!(f(&r["enabled_after_ms"]) <= bit, "STATUS2 enable bit: {r}");
    assert!(f(&r["disabled_after_ms"]) <= bit, "STATUS2 enable bit: {r}");
    assert_eq!(r["status2_after"].as_u64().map(|s| s & 1), Some(0));
    assert_eq!(r["forward_close"], json!([0, 0]), "{r}");
}

/// Example 8.2: MOVED 10 moves the actual position by 10 units, then motion completed.
fn indexing(t: &dyn Target) {
    let r = peer(t, "indexing", class1_input(0.0));
    assert_eq!(r["writes"], json!([0, 0, 0]), "{r}");
    assert_eq!(r["forward_open"], json!([0, 0]), "{r}");
    assert_eq!(r["enabled"], true, "{r}");
    assert_eq!(r["moved"], 0, "{r}");
    let (before, after) = (f(&r["position_before"]), f(&r["position_after"]));
    // Exact in the drive; 105 reports REALs, exact to their precision.
    assert!((after - before - 10.0).abs() <= 1e-4, "{r}");
    assert_eq!(f(&r["variable_215"]), after);
    // At 10 units/s with the accel/decel limits (100 by default, 1000 after 8.3).
    let done = f(&r["completed_ms"]);
    assert!(
        (950.0..=1400.0).contains(&done),
        "completed after {done} ms: {r}"
    );
    let cleared = 20.0 + t.slack_ms();
    assert!(
        f(&r["cleared_ms"]) <= cleared,
        "motion completed cleared late: {r}"
    );
    let status2 = r["status2_after"].as_u64().unwrap_or(0);
    assert_eq!(status2 & (1 << 9 | 1 << 2 | 1), 1 << 9 | 1 << 2 | 1, "{r}");
    assert_eq!(r["forward_close"], json!([0, 0]), "{r}");
}

/// Table 13: input link A = 0xC00000BC puts the phase current in 105 word 5 as REAL.
fn datalink(t: &dyn Target) {
    let r = peer(t, "datalink", class1_input(50.0));
    assert_eq!(r["forward_open"], 0, "{r}");
    assert_eq!(r["at_speed"], true, "{r}");
    assert_eq!(
        (r["link_write"].as_u64(), r["link_readback"].as_u64()),
        (Some(0), Some(0xC000_00BC))
    );
    assert_eq!(r["changed"], true, "{r}");
    let current = f(&r["after"]["word3"]);
    assert!(current > 0.0, "{r}");
    assert_eq!(f(&r["after"]["word5"]), current, "{r}");
    assert_eq!(f(&r["variable_188"]), current, "{r}");
}

/// 8.4: killing the exclusive owner clears EXSTATUS bit 24 within the watchdog and the
/// drive disables.
fn ownership(t: &dyn Target) {
    let r = peer(t, "ownership", class1_input(10.0));
    assert_eq!(r["owner"]["forward_open"], 0, "{r}");
    assert_eq!(
        r["exstatus_owned"].as_u64().map(|v| v & 1 << 24),
        Some(1 << 24),
        "{r}"
    );
    assert_eq!(r["status_owned"].as_u64().map(|v| v & 1), Some(1), "{r}");
    let (cleared, watchdog) = (f(&r["cleared_ms"]), f(&r["watchdog_ms"]));
    // The watchdog runs from the owner's last datagram, which may precede the kill by an
    // RPI or more (the peer's own jitter); reading EXSTATUS takes about a millisecond.
    let bound = watchdog / 2.0..=watchdog + t.slack_ms();
    assert!(
        bound.contains(&cleared),
        "cleared {cleared} ms after the kill: {r}"
    );
    assert_eq!(
        r["exstatus_after"].as_u64().map(|v| v & 1 << 24),
        Some(0),
        "{r}"
    );
    assert_eq!(r["status_after"].as_u64().map(|v| v & 1), Some(0), "{r}");
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn position_servo_example_6_3_explicit() {
    let rig = start("position_servo_explicit");
    explicit(&rig);
    common::finish(rig);
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn position_servo_examples_8_3_and_8_1_velocity() {
    let rig = start("position_servo_velocity");
    velocity(&rig);
    common::finish(rig);
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn position_servo_example_8_2_indexing() {
    let rig = start("position_servo_indexing");
    indexing(&rig);
    common::finish(rig);
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn position_servo_table_13_datalink() {
    let rig = start("position_servo_datalink");
    datalink(&rig);
    common::finish(rig);
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn position_servo_exclusive_owner_loss() {
    let rig = start("position_servo_ownership");
    ownership(&rig);
    common::finish(rig);
}

/// A named scenario.
type Scenario = (&'static str, fn(&dyn Target));

/// Every scenario on the QEMU board, one boot (skipped, loudly, without the ELF).
#[test]
#[ignore = "needs root and ENIP_QEMU_POSITION_SERVO_ELF"]
fn position_servo_on_qemu() {
    let Some(elf) = host_tests::rig::qemu_elf("position-servo") else {
        return;
    };
    let board = QemuBoard::boot(&elf).unwrap_or_else(|e| panic!("{e}"));
    let scenarios: [Scenario; 6] = [
        ("example 6.3", explicit),
        ("connections and multicast", connections_scenario),
        ("examples 8.3 and 8.1", velocity),
        ("table 13", datalink),
        ("8.4 ownership loss", ownership),
        ("example 8.2", indexing),
    ];
    for (name, scenario) in scenarios {
        let start = Instant::now();
        scenario(&board);
        println!("QEMU: {name} passed in {:?}", start.elapsed());
    }
    multicast_on_the_wire(&board.finish());
}

/// The EDS parses without a warning and declares the manual's sizes and connections.
#[test]
#[ignore = "needs the Python peers (eds-pie)"]
fn position_servo_eds_is_clean() {
    let r = common::eds_check("position-servo");
    assert_eq!(r["protocol"], "EtherNetIP");
    let sizes = [(103, 0), (104, 8), (105, 36), (106, 8), (108, 24), (109, 4)];
    for (instance, size) in sizes {
        assert_eq!(r["assemblies"][format!("Assem{instance}")], size, "{r}");
    }
    let connections = r["connections"].as_array().map_or(0, Vec::len);
    assert_eq!(connections, 10, "{r}");
}
