//! The Kollmorgen AKD profile (`--profile kollmorgen-akd`) with peers nobody here wrote:
//! the PyPI `ethernetip` package as the Class 1 exclusive owner of command 101 / response
//! 102 at the manual's minimum RPI, pycomm3 for the Position Controller (0x25) and
//! Parameter (0x0F) objects, and `eds-pie` for the EDS (`eds_check.py`; scripts
//! `host-tests/peers/kollmorgen_akd_*.py`); the project's scanner as Class 1 owner for the
//! stops on Program mode and on the owner's timeout ([`stops`]). Every run is captured and
//! must dissect cleanly.

use std::path::PathBuf;
use std::time::Duration;

use serde_json::{json, Value};

use crate::common;
use host_tests::peers;
use host_tests::rig::{Rig, BOARD_IP};

mod stops;

/// Bound for one peer program run.
const PEER_TIMEOUT: Duration = Duration::from_secs(90);
/// The manual's minimum RPI (p.11: "10 ms or greater").
const RPI_MS: u32 = 10;
/// Forward_Open timeout multiplier code 2: the watchdog is 16 x RPI.
const MULTIPLIER: u32 = 2;

/// Starts the AKD board for test `name` with `extra` arguments (e.g. `--nv-file PATH`).
fn start(name: &str, extra: &[&str]) -> Rig {
    let pcap = common::scratch(&format!("{name}.pcapng"));
    Rig::start_with_args(&common::host_bin(), "kollmorgen-akd", extra, Some(&pcap))
        .unwrap_or_else(|e| panic!("rig for {name}: {e}"))
}

fn peer(rig: &Rig, script: &str, input: Value) -> Value {
    let out = peers::run(rig.ns(), script, &input, PEER_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}\nboard log:\n{}", rig.board_log()));
    println!("{script}: {out}");
    out
}

fn hex(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02x}")).collect()
}

/// A response assembly from its hex.
fn bytes(v: &Value) -> Vec<u8> {
    let s = v.as_str().unwrap_or("");
    (0..s.len() / 2)
        .filter_map(|i| u8::from_str_radix(s.get(2 * i..2 * i + 2)?, 16).ok())
        .collect()
}

fn dint(r: &[u8], i: usize) -> i32 {
    i32::from_le_bytes([r[i], r[i + 1], r[i + 2], r[i + 3]])
}

fn ms(v: &Value) -> f64 {
    v.as_f64().unwrap_or(f64::INFINITY)
}

const ENABLED: u8 = 0x80;
const HOMED: u8 = 0x20;
const DIRECTION: u8 = 0x10;
const FAULT: u8 = 0x08;
const IN_POSITION: u8 = 0x04;
const IN_MOTION: u8 = 0x01;
const LOAD_COMPLETE: u8 = 0x80;

