//! Explicit messaging with independent clients: pycomm3 (UCMM, and once through
//! Unconnected_Send) and cpppo (direct UCMM and its default Unconnected_Send route path).

use std::time::Duration;

use serde_json::{json, Value};

use crate::common::{self, DEVICE_TYPE, NAME, PRODUCT_CODE, REVISION, SERIAL, STATUS, VENDOR};
use host_tests::peers;
use host_tests::rig::BOARD_IP;

/// Bound for one peer program run.
const PEER_TIMEOUT: Duration = Duration::from_secs(60);

/// 32 distinct bytes for the output assembly.
fn pattern(seed: u8) -> Vec<u8> {
    (0..32u8)
        .map(|i| i.wrapping_mul(7).wrapping_add(seed))
        .collect()
}

fn hex(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02x}")).collect()
}

/// A pycomm3 request description (see `peers/pycomm3_explicit.py`).
fn req(name: &str, service: u8, class: u16, instance: u16, attribute: Option<u8>) -> Value {
    json!({"name": name, "service": service, "class": class, "instance": instance,
           "attribute": attribute, "data": ""})
}

fn with_data(mut r: Value, data: &[u8]) -> Value {
    r["data"] = json!(hex(data));
    r
}

fn get(name: &str, class: u16, instance: u16, attribute: u8) -> Value {
    req(name, 0x0E, class, instance, Some(attribute))
}

fn set(name: &str, class: u16, instance: u16, attribute: u8, data: &[u8]) -> Value {
    with_data(req(name, 0x10, class, instance, Some(attribute)), data)
}

/// The pycomm3 result named `name`: its general status and reply data.
fn result<'a>(out: &'a Value, name: &str) -> (i64, Vec<u8>, &'a Value) {
    let r = out["results"]
        .as_array()
        .and_then(|a| a.iter().find(|r| r["name"] == name))
        .unwrap_or_else(|| panic!("no result {name} in {out}"));
    let status = r["status"]
        .as_i64()
        .unwrap_or_else(|| panic!("{name}: no reply: {r}"));
    let data = r["data"].as_str().unwrap_or_default();
    let bytes = (0..data.len() / 2)
        .map(|i| u8::from_str_radix(&data[2 * i..2 * i + 2], 16).expect("hex"))
        .collect();
    (status, bytes, r)
}

#[track_caller]
fn ok(out: &Value, name: &str) -> Vec<u8> {
    let (status, data, r) = result(out, name);
    assert_eq!(status, 0, "{name}: {r}");
    data
}

#[track_caller]
fn status(out: &Value, name: &str) -> i64 {
    result(out, name).0
}

fn identity_all() -> Vec<u8> {
    let mut v = Vec::new();
    for w in [VENDOR, DEVICE_TYPE, PRODUCT_CODE] {
        v.extend_from_slice(&w.to_le_bytes());
    }
    v.extend_from_slice(&REVISION);
    v.extend_from_slice(&STATUS.to_le_bytes());
    v.extend_from_slice(&SERIAL.to_le_bytes());
    v.push(NAME.len() as u8);
    v.extend_from_slice(NAME.as_bytes());
    v
}

