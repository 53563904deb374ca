//! The Parker IPA / ACR9000 profile (`--profile parker-ipa`) replaying its manual's examples
//! with peers nobody here wrote: pycomm3 (UCMM and Class 3) for classes 0x64/0x65 and every
//! Table 8 error and for the jog command and the binary commands, cpppo for the "P..." tag
//! services, the PyPI `ethernetip` package for
//! Class 1 (scripts `host-tests/peers/parker_ipa_*.py`), and eds-pie for the EDS. The same
//! scenarios run on the QEMU board ([`parker_ipa_on_qemu`], one boot) when
//! `ENIP_QEMU_PARKER_IPA_ELF` names an `enip-qemu-mps2` ELF built with the parker-ipa profile.

use std::path::PathBuf;
use std::time::Duration;

use serde_json::{json, Value};

use crate::common;
use crate::position_servo::pcap;
use host_tests::peers;
use host_tests::rig::{Rig, BOARD_IP};

/// Bound for one peer program run.
const PEER_TIMEOUT: Duration = Duration::from_secs(90);
/// The RPI of the Class 1 scenario (the manual's CIP report: every 10 ms).
const RPI_MS: u32 = 10;
/// The profile's name.
const PROFILE: &str = "parker-ipa";

fn start(name: &str) -> Rig {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let bin = std::env::var_os("ENIP_HOST_BIN").unwrap_or("target/debug/enip-host".into());
    Rig::start(&root.join(bin), PROFILE, Some(&pcap(name)))
        .unwrap_or_else(|e| panic!("rig for {name}: {e}"))
}

/// Runs `parker_ipa_<name>.py` with `input`; returns its JSON.
fn peer(rig: &Rig, name: &str, input: Value) -> Value {
    let script = format!("parker_ipa_{name}.py");
    let out = peers::run(rig.ns(), &script, &input, PEER_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}\nboard log:\n{}", rig.board_log()));
    println!("{script}: {out}");
    out
}

fn hex(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02x}")).collect()
}

fn floats(v: &[f32]) -> String {
    hex(&v.iter().flat_map(|f| f.to_le_bytes()).collect::<Vec<_>>())
}