/// The Class 1 scenario on a board fresh from power-up (not homed).
fn class1_scenario(rig: &Rig) {
    let r = peer(
        rig,
        "kollmorgen_akd_io.py",
        json!({"host": BOARD_IP.to_string(), "rpi_ms": RPI_MS, "multiplier": MULTIPLIER}),
    );
    assert_eq!(r["forward_open"], 0, "{r}");
    // The seed page's layout and the handshake example's first response.
    let first = bytes(&r["first_response"]);
    assert_eq!(first.len(), 64, "{r}");
    assert_eq!(first[..8], [0x84, 0, 0, 0x20, 0, 0, 0, 0], "{r}");
    assert_eq!(first[20..24], [0; 4]);
    assert_eq!(first[32..64], [0; 32]);
    // MT.TPOSWND at power-up: 0.5 rev, the parameter reference's default.
    let window = json!({"status": 0, "data": hex(&32_768i64.to_le_bytes())});
    assert_eq!(r["tposwnd_default"], window, "{r}");
    // A move before homing: General Fault and the error response; an enable cycle clears.
    let unhomed = bytes(&r["unhomed_move"]);
    assert_eq!(unhomed[0] & (FAULT | ENABLED), FAULT, "{r}");
    assert_eq!(unhomed[3..8], [0x34, 0x10, 0xFF, 0x26, 0x20], "{r}");
    // A jog in position mode before homing: the same fault (p.11).
    let jog = bytes(&r["unhomed_jog"]);
    assert_eq!(jog[0] & (FAULT | ENABLED | IN_MOTION), FAULT, "{r}");
    assert_eq!(jog[3..8], [0x34, 0x10, 0xFF, 0x27, 0x23], "{r}");
    let cleared = bytes(&r["after_enable_cycle"]);
    assert_eq!(cleared[0] & (FAULT | ENABLED), ENABLED, "{r}");
    // Load/Start edge; data changed while it stays high is not loaded.
    assert_eq!(r["set_velocity_mode"], 0);
    assert_ne!(bytes(&r["loaded"])[2] & LOAD_COMPLETE, 0, "{r}");
    let attr6 = json!({"status": 0, "data": hex(&1000i32.to_le_bytes())});
    assert_eq!(r["attr6_after_load"], attr6);
    assert_eq!(r["attr6_while_high"], attr6);
    assert_eq!(r["load_complete_while_high"], 0x80);
    assert_eq!(r["load_complete_after_clear"], 0);
    // Undefined command type: type 0x14 (axis bits kept), invalid parameter, the echo.
    let undefined = bytes(&r["undefined_type"]);
    assert_eq!(undefined[3..8], [0x34, 0x20, 0xFF, 0x2A, 0x25], "{r}");
    assert_eq!(undefined[2] & LOAD_COMPLETE, 0);
    // Jog follows Direction; Current Direction follows the motion; Smooth Stop stops it.
    assert!(ms(&r["jog_up_ms"]) < 400.0, "{r}");
    let up = bytes(&r["jog_positive"]);
    assert_eq!((dint(&up, 12), dint(&up, 4)), (1000, 1000), "{r}");
    assert_eq!(
        up[0] & (IN_MOTION | DIRECTION),
        IN_MOTION | DIRECTION,
        "{r}"
    );
    assert!(dint(&up, 8) > 0);
    assert!(ms(&r["smooth_stop_ms"]) < 400.0, "{r}");
    let stopped = bytes(&r["after_smooth_stop"]);
    assert_eq!((dint(&stopped, 12), stopped[0] & IN_MOTION), (0, 0), "{r}");
    let down = bytes(&r["jog_negative"]);
    assert_eq!(dint(&down, 12), -1000, "{r}");
    assert_eq!(down[0] & DIRECTION, 0, "{r}");
    // Hard Stop: stopped and disabled; no motion until Enable is cycled.
    assert!(ms(&r["hard_stop_ms"]) < 200.0, "{r}");
    assert_eq!(bytes(&r["after_hard_stop"])[0] & ENABLED, 0, "{r}");
    let without = bytes(&r["load_without_cycle"]);
    assert_eq!((without[0] & IN_MOTION, dint(&without, 12)), (0, 0), "{r}");
    let with = bytes(&r["load_after_cycle"]);
    assert_eq!(with[0] & (ENABLED | IN_MOTION), ENABLED | IN_MOTION, "{r}");
    // Target velocity 0 ends the trajectory (attribute 9's 10 rev/s²: 2 ms at 1000 units/s).
    assert!(ms(&r["zero_velocity_ms"]) < 200.0, "{r}");
    // Torque through a ramp to 1 rev/s: within the 20 A peak, 100 mA of friction at speed.
    let peak = r["ramp_torque_max"].as_i64().unwrap_or(i64::MAX);
    assert!((1..=20_000).contains(&peak), "{r}");
    assert_eq!(r["speed_torque"], 100, "{r}");
    // Attribute to Get mirrors attribute 3 every cycle.
    let get = bytes(&r["attribute_to_get_velocity"]);
    assert_eq!((get[3], get[24], get[32]), (0x25, 1, 3), "{r}");
    assert_eq!(r["set_position_mode"], 0);
    assert!(ms(&r["mode_seen_ms"]) < 1000.0, "{r}");
    // HOME.MOVE through parameter 205, then an absolute move ends in position.
    assert_eq!(r["home_move"]["status"], 0, "{r}");
    assert!(ms(&r["homed_ms"]) < 10_000.0, "{r}");
    assert_eq!(r["moving"], true, "{r}");
    // DRV.MOTIONSTAT: 15 (target reached, inside MT.TPOSWND) while moving, 11 (completed)
    // only at the end, 14 (target crossed) never in a move that ends normally.
    let ms_bits = |v: &[u8]| dint(v, 16) as u32 & (1 << 11 | 1 << 14 | 1 << 15);
    let moving = bytes(&r["while_moving"]);
    assert_ne!(moving[0] & IN_MOTION, 0, "{r}");
    assert_eq!(ms_bits(&moving), 1 << 15, "{r}");
    let moved = bytes(&r["after_move"]);
    assert_eq!(ms_bits(&moved), 1 << 11 | 1 << 15, "{r}");
    assert_eq!((dint(&moved, 8), dint(&moved, 4)), (5000, 5000), "{r}");
    assert_eq!(
        moved[0] & (HOMED | IN_POSITION | IN_MOTION),
        HOMED | IN_POSITION,
        "{r}"
    );
    // 5000 units at 2000 units/s with 100 ms ramps: 2.6 s, plus the peer's latency.
    assert!((2400.0..3500.0).contains(&ms(&r["move_ms"])), "{r}");
    let target = json!({"status": 0, "data": hex(&5000i32.to_le_bytes())});
    assert_eq!(r["attr6_after_move"], target);
    assert_eq!(r["pl_fb"]["data"], hex(&5000i64.to_le_bytes()));
    assert_eq!(dint(&bytes(&r["after_relative"]), 8), 3500, "{r}");
    // Motion task 3 by Start Block: executing block # 3 and Block in Execution, then 1000.
    assert_eq!(r["task_writes"], json!([0, 0, 0, 0, 0, 0]), "{r}");
    let running = bytes(&r["block_running"]);
    assert_eq!((running[1], running[0] & 0x02), (3, 0x02), "{r}");
    let refused = bytes(&r["refused_during_task"]);
    assert_eq!(refused[3..5], [0x34, 0x20], "{r}");
    assert_eq!((refused[1], refused[0] & 0x03), (3, 0x03), "{r}");
    let done = bytes(&r["after_task"]);
    assert_eq!(
        (done[1], done[0] & 0x02, dint(&done, 8)),
        (0, 0, 1000),
        "{r}"
    );
    let undefined = bytes(&r["undefined_task"]);
    assert_eq!(undefined[3..5], [0x34, 0x16], "{r}");
    assert_ne!(dint(&undefined, 16) & 1 << 10, 0, "{r}");
    // Map type 2: EIP.RSPMAP set with pycomm3, its values in the Class 1 response.
    assert_eq!(r["set_rspmap"], 0, "{r}");
    let rspmap = [1017u16, 1010, 797, 0, 0, 0, 0];
    let list: Vec<u8> = rspmap.iter().flat_map(|e| e.to_le_bytes()).collect();
    assert_eq!(r["rspmap"], json!({"status": 0, "data": hex(&list)}));
    assert_eq!(r["rspmap_unknown"], 0x09, "{r}");
    let dynamic = bytes(&r["dynamic_response"]);
    assert_eq!(dynamic[33], 2, "{r}");
    assert_eq!(dint(&dynamic, 36), dint(&dynamic, 8), "{r}"); // PL.FB
    assert_eq!(dint(&dynamic, 36), 1000, "{r}");
    assert_eq!(dint(&dynamic, 40), dint(&dynamic, 16), "{r}"); // DRV.MOTIONSTAT
    assert_eq!(dint(&dynamic, 44), 65_536, "{r}"); // EIP.PROFUNIT
    assert_eq!(dynamic[48..64], [0; 16], "{r}");
    // EIP.CMDMAP: MT.TPOSWND from command bytes 36-39 on the Load/Start edge.
    assert_eq!(r["set_cmdmap"], 0, "{r}");
    assert_eq!(r["cmdmap_load_complete"], 0x80, "{r}");
    let window = json!({"status": 0, "data": hex(&7i64.to_le_bytes())});
    assert_eq!(r["tposwnd_after_map"], window, "{r}");
    assert_eq!(bytes(&r["refused_map_load"])[3..5], [0x34, 0x20], "{r}");
    assert_eq!(r["tposwnd_after_refused"], window, "{r}");
    assert_eq!(bytes(&r["disabled"])[0] & ENABLED, 0, "{r}");
    assert_eq!(r["forward_close"], 0, "{r}");
    // Admission: below the minimum RPI refused (0x0112); multicast T->O accepted.
    assert_eq!(r["rpi_5ms"], 0x0112, "{r}");
    assert_eq!(r["multicast_open"], 0, "{r}");
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn kollmorgen_akd_class1_handshake_and_motion() {
    let rig = start("kollmorgen_akd_io", &[]);
    class1_scenario(&rig);
    common::finish(rig);
}

/// The explicit scenario (position mode, units at their defaults, drive disabled).
fn explicit_scenario(rig: &Rig) {
    let r = peer(
        rig,
        "kollmorgen_akd_explicit.py",
        json!({"host": BOARD_IP.to_string()}),
    );
    let ok = |k: &str, data: &str| {
        assert_eq!(
            (r[k]["status"].as_u64(), r[k]["data"].as_str()),
            (Some(0), Some(data)),
            "{k}: {r}"
        );
    };
    ok("count", "11");
    ok("list", "0102030405060708090a0b1116193a6465");
    // Class 0x24, attribute 22 and the vendor (issue 25 item 2).
    ok("supervisor_count", "06");
    ok("supervisor_list", "010203050607");
    ok("supervisor_axis", "01");
    ok("jog_velocity", &hex(&65_536i32.to_le_bytes()));
    ok("set_jog_velocity", "");
    ok("jog_velocity_after", &hex(&(-2000i32).to_le_bytes()));
    ok("vendor", &hex(&452u16.to_le_bytes()));
    // The drive's ranges: SWLS.EN 0-3, MT.NUM 0-128, MT.CNTL 3; MT.SET of a task that
    // cannot move (MT.V 0, as at power-up) refused.
    ok("mt_v_zero", "");
    ok("swls_en_3", "");
    ok("swls_en_after", "03");
    ok("mt_num_128", "");
    ok("mt_cntl_3", "");
    ok("mode", "00");
    ok("position_units", "00000100");
    ok("profile_units", "00000100");
    ok("set_target_position", "");
    ok("target_position", &hex(&(-1234i32).to_le_bytes()));
    ok("set_mode_velocity", "");
    ok("mode_after", "01");
    ok("set_profunit_param", "");
    ok("profile_units_after", &hex(&1000u32.to_le_bytes()));
    ok("set_accel_attr", "");
    ok("drv_acc_param", &hex(&5000i64.to_le_bytes()));
    ok("enable", "00");
    ok("p1_type", "c8");
    ok("p1_length", "04");
    ok("p1_value", &hex(&5_000_000u32.to_le_bytes()));
    ok("p205_length", "01");
    ok("p5_length", "08");
    ok("p5_set32", "");
    ok("p5_value", &hex(&(-9i64).to_le_bytes()));
    ok("p6_value", &hex(&(-9i32).to_le_bytes()));
    ok("set_enable", "");
    ok("home_move", "");
    // DRV.MOTIONSTAT: home found and home finished (bits 1 and 2).
    let motionstat = u32::from_str_radix(r["motionstat"]["data"].as_str().unwrap_or(""), 16)
        .map(u32::swap_bytes)
        .unwrap_or(0);
    assert_eq!(motionstat & 0b110, 0b110, "{r}");
    ok("set_disable", "");
    ok("enable_after", "00");
    for (k, status) in [
        ("read_only", 0x0E),
        ("unknown_attribute", 0x14),
        ("mode_out_of_range", 0x09),
        ("get_all", 0x08),
        ("home_move_get", 0x2C),
        ("supervisor_set", 0x0E),
        ("swls_en_4", 0x09),
        ("mt_num_129", 0x09),
        ("mt_set_empty", 0x09),
        ("mt_cntl_2", 0x09),
        ("absent_class", 0x16),
        ("absent_class_2", 0x16),
        ("p1_short", 0x13),
        ("p1_long", 0x15),
        ("p7_read_only", 0x0E),
        ("posunit_zero", 0x09),
        ("unknown_parameter", 0x16),
        ("home_move_disabled", 0x10),
    ] {
        assert_eq!(r[k]["status"].as_u64(), Some(status), "{k}: {r}");
    }
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn kollmorgen_akd_explicit_objects() {
    let rig = start("kollmorgen_akd_explicit", &[]);
    explicit_scenario(&rig);
    common::finish(rig);
}

/// DRV.NVSAVE survives a restart of the board on the same `--nv-file`, with the TCP/IP host
/// name beside it; Identity Reset type 1 erases both, so the restart after it is at the
/// parameter's default (AIN.CUTOFF 5 000 Hz) and an empty host name.
#[test]
#[ignore = "needs root: network namespace and TAP"]
fn kollmorgen_akd_nvsave_and_factory_reset_across_restarts() {
    let file = common::fresh_nv_file("kollmorgen_akd_nv.bin");
    let nv = ["--nv-file", file.to_str().unwrap()];
    let host = BOARD_IP.to_string();
    let phase = |name: &str, phase: &str| {
        let rig = start(name, &nv);
        let r = peer(
            &rig,
            "kollmorgen_akd_nv.py",
            json!({"host": host, "phase": phase, "cutoff": 1234}),
        );
        common::finish(rig);
        r
    };
    let ok = |r: &Value, k: &str| assert_eq!(r[k]["status"], 0, "{k}: {r}");
    let saved = (hex(&1234u32.to_le_bytes()), "0400616b6431".to_string());
    let r = phase("kollmorgen_akd_nv_save", "save");
    for k in ["set_cutoff", "set_host_name", "nvsave"] {
        ok(&r, k);
    }
    let seen = |r: &Value| {
        ok(r, "cutoff");
        ok(r, "host_name");
        (
            r["cutoff"]["data"].as_str().unwrap_or("").to_string(),
            r["host_name"]["data"].as_str().unwrap_or("").to_string(),
        )
    };
    assert_eq!(seen(&r), saved, "{r}");
    let r = phase("kollmorgen_akd_nv_restart", "check");
    assert_eq!(seen(&r), saved, "after a restart: {r}");
    let r = phase("kollmorgen_akd_nv_reset", "reset");
    ok(&r, "reset");
    let r = phase("kollmorgen_akd_nv_factory", "check");
    let factory = (hex(&5_000_000u32.to_le_bytes()), "0000".to_string());
    assert_eq!(seen(&r), factory, "after Reset type 1 and a restart: {r}");
}

/// Both scenarios on the QEMU board, one boot (skipped, loudly, without the ELF). Not the
/// stop scenario: the emulated board's clock catches up after the host stalls it, so its
/// timing shows the host, not the drive.
#[test]
#[ignore = "needs root and ENIP_QEMU_KOLLMORGEN_AKD_ELF"]
fn kollmorgen_akd_on_qemu() {
    let Some(elf) = host_tests::rig::qemu_elf("kollmorgen-akd") else {
        return;
    };
    let pcap = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("tap_interop")
        .join("kollmorgen_akd_qemu.pcapng");
    let rig = Rig::start_qemu(&elf, Some(&pcap)).unwrap_or_else(|e| panic!("QEMU rig: {e}"));
    for (name, scenario) in [
        ("class 1", class1_scenario as fn(&Rig)),
        ("explicit", explicit_scenario),
    ] {
        let t = std::time::Instant::now();
        scenario(&rig);
        println!("QEMU: {name} passed in {:?}", t.elapsed());
    }
    let log = rig.board_log();
    assert!(!log.contains("PANIC"), "the board panicked:\n{log}");
    common::finish(rig);
}

/// The EDS parses without a warning and declares the manual's sizes and connection.
#[test]
#[ignore = "needs the Python peers (eds-pie)"]
fn kollmorgen_akd_eds_is_clean() {
    let r = common::eds_check("kollmorgen-akd");
    assert_eq!(r["protocol"], "EtherNetIP");
    for (instance, size) in [(100, 0), (101, 64), (102, 64)] {
        assert_eq!(r["assemblies"][format!("Assem{instance}")], size, "{r}");
    }
    assert_eq!(r["connections"].as_array().map_or(0, Vec::len), 1, "{r}");
}