#[test]
#[ignore = "needs root, tshark and the Python peers"]
fn pycomm3_explicit_messaging() {
    let rig = common::start("pycomm3_explicit_messaging");
    let (a, b) = (pattern(1), pattern(100));
    // The one request that goes through Unconnected_Send (port 1, link 0).
    let mut ucs = get("identity.ucs", 1, 1, 7);
    ucs["route"] = json!("1/0");
    let mut requests: Vec<Value> = (1..=7)
        .map(|i| get(&format!("identity.{i}"), 1, 1, i))
        .collect();
    requests.extend([
        req("identity.all", 0x01, 1, 1, None),
        ucs,
        get("tcpip.1", 0xF5, 1, 1),
        get("tcpip.5", 0xF5, 1, 5),
        get("tcpip.8", 0xF5, 1, 8),
        get("tcpip.9", 0xF5, 1, 9),
        get("tcpip.13", 0xF5, 1, 13),
        get("link.1", 0xF6, 1, 1),
        get("link.2", 0xF6, 1, 2),
        get("link.3", 0xF6, 1, 3),
        get("asm100.size", 4, 100, 4),
        set("asm150.set", 4, 150, 3, &a),
        get("asm150.get", 4, 150, 3),
        get("asm100.get", 4, 100, 3),
        set("asm154.set", 4, 154, 3, &b),
        get("asm154.get", 4, 154, 3),
        set("asm100.set", 4, 100, 3, &b),
        set("asm150.short", 4, 150, 3, &a[..31]),
        set("asm150.long", 4, 150, 3, &[a.as_slice(), &[0]].concat()),
        req("identity.svc4b", 0x4B, 1, 1, None),
        get("class77", 0x77, 1, 1),
        get("identity.inst2", 1, 2, 1),
        get("identity.attr99", 1, 1, 99),
        get("asm150.after", 4, 150, 3),
    ]);
    let input = json!({"host": BOARD_IP.to_string(), "requests": requests});
    let out = peers::run(rig.ns(), "pycomm3_explicit.py", &input, PEER_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}\nboard log:\n{}", rig.board_log()));

    assert_eq!(ok(&out, "identity.1"), VENDOR.to_le_bytes());
    assert_eq!(ok(&out, "identity.2"), DEVICE_TYPE.to_le_bytes());
    assert_eq!(ok(&out, "identity.3"), PRODUCT_CODE.to_le_bytes());
    assert_eq!(ok(&out, "identity.4"), REVISION);
    assert_eq!(ok(&out, "identity.5"), STATUS.to_le_bytes());
    assert_eq!(ok(&out, "identity.6"), SERIAL.to_le_bytes());
    let name = [&[NAME.len() as u8], NAME.as_bytes()].concat();
    assert_eq!(ok(&out, "identity.7"), name);
    assert_eq!(ok(&out, "identity.all"), identity_all());
    assert_eq!(ok(&out, "identity.ucs"), name);

    assert_eq!(ok(&out, "tcpip.1"), 1u32.to_le_bytes());
    let iface = ok(&out, "tcpip.5");
    assert_eq!(iface.len(), 22, "5 addresses and an empty domain name");
    assert_eq!(iface[..4], u32::from(BOARD_IP).to_le_bytes(), "ip");
    assert_eq!(iface[4..8], 0xFFFF_FF00u32.to_le_bytes(), "netmask /24");
    assert_eq!(ok(&out, "tcpip.8"), [1], "default TTL");
    let mcast = ok(&out, "tcpip.9");
    assert_eq!(mcast.len(), 8);
    assert_eq!(mcast[..4], [0, 0, 1, 0], "default allocation, one address");
    assert_eq!(ok(&out, "tcpip.13"), 120u16.to_le_bytes());
    assert_eq!(ok(&out, "link.1").len(), 4, "interface speed");
    let flags = ok(&out, "link.2");
    assert_eq!(flags.len(), 4);
    assert_eq!(flags[0] & 1, 1, "link up");
    let mac = ok(&out, "link.3");
    assert_eq!(mac.len(), 6, "MAC");
    assert_eq!(mac[0] & 1, 0, "unicast MAC");

    assert_eq!(ok(&out, "asm100.size"), 32u16.to_le_bytes());
    assert!(ok(&out, "asm150.set").is_empty());
    assert_eq!(ok(&out, "asm150.get"), a, "output assembly reads back");
    assert_eq!(ok(&out, "asm100.get"), a, "outputs are copied to inputs");
    ok(&out, "asm154.set");
    assert_eq!(ok(&out, "asm154.get"), b);
    assert_eq!(
        status(&out, "asm100.set"),
        0x0E,
        "input assembly is read-only"
    );
    assert_eq!(status(&out, "asm150.short"), 0x13, "not enough data");
    assert_eq!(status(&out, "asm150.long"), 0x15, "too much data");
    assert_eq!(
        status(&out, "identity.svc4b"),
        0x08,
        "service not supported"
    );
    assert_eq!(status(&out, "class77"), 0x05, "unknown class");
    assert_eq!(status(&out, "identity.inst2"), 0x16, "unknown instance");
    assert_eq!(status(&out, "identity.attr99"), 0x14, "unknown attribute");
    assert_eq!(ok(&out, "asm150.after"), a, "failed sets change nothing");
    common::finish(rig);
}

/// A cpppo op (see `peers/cpppo_explicit.py`).
fn op(name: &str, path: &str, typ: &str, values: Option<&[u8]>) -> Value {
    json!({"name": name, "path": path, "type": typ, "values": values})
}

