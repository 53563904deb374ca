//! The Ametek 7500 PLS profile (`--profile ametek-pls`) with peers nobody here wrote:
//! pycomm3 for the explicit messages of the manual's §3.2 (classes 0xC0/0xC1), the PyPI
//! `ethernetip` package as the exclusive owner of §3.1 (output 150, input 100, configuration
//! 1) at 10 ms, and `eds-pie` for the EDS (scripts `host-tests/peers/ametek_pls_*.py`).
//!
//! Every run is captured and checked by tshark ([`common::finish`]).

use std::path::PathBuf;
use std::time::Duration;

use serde_json::{json, Value};

use crate::common;
use host_tests::peers;
use host_tests::rig::{Rig, BOARD_IP};

/// Bound for one peer program run.
const PEER_TIMEOUT: Duration = Duration::from_secs(120);
/// The RPI of the acceptance list: 10 ms.
pub(crate) const RPI_MS: u32 = 10;
/// Forward_Open timeout multiplier code 2: the watchdog is 16 x RPI.
pub(crate) const MULTIPLIER: u32 = 2;
/// The profile's name.
const PROFILE: &str = "ametek-pls";
/// Slack for the host being descheduled, and the peer's sampling, in ms.
const SLACK_MS: f64 = 150.0;

fn pcap(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("tap_interop")
        .join(format!("{name}.pcapng"))
}

/// Starts the host board with the profile and `extra` arguments, capturing into `name`.
pub(crate) fn start(name: &str, extra: &[&str]) -> Rig {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let bin = std::env::var_os("ENIP_HOST_BIN").unwrap_or("target/debug/enip-host".into());
    Rig::start_with_args(&root.join(bin), PROFILE, extra, Some(&pcap(name)))
        .unwrap_or_else(|e| panic!("rig for {name}: {e}"))
}

/// Runs the peer script `ametek_pls_<name>.py` with `input`; returns its JSON.
pub(crate) fn peer(rig: &Rig, name: &str, input: Value) -> Value {
    let script = format!("ametek_pls_{name}.py");
    let out = peers::run(rig.ns(), &script, &input, PEER_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}\nboard log:\n{}", rig.board_log()));
    println!("{script}: {out}");
    out
}

fn pls_object() -> Vec<u16> {
    let mut w = vec![0u16; 48];
    for g in 0..8 {
        w[6 * g] = 360;
    }
    w[1] = 1;
    w[2] = 1;
    w[3] = 0x0100;
    w
}

fn output_1() -> Vec<u16> {
    let mut w = vec![0u16; 26];
    w[6..10].copy_from_slice(&[2, 1, 100, 200]);
    w[12..14].copy_from_slice(&[300, 330]);
    w
}

fn output_17() -> Vec<u16> {
    let mut w = vec![0u16; 20];
    w[..4].copy_from_slice(&[1, 1, 50, 60]);
    w
}

fn inputs(edits: &[(usize, u16)]) -> Vec<u16> {
    let mut w = vec![0u16; 112];
    w[56..63].copy_from_slice(&[0b011, 0, 0, 120, 77, 0, 0]);
    edit(w, edits)
}

/// `w` with 1-based word edits.
fn edit(mut w: Vec<u16>, edits: &[(usize, u16)]) -> Vec<u16> {
    for &(i, v) in edits {
        w[i - 1] = v;
    }
    w
}