fn longs(v: &[i32]) -> String {
    hex(&v.iter().flat_map(|f| f.to_le_bytes()).collect::<Vec<_>>())
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn parker_ipa_manual_examples_with_pycomm3() {
    let rig = start("parker_ipa_explicit");
    explicit(&rig);
    common::finish(rig);
}

/// The manual's examples and Table 8 with pycomm3, UCMM and Class 3 (on a fresh board).
fn explicit(rig: &Rig) {
    let r = peer(rig, "explicit", json!({"host": BOARD_IP.to_string()}));
    let ok = |k: &str, data: &str| {
        assert_eq!(
            (r[k]["status"].as_u64(), r[k]["data"].as_str()),
            (Some(0), Some(data)),
            "{k}: {r}"
        );
    };
    ok("fig4_write", "");
    assert_eq!(r["fig4_readback"], json!([15.0, 150.0, 125.0, 625.0]));
    ok("fig6_read", "200030612000306100005000");
    ok("fig8_and_or", "");
    assert_eq!(r["fig8_result"], json!([0x12345655]));
    assert_eq!(r["p23_long"], json!([1234]));
    ok("fig10_group", &floats(&[10.5, 11.5, 12.5, 13.5]));
    let individual: Vec<i32> = serde_json::from_value(r["individual_0x30_2"].clone()).unwrap();
    ok("group_0x30_2", &longs(&individual));
    ok("no_attribute", "200030612000306100005000");
    ok("attribute_7", "200030612000306100005000");
    for (k, status) in [
        ("case1_get_attr", 0x08),
        ("case1_0x55", 0x08),
        ("case1_0x4c_class_path", 0x08),
        ("case1_0x50_on_group", 0x08),
        ("case2_binary_ucmm", 0x10),
        ("case3_read_longs_17", 0x20),
        ("case3_read_floats_17", 0x20),
        ("case4_write_longs_17", 0x15),
        ("case4_write_floats_17", 0x15),
        ("case5_and_or_4", 0x13),
        ("case5_and_or_0", 0x13),
        ("case6_block_0", 0x20),
        ("case6_block_9", 0x20),
        ("case7_group_0x80", 0x05),
        ("case7_group_0xbf", 0x05),
        ("unknown_p10", 0x05),
    ] {
        assert_eq!(r[k]["status"].as_u64(), Some(status), "{k}: {}", r[k]);
    }
    assert_eq!(r["case4_unchanged"], json!([0, 0.0]));
    assert_eq!(r["case5_unchanged"], json!([0x12345655]));
    ok("c3_binary", "");
    assert_eq!(r["c3_binary_value"], json!([5]), "binary Set Long ran: {r}");
    ok("c3_read", "200030612000306100005000");
    assert_eq!(
        r["c3_stream"],
        json!([2]),
        "P37424 with a Class 3 connection"
    );
    assert!(r["c3_status"][4].as_i64() >= Some(1), "P37428: {r}");
    ok("identity_vendor", "6c02");
    ok("identity_name", &format!("0e{}", hex(b"IPA Controller")));
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn parker_ipa_tags_with_cpppo() {
    let rig = start("parker_ipa_cpppo");
    tags(&rig);
    common::finish(rig);
}

/// cpppo's Read/Write Tag on "P..." names, checked against class 0x64.
fn tags(rig: &Rig) {
    let r = peer(rig, "cpppo", json!({"host": BOARD_IP.to_string()}));
    let c = &r["cpppo"];
    assert_eq!(c[0]["value"], json!([7, -8, 9]), "{r}");
    for i in 1..4 {
        assert_eq!(c[i]["status"], json!(0), "op {i}: {r}");
    }
    assert_eq!(c[4]["value"], json!([99]), "a float read as DINT: {r}");
    assert_eq!(c[5]["status"], json!(0));
    assert_eq!(c[6]["status"], json!(0));
    assert_eq!(c[7]["status"], json!(0x20), "17 elements: {r}");
    assert_eq!(c[8]["status"], json!(0x05), "P10: {r}");
    assert_eq!(r["p4112_by_0x53"], json!([7, -8, 9]));
    assert_eq!(r["p4100_by_0x53"], json!([0x0BADCAFE]));
    assert_eq!(r["p39001_by_0x53"], json!([77]));
    assert_eq!(r["p39201_by_0x51"], json!([-3.0]));
    assert_eq!(r["p38920_by_0x53"], json!([1, 2, 3, 4]));
    assert_eq!(r["p39300_by_0x51"], json!([1.5, -2.25]));
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn parker_ipa_class1_with_ethernetip() {
    let rig = start("parker_ipa_class1");
    class1(&rig, 10.0);
    common::finish(rig);
}

/// Class 1 with `ethernetip`; `slack_ms` allows for a board descheduled by the host.
fn class1(rig: &Rig, slack_ms: f64) {
    let r = peer(
        rig,
        "class1",
        json!({"host": BOARD_IP.to_string(), "rpi_ms": RPI_MS}),
    );
    assert_eq!(r["configure"], json!(0), "{r}");
    assert_eq!(r["open"], json!(0), "{r}");
    assert_eq!(r["t_o_initial"], json!(true), "{r}");
    assert_eq!(r["t_o_tail_zero"], json!(true), "{r}");
    assert_eq!(r["o_t_longs"], json!([9, 8, 7]), "{r}");
    assert_eq!(r["o_t_reals_as_longs"], json!([1, -2]), "{r}");
    let delay = r["write_to_t_o_ms"]
        .as_f64()
        .expect("the write shows in T->O");
    assert!(
        delay <= 2.0 * f64::from(RPI_MS) + slack_ms,
        "{delay} ms: {r}"
    );
    let s = &r["status_open"];
    assert_eq!(s[9], json!(1), "P37433: {r}");
    assert_eq!(
        s[5].as_i64().map(|v| v as u32),
        Some(0xC612_0001),
        "P37429: {r}"
    );
    assert_eq!(
        (s[7].clone(), s[8].clone()),
        (json!(RPI_MS), json!(RPI_MS)),
        "{r}"
    );
    assert!(s[4].as_i64() >= Some(1) && s[6].as_i64() >= Some(1), "{r}");
    assert!(s[1].as_i64() >= Some(1), "P37425 counts O->T: {r}");
    assert_eq!(r["second_open"], json!(0x0106), "{r}");
    assert_eq!(r["first_still_runs"], json!(true), "{r}");
    assert_eq!(r["status_after_second"], json!([1]), "{r}");
    assert_eq!(
        r["client_after_second"],
        json!([s[5], s[6]]),
        "P37429/P37430 keep the running connection's client: {r}"
    );
    assert_eq!(r["status_closed"], json!([0]), "{r}");
    for (k, status) in [("error2", 2), ("error3", 3), ("error4", 4), ("error5", 5)] {
        assert_eq!(r[k]["open"], json!(0x0110), "{k}: {r}");
        assert_eq!(r[k]["status"][0], json!(status), "{k}: {r}");
    }
    assert_eq!(r["error7_example2"]["open"], json!(0x0110), "{r}");
    assert_eq!(
        r["error7_example2"]["status"],
        json!([7, 4, 1, 10, 8]),
        "{r}"
    );
    for k in ["rpi_ot_half_ms", "rpi_to_half_ms"] {
        assert!(matches!(r[k].as_u64(), Some(0x0111 | 0x0112)), "{k}: {r}");
    }
    assert_eq!(r["rpi_1ms"], json!(0), "{r}");
    assert_eq!(r["status_1ms"], json!([1, 1, 1]), "{r}");
    assert_eq!(r["multicast_open"], json!(0), "{r}");
    assert_eq!(r["multicast_status"], json!([1]), "{r}");
    assert_eq!(r["timeout_open"], json!(0), "{r}");
    assert_eq!(r["timeout_status"], json!([0]), "{r}");
    let closed = r["timeout_closed_ms"].as_f64().unwrap_or(f64::MAX);
    assert!(closed < 3000.0, "watchdog after {closed} ms: {r}");
    assert_eq!(r["timeout_reopen"], json!(0), "{r}");
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn parker_ipa_jog_and_binary_with_pycomm3() {
    let rig = start("parker_ipa_motion");
    motion(&rig);
    common::finish(rig);
}

/// The axes move only on a jog command; the binary commands of Table 7 run or are refused.
fn motion(rig: &Rig) {
    const FLAGS: i64 = 1_630_535_712;
    let r = peer(rig, "motion", json!({"host": BOARD_IP.to_string()}));
    assert_eq!(r["fig4_write"], json!(0), "{r}");
    assert_eq!(
        r["fig4_positions"][0], r["fig4_positions"][1],
        "figure 4 moved: {r}"
    );
    assert_eq!(r["fig4_flags"], json!([FLAGS]), "{r}");
    assert_eq!(r["set_jog"], json!(0), "{r}");
    assert_eq!(
        r["jog_flags"],
        json!([FLAGS | 0b101 << 16]),
        "jog fwd + active: {r}"
    );
    // 15 units/s for about 0.5 s.
    let moved = r["jog_position"][0].as_i64().unwrap_or(0);
    assert!((4..=12).contains(&moved), "{moved}: {r}");
    assert_eq!(r["clr_jog"], json!(0), "{r}");
    let stopped = &r["stopped_positions"];
    assert_eq!(stopped[0], stopped[1], "still moving after CLR: {r}");
    assert_eq!(r["stopped_flags"], json!([FLAGS]), "{r}");
    assert_eq!(r["set_long_ieee"], json!(0), "{r}");
    assert_eq!(r["set_long_value"], json!([-7]), "{r}");
    assert_eq!(r["set_ieee_value"], json!([2.5]), "{r}");
    assert_eq!(r["mask"], json!(0), "{r}");
    assert_eq!(r["mask_value"], json!([1]), "{r}");
    assert_eq!(r["refused"], json!([0x08, 0x08, 0x13, 0x20]), "{r}");
    assert_eq!(
        r["refused_value"],
        json!([-7]),
        "a refused request ran: {r}"
    );
    assert_eq!(r["ucmm"], json!(0x10), "{r}");
}

/// A named scenario.
type Scenario = (&'static str, fn(&Rig));

/// Every scenario on the QEMU board, one boot (skipped, loudly, without the ELF).
#[test]
#[ignore = "needs root and ENIP_QEMU_PARKER_IPA_ELF"]
fn parker_ipa_on_qemu() {
    let Some(elf) = host_tests::rig::qemu_elf("parker-ipa") else {
        return;
    };
    let rig =
        Rig::start_qemu(&elf, Some(&pcap("parker_ipa_qemu"))).unwrap_or_else(|e| panic!("{e}"));
    let scenarios: [Scenario; 4] = [
        ("manual examples (pycomm3)", explicit),
        ("jog and binary commands (pycomm3)", motion),
        ("tags (cpppo)", tags),
        ("Class 1 (ethernetip)", |rig| class1(rig, 40.0)),
    ];
    for (name, scenario) in scenarios {
        let start = std::time::Instant::now();
        scenario(&rig);
        println!("QEMU: {name} passed in {:?}", start.elapsed());
    }
    let log = rig.board_log();
    assert!(!log.contains("PANIC"), "the board panicked:\n{log}");
    common::finish(rig);
}

/// The EDS parses with eds-pie without a warning and declares the RSLogix set-up (p.11).
/// The checker script is the PositionServo's (it reads any EDS path).
#[test]
#[ignore = "needs the Python peers (eds-pie)"]
fn parker_ipa_eds_is_clean() {
    let r = common::eds_check("parker-ipa");
    assert_eq!(r["protocol"], "EtherNetIP");
    for (instance, size) in [(3, 0), (101, 400), (102, 400)] {
        assert_eq!(r["assemblies"][format!("Assem{instance}")], size, "{r}");
    }
    assert_eq!(r["connections"].as_array().map_or(0, Vec::len), 1, "{r}");
}