/// Runs the cpppo peer with `route` and checks identity and the output assembly round trip.
fn cpppo_round(rig: &host_tests::rig::Rig, route: &str, data: &[u8]) {
    let ops = vec![
        op("vendor", "@1/1/1", "UINT", None),
        op("type", "@1/1/2", "UINT", None),
        op("product", "@1/1/3", "UINT", None),
        op("revision", "@1/1/4", "USINT", None),
        op("status", "@1/1/5", "UINT", None),
        op("serial", "@1/1/6", "UDINT", None),
        op("name", "@1/1/7", "SSTRING", None),
        op("write", "@4/150/3", "USINT", Some(data)),
        op("read", "@4/150/3", "USINT", None),
        op("inputs", "@4/100/3", "USINT", None),
    ];
    let input = json!({"host": BOARD_IP.to_string(), "route": route, "ops": ops});
    let out = peers::run(rig.ns(), "cpppo_explicit.py", &input, PEER_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}\nboard log:\n{}", rig.board_log()));
    let value = |name: &str| {
        let r = out["results"]
            .as_array()
            .and_then(|a| a.iter().find(|r| r["name"] == name))
            .unwrap_or_else(|| panic!("{route}: no result {name} in {out}"));
        assert_eq!(r["status"], 0, "{route} {name}: {r}");
        r["value"].clone()
    };
    assert_eq!(value("vendor"), json!([VENDOR]), "{route}");
    assert_eq!(value("type"), json!([DEVICE_TYPE]), "{route}");
    assert_eq!(value("product"), json!([PRODUCT_CODE]), "{route}");
    assert_eq!(value("revision"), json!(REVISION), "{route}");
    assert_eq!(value("status"), json!([STATUS]), "{route}");
    assert_eq!(value("serial"), json!([SERIAL]), "{route}");
    assert_eq!(value("name"), json!([NAME]), "{route}");
    assert_eq!(value("write"), json!(true), "{route}");
    assert_eq!(value("read"), json!(data), "{route}");
    assert_eq!(value("inputs"), json!(data), "{route}");
    assert_eq!(
        out["identity"],
        json!(NAME),
        "{route}: cpppo's ListIdentity"
    );
}

#[test]
#[ignore = "needs root, tshark and the Python peers"]
fn cpppo_explicit_messaging() {
    let rig = common::start("cpppo_explicit_messaging");
    cpppo_round(&rig, "direct", &pattern(3));
    cpppo_round(&rig, "default", &pattern(50));
    common::finish(rig);
}

#[test]
#[ignore = "needs root, tshark and the Python peers"]
fn get_attributes_all_of_every_object_dissects_cleanly() {
    let rig = common::start("get_attributes_all");
    let objects: [(u16, &[u16]); 6] = [
        (1, &[0, 1]),
        (2, &[0, 1]),
        (4, &[0]),
        (6, &[0]),
        (0xF5, &[0, 1]),
        (0xF6, &[0, 1]),
    ];
    let mut requests: Vec<Value> = objects
        .iter()
        .flat_map(|(class, instances)| {
            instances
                .iter()
                .map(move |i| req(&format!("gaa.{class:x}.{i}"), 0x01, *class, *i, None))
        })
        .collect();
    requests.push(req("getclear.4", 0x4C, 0xF6, 1, Some(4)));
    requests.push(with_data(
        req("gal", 0x03, 0xF5, 1, None),
        &[3, 0, 1, 0, 8, 0, 13, 0],
    ));
    let input = json!({"host": BOARD_IP.to_string(), "requests": requests});
    let out = peers::run(rig.ns(), "pycomm3_explicit.py", &input, PEER_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}\nboard log:\n{}", rig.board_log()));
    for (class, instances) in objects {
        for i in instances {
            let data = ok(&out, &format!("gaa.{class:x}.{i}"));
            if *i == 0 {
                // Class attributes 1-7: revision, max instance, count, two lists, two maxima.
                assert!(data.len() >= 14, "class {class:#x}: {data:?}");
            }
        }
    }
    assert_eq!(ok(&out, "getclear.4").len(), 44);
    assert_eq!(
        ok(&out, "gal"),
        [
            &[3, 0, 1, 0, 0, 0, 1, 0, 0, 0, 8, 0, 0, 0, 1, 13, 0, 0, 0][..],
            &120u16.to_le_bytes()
        ]
        .concat()
    );
    common::finish(rig);
}

/// Every shipped profile's EDS (`eds/`) parses with eds-pie without a warning; the generic
/// one declares the generic profile's assemblies and connections.
#[test]
#[ignore = "needs the Python peers (eds-pie)"]
fn every_eds_file_is_clean() {
    for profile in enip_profiles::Profile::NAMES {
        let r = common::eds_check(profile);
        assert_eq!(r["protocol"], "EtherNetIP", "{profile}");
    }
    let r = common::eds_check("generic");
    for (instance, size) in [
        (100, 32),
        (150, 32),
        (151, 10),
        (152, 0),
        (153, 0),
        (154, 32),
    ] {
        assert_eq!(r["assemblies"][format!("Assem{instance}")], size, "{r}");
    }
    // Output 150 and the two heartbeat points, each with input 100.
    assert_eq!(r["connections"].as_array().map_or(0, Vec::len), 3, "{r}");
}