/// A broken rule: (name, attribute, words, CIP status, input words 15-17).
type Case = (&'static str, u8, Vec<u16>, u64, [u64; 3]);

/// Every validation rule of the digest broken once.
fn cases() -> Vec<Case> {
    let offsets = |mask: u16, g1: u16| edit(vec![0; 9], &[(1, mask), (2, g1)]);
    vec![
        (
            "scale factor 1",
            1,
            edit(pls_object(), &[(1, 1)]),
            9,
            [1, 1, 1],
        ),
        (
            "group 2 scale 0",
            1,
            edit(pls_object(), &[(7, 0)]),
            9,
            [1, 1, 7],
        ),
        (
            "output 1 twice",
            1,
            edit(pls_object(), &[(8, 1)]),
            9,
            [2, 1, 8],
        ),
        (
            "output 17 twice",
            1,
            edit(pls_object(), &[(9, 1)]),
            9,
            [2, 1, 9],
        ),
        (
            "input 9 twice",
            1,
            edit(pls_object(), &[(10, 0x100)]),
            9,
            [2, 1, 10],
        ),
        (
            "min speed 2049",
            1,
            edit(pls_object(), &[(5, 2049)]),
            9,
            [1, 1, 5],
        ),
        (
            "min speed mask",
            1,
            edit(pls_object(), &[(6, 2)]),
            9,
            [1, 1, 6],
        ),
        (
            "rpm end 2049",
            2,
            edit(output_1(), &[(4, 2049)]),
            9,
            [1, 2, 4],
        ),
        (
            "rpm start > end",
            2,
            edit(output_1(), &[(1, 200), (4, 100)]),
            9,
            [2, 2, 1],
        ),
        (
            "on counts",
            2,
            edit(output_1(), &[(4, 100), (2, 10), (5, 5)]),
            9,
            [2, 2, 2],
        ),
        (
            "off counts",
            2,
            edit(output_1(), &[(4, 100), (3, 10), (6, 5)]),
            9,
            [2, 2, 3],
        ),
        ("9 setpoints", 2, edit(output_1(), &[(7, 9)]), 9, [1, 2, 7]),
        ("on 360", 2, edit(output_1(), &[(9, 360)]), 9, [1, 2, 9]),
        ("off 400", 2, edit(output_1(), &[(10, 400)]), 9, [1, 2, 10]),
        (
            "setpoint 3 on 360",
            2,
            edit(output_1(), &[(7, 3), (15, 360)]),
            9,
            [1, 2, 15],
        ),
        (
            "setpoint type 5",
            2,
            edit(output_1(), &[(8, 5)]),
            9,
            [1, 2, 8],
        ),
        (
            "time-based with 2",
            2,
            edit(output_1(), &[(8, 3)]),
            9,
            [2, 2, 7],
        ),
        (
            "low speed 9 setpoints",
            18,
            edit(output_17(), &[(1, 9)]),
            9,
            [1, 18, 1],
        ),
        (
            "low speed off 360",
            18,
            edit(output_17(), &[(1, 2), (8, 360)]),
            9,
            [1, 18, 8],
        ),
        (
            "capture update 3",
            34,
            inputs(&[(57, 0b111)]),
            9,
            [1, 34, 57],
        ),
        ("input type 5", 34, inputs(&[(60, 5)]), 9, [1, 34, 60]),
        ("preset 360", 34, inputs(&[(61, 360)]), 9, [1, 34, 61]),
        (
            "mask outside group",
            34,
            inputs(&[(60, 20), (58, 3)]),
            9,
            [2, 34, 58],
        ),
        ("add-on rpm 2049", 35, vec![2049, 0, 1], 9, [1, 35, 1]),
        ("home 360", 36, offsets(1, 360), 9, [1, 36, 2]),
        ("control code 9", 37, vec![9, 0], 9, [1, 37, 1]),
        ("restore, nothing saved", 37, vec![3, 0], 0x19, [4, 37, 1]),
        ("encoder on resolver", 38, vec![1000, 1], 0x0C, [2, 38, 1]),
    ]
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn ametek_pls_attributes_and_validation() {
    let rig = start("ametek_pls_explicit", &[]);
    attributes_and_validation(&rig);
    common::finish(rig);
}

/// Sizes, a valid configuration read back, every rule broken once (status and words 15-17
/// over Class 1, latched until the Acknowledge edge).
fn attributes_and_validation(rig: &Rig) {
    let cases = cases();
    let input = json!({
        "host": BOARD_IP.to_string(), "rpi_ms": RPI_MS, "multiplier": MULTIPLIER,
        "cases": cases.iter().map(|(n, a, w, _, _)| json!({"name": n, "attribute": a, "words": w}))
            .collect::<Vec<_>>(),
    });
    let r = peer(rig, "explicit", input);
    for (a, size) in [(1, 4), (2, 96), (3, 48)] {
        assert_eq!(r["sizes"][format!("C0/{a}")], json!([0, size]), "{r}");
    }
    for a in 1..=38 {
        let size = match a {
            1 => 96,
            2..=17 => 52,
            18..=33 => 40,
            34 => 224,
            35 => 6,
            36 => 18,
            _ => 4,
        };
        assert_eq!(r["sizes"][format!("C1/{a}")], json!([0, size]), "C1/{a}");
    }
    for a in ["1", "2", "18", "34", "35"] {
        assert_eq!(r["writes"][a], 0, "write {a}: {r}");
        assert_eq!(r["readback"][a], true, "readback {a}: {r}");
    }
    for other in r["others"].as_array().unwrap() {
        assert_eq!(other[1], 0, "Set of attribute {}", other[0]);
    }
    assert_eq!(r["forward_open"], 0, "{r}");
    assert_eq!(r["error_at_open"], json!([0, 0, 0]));
    let results = r["cases"].as_array().unwrap();
    assert_eq!(results.len(), cases.len());
    for ((name, _, _, status, words), got) in cases.iter().zip(results) {
        assert_eq!(got["status"], *status, "{name}: {got}");
        assert_eq!(got["words"], json!(words), "{name}: {got}");
        assert_eq!(got["unchanged"], true, "{name}: {got}");
        assert_eq!(got["valid"], 0, "{name}: {got}");
        assert_eq!(
            got["after_valid"],
            json!(words),
            "{name}: a valid write cleared it"
        );
        assert_eq!(
            got["cleared"], true,
            "{name}: the acknowledge edge did not clear"
        );
    }
    assert_eq!(r["forward_close"], 0, "{r}");
}

/// Output 1 changed state at these times (ms) inside `from..to`.
fn changes_between(v: &Value, from: f64, to: f64) -> usize {
    v["changes"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(Value::as_f64)
        .filter(|t| (from..to).contains(t))
        .count()
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn ametek_pls_class1_outputs_forces_add_on_and_inputs() {
    let rig = start("ametek_pls_io", &[]);
    outputs_forces_add_on_and_inputs(&rig);
    common::finish(rig);
}

/// The limit switch over Class 1 at 10 ms.
fn outputs_forces_add_on_and_inputs(rig: &Rig) {
    let r = peer(
        rig,
        "io",
        json!({"host": BOARD_IP.to_string(), "rpi_ms": RPI_MS, "multiplier": MULTIPLIER}),
    );
    assert_eq!(r["writes"], json!([0, 0, 0]), "{r}");
    assert_eq!(r["forward_open"], 0, "{r}");
    // Error words 0, no resolver fault, positions below the scale factor.
    let w = &r["words_at_open"];
    assert_eq!((w[9].as_u64(), w[14].as_u64()), (Some(0), Some(0)), "{r}");
    assert!((0..8).all(|g| w[g].as_u64().unwrap() < 360), "{r}");
    let expected = json!([
        [0, 150, 1, 0],
        [0, 250, 0, 0],
        [0, 315, 1, 0],
        [0, 55, 0, 1]
    ]);
    assert_eq!(r["positions"], expected, "{r}");
    assert_eq!(r["force_on_at_250"], 1, "{r}");
    assert_eq!(r["force_off_at_150"], 0, "{r}");
    assert_eq!(r["group_on_over_force_off"], 1 | 1 << 16, "{r}");
    assert_eq!(r["group_off_over_force_on"], 0, "{r}");
    assert_eq!(r["word4_forces_17"], 1 << 16, "{r}");
    assert_eq!(r["run_enable_0"], 0, "{r}");
    assert_eq!(r["run_enable_1"], 1, "{r}");
    // Timed add-on test: fires within its 1.5 s, then quiet while the bit stays 1.
    assert_eq!(
        (r["addon_write"].as_u64(), r["before_addon"].as_u64()),
        (Some(0), Some(0))
    );
    let t = &r["timed"];
    let start = t["start"].as_f64().unwrap();
    assert!(
        changes_between(t, start, start + 1500.0 + SLACK_MS) >= 2,
        "{t}"
    );
    let quiet = changes_between(t, start + 1500.0 + SLACK_MS, t["end"].as_f64().unwrap());
    assert_eq!(quiet, 0, "output 1 changed after the test's time: {t}");
    // Held test (time 0): toggles beyond 2 s, stops within 0.5 s of the clear.
    let h = &r["held"];
    let (start, clear) = (h["start"].as_f64().unwrap(), h["clear"].as_f64().unwrap());
    assert!(changes_between(h, start + 2000.0, clear) >= 1, "{h}");
    let late = changes_between(h, clear + 500.0, h["end"].as_f64().unwrap());
    assert_eq!(late, 0, "{h}");
    assert_eq!(h["final"], 0, "{h}");
    // Soft input 9, reset to preset group 77 on rising edges only.
    assert_eq!(r["input_write"], 0, "{r}");
    assert_eq!(r["preset_on_edge"], true, "{r}");
    assert_eq!(r["held_high"], 150, "{r}");
    assert_eq!(r["falling"], 150, "{r}");
    assert_eq!(r["second_edge"], true, "{r}");
    assert_eq!(r["input_status_9"], json!([150, 150, 3]), "{r}");
    let offsets = r["offsets"].as_array().unwrap();
    assert_eq!(
        offsets[16], offsets[0],
        "input 9's offset is group 1's: {r}"
    );
    assert_eq!(r["forward_close"], 0, "{r}");
}

/// True inside on (inclusive) .. off (exclusive).
fn inside(pos: u64, on: u64, off: u64) -> bool {
    (on..off).contains(&pos)
}

/// A moving resolver (`--pls-rpm 60`): every T->O sample is consistent with the windows of
/// outputs 1 (100-200, 300-330) and 17 (50-60), and the positions advance at 60 RPM.
#[test]
#[ignore = "needs root: network namespace and TAP"]
fn ametek_pls_moving_resolver() {
    let rig = start("ametek_pls_moving", &["--pls-rpm", "60"]);
    moving(&rig);
    common::finish(rig);
}

/// The emulated board built with `ENIP_PLS_RPM=60` (its ELF in
/// `ENIP_QEMU_AMETEK_PLS_MOVING_ELF`): the same moving-resolver scenario as on the host
/// board (skipped, loudly, without the ELF).
#[test]
#[ignore = "needs root and ENIP_QEMU_AMETEK_PLS_MOVING_ELF"]
fn ametek_pls_moving_resolver_on_qemu() {
    let var = "ENIP_QEMU_AMETEK_PLS_MOVING_ELF";
    let Some(elf) = std::env::var_os(var) else {
        eprintln!("SKIPPED: set {var} to an ametek-pls QEMU ELF built with ENIP_PLS_RPM=60");
        return;
    };
    let rig = Rig::start_qemu(
        std::path::Path::new(&elf),
        Some(&pcap("ametek_pls_qemu_moving")),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    moving(&rig);
    let log = rig.board_log();
    assert!(!log.contains("PANIC"), "the board panicked:\n{log}");
    common::finish(rig);
}

/// Every T->O sample of 3 s consistent with the windows; the resolver at 60 RPM.
fn moving(rig: &Rig) {
    let input = json!({"host": BOARD_IP.to_string(), "rpi_ms": RPI_MS,
                       "multiplier": MULTIPLIER, "seconds": 3.0});
    let r = peer(rig, "moving", input);
    assert_eq!(r["writes"], json!([0, 0, 0]), "{r}");
    assert_eq!(r["forward_open"], 0, "{r}");
    let samples = r["samples"].as_array().unwrap();
    // 3 s at 10 ms: about 300 datagrams, each with a new position.
    assert!(samples.len() >= 200, "{} samples", samples.len());
    let (mut on1, mut on17) = (0, 0);
    for s in samples {
        let v: Vec<u64> = s.as_array().unwrap()[1..]
            .iter()
            .map(|x| x.as_u64().unwrap())
            .collect();
        let (pos, rpm, low, high) = (v[0], v[1], v[2], v[3]);
        assert_eq!(rpm, 60, "{s}");
        assert!(pos < 360, "{s}");
        assert_eq!(
            low & 1 == 1,
            inside(pos, 100, 200) || inside(pos, 300, 330),
            "{s}"
        );
        assert_eq!(high & 1 == 1, inside(pos, 50, 60), "{s}");
        on1 += usize::from(low & 1 == 1);
        on17 += usize::from(high & 1 == 1);
    }
    // 130 and 10 of 360 counts: about 36 % and 3 % of the samples.
    let n = samples.len() as f64;
    assert!(
        (0.30..0.42).contains(&(on1 as f64 / n)),
        "output 1 on in {on1} of {n}"
    );
    assert!(
        (0.01..0.06).contains(&(on17 as f64 / n)),
        "output 17 on in {on17} of {n}"
    );
    // The position advances 3.6 counts per 10 ms (6 revolutions in 3 s).
    let first = &samples[0];
    let last = &samples[samples.len() - 1];
    let dt = last[0].as_f64().unwrap() - first[0].as_f64().unwrap();
    assert!(dt > 2500.0, "{dt}");
    assert_eq!(r["forward_close"], 0, "{r}");
}

/// Both scenarios on the QEMU board, one boot (skipped, loudly, without the ELF).
#[test]
#[ignore = "needs root and ENIP_QEMU_AMETEK_PLS_ELF"]
fn ametek_pls_on_qemu() {
    let Some(elf) = host_tests::rig::qemu_elf("ametek-pls") else {
        return;
    };
    let rig =
        Rig::start_qemu(&elf, Some(&pcap("ametek_pls_qemu"))).unwrap_or_else(|e| panic!("{e}"));
    attributes_and_validation(&rig);
    outputs_forces_add_on_and_inputs(&rig);
    let log = rig.board_log();
    assert!(!log.contains("PANIC"), "the board panicked:\n{log}");
    common::finish(rig);
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn ametek_pls_program_control_survives_a_restart() {
    let file = common::fresh_nv_file("ametek_pls_nvram.bin");
    let nvram = file.to_str().unwrap();
    let rig = start("ametek_pls_nvram_save", &["--nv-file", nvram]);
    let r = peer(
        &rig,
        "nvram",
        json!({"host": BOARD_IP.to_string(), "phase": "save"}),
    );
    assert_eq!(r["writes"], json!([0, 0, 0, 0]), "{r}");
    assert_eq!(
        (r["save"].as_u64(), r["change"].as_u64()),
        (Some(0), Some(0))
    );
    assert_ne!(r["changed"]["2"], r["saved"]["2"], "{r}");
    assert_eq!(r["restore"], 0, "{r}");
    assert_eq!(r["restored"], r["saved"], "{r}");
    assert_eq!(r["restored"], r["expected"], "{r}");
    assert_eq!(r["control_readback"], json!([3, 0]));
    assert_eq!(r["offsets"][0], 150, "{r}");
    common::finish(rig);
    // A restart of the board with the same file: the saved program and offset come back.
    let rig = start("ametek_pls_nvram_restart", &["--nv-file", nvram]);
    let r = peer(
        &rig,
        "nvram",
        json!({"host": BOARD_IP.to_string(), "phase": "check"}),
    );
    assert_eq!(r["restored"], r["expected"], "{r}");
    assert_eq!(r["offsets"][0], 150, "{r}");
    common::finish(rig);
}

/// The EDS parses without a warning and declares the manual's sizes and connections.
#[test]
#[ignore = "needs the Python peers (eds-pie)"]
fn ametek_pls_eds_is_clean() {
    let r = common::eds_check("ametek-pls");
    assert_eq!(r["protocol"], "EtherNetIP");
    for (instance, size) in [(1, 0), (100, 34), (150, 14)] {
        assert_eq!(r["assemblies"][format!("Assem{instance}")], size, "{r}");
    }
    let connections = r["connections"].as_array().map_or(0, Vec::len);
    assert_eq!(connections, 3, "{r}");
}
