//! Electronic keys in explicit request paths, sent by pycomm3 (`peers/electronic_key.py`):
//! Get_Attribute_Single on the Identity object with a key segment first in its path, as
//! UCMM, inside Unconnected_Send and over a Class 3 connection, and as members of a
//! Multiple_Service_Packet. Exact, all-zero and compatible keys are served; a wrong vendor,
//! product code, device type or major revision, or a newer minor revision with the
//! compatibility bit, is key failure in path (0x25) with the extended status of the part
//! that failed, and a refused Set_Attribute_Single changes nothing.
//!
//! The board runs the PositionServo profile: its revision 3.4 has a minor revision a
//! compatible key can name below its own (the generic profile's 1.1 has only 1: with the compatibility bit
//! a minor revision must be 1 or more, and no more than the device's).

use std::time::Duration;

use enip_profiles::position_servo::identity::{DEVICE_TYPE, PRODUCT_CODE, REVISION, VENDOR_ID};
use enip_stack::wire::epath::{ElectronicKey, SegmentRepr};
use enip_stack::wire::Writer;
use serde_json::{json, Value};

use crate::position_servo;
use host_tests::peers;
use host_tests::rig::BOARD_IP;

/// Bound for the peer program run.
const PEER_TIMEOUT: Duration = Duration::from_secs(60);

/// The board's own key, compatibility bit clear.
const EXACT: ElectronicKey = ElectronicKey {
    vendor_id: VENDOR_ID,
    device_type: DEVICE_TYPE,
    product_code: PRODUCT_CODE,
    major_revision: REVISION.0,
    compatibility: false,
    minor_revision: REVISION.1,
};

/// The key segment's bytes in hex.
fn hex_key(key: ElectronicKey) -> String {
    let mut buf = [0u8; 16];
    let mut w = Writer::new(&mut buf);
    SegmentRepr::ElectronicKey(key)
        .emit(&mut w)
        .expect("key fits");
    w.written().iter().map(|b| format!("{b:02x}")).collect()
}

/// Keys the board must accept, by name.
fn accepted() -> Vec<(&'static str, ElectronicKey)> {
    let zero = ElectronicKey {
        vendor_id: 0,
        device_type: 0,
        product_code: 0,
        major_revision: 0,
        compatibility: false,
        minor_revision: 0,
    };
    let compatible = ElectronicKey {
        compatibility: true,
        minor_revision: REVISION.1 - 1,
        ..EXACT
    };
    vec![("exact", EXACT), ("zero", zero), ("compatible", compatible)]
}

/// Keys the board must refuse, by name, with their extended status.
fn refused() -> Vec<(&'static str, ElectronicKey, u16)> {
    vec![
        (
            "vendor",
            ElectronicKey {
                vendor_id: VENDOR_ID - 1,
                ..EXACT
            },
            0x0114,
        ),
        (
            "product",
            ElectronicKey {
                product_code: PRODUCT_CODE + 1,
                ..EXACT
            },
            0x0114,
        ),
        (
            "device_type",
            ElectronicKey {
                device_type: DEVICE_TYPE + 1,
                ..EXACT
            },
            0x0115,
        ),
        (
            "major",
            ElectronicKey {
                major_revision: REVISION.0 + 1,
                ..EXACT
            },
            0x0116,
        ),
        (
            "newer_minor",
            ElectronicKey {
                compatibility: true,
                minor_revision: REVISION.1 + 1,
                ..EXACT
            },
            0x0116,
        ),
    ]
}

/// A keyed request for the peer.
fn request(name: String, via: &str, key: ElectronicKey, service: u8, attr: (u16, u8)) -> Value {
    json!({"name": name, "via": via, "key": hex_key(key), "service": service,
           "class": attr.0, "instance": 1, "attribute": attr.1, "data": ""})
}

/// The peer's result named `name`.
fn result<'a>(out: &'a Value, name: &str) -> &'a Value {
    out["results"]
        .as_array()
        .and_then(|a| a.iter().find(|r| r["name"] == name))
        .unwrap_or_else(|| panic!("no result {name} in {out}"))
}

/// Encapsulation inactivity timeout (TCP/IP attribute 13) as request data, in hex.
fn timeout_hex(seconds: u16) -> String {
    seconds
        .to_le_bytes()
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

#[test]
#[ignore = "needs root, tshark and the Python peers"]
fn pycomm3_keys_in_explicit_paths() {
    let rig = position_servo::start("electronic_key");
    let vendor = VENDOR_ID.to_le_bytes();
    let vias = ["ucmm", "ucs", "class3"];
    let mut requests = Vec::new();
    for via in vias {
        for (name, key) in accepted() {
            requests.push(request(format!("{via}.{name}"), via, key, 0x0E, (1, 1)));
        }
        for (name, key, _) in refused() {
            requests.push(request(format!("{via}.{name}"), via, key, 0x0E, (1, 1)));
        }
        // Not executed: a write with a wrong key leaves TCP/IP attribute 13 as it was.
        let wrong = refused()[2].1;
        let mut set = request(format!("{via}.set_refused"), via, wrong, 0x10, (0xF5, 13));
        set["data"] = json!(timeout_hex(300));
        requests.push(set);
        requests.push(request(
            format!("{via}.after"),
            via,
            EXACT,
            0x0E,
            (0xF5, 13),
        ));
    }
    // The same write with the right key is served: the refused ones were real writes.
    let mut set = request("set_exact".into(), "ucmm", EXACT, 0x10, (0xF5, 13));
    set["data"] = json!(timeout_hex(300));
    requests.push(set);
    requests.push(request(
        "after_exact".into(),
        "ucmm",
        EXACT,
        0x0E,
        (0xF5, 13),
    ));
    let member = |key: ElectronicKey| json!({"key": hex_key(key), "service": 0x0E, "class": 1, "instance": 1, "attribute": 1});
    let mut members: Vec<Value> = accepted().into_iter().map(|(_, k)| member(k)).collect();
    members.extend(refused().into_iter().map(|(_, k, _)| member(k)));
    let input = json!({
        "host": BOARD_IP.to_string(),
        "requests": requests,
        "multiple": [{"name": "msp", "members": members}],
    });
    let out = peers::run(rig.ns(), "electronic_key.py", &input, PEER_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}\nboard log:\n{}", rig.board_log()));
    println!("electronic_key.py: {out}");

    let vendor_hex: String = vendor.iter().map(|b| format!("{b:02x}")).collect();
    for via in vias {
        for (name, _) in accepted() {
            let r = result(&out, &format!("{via}.{name}"));
            assert_eq!(r["status"], 0, "{via}.{name}: {r}");
            assert_eq!(r["data"], vendor_hex, "{via}.{name}: {r}");
        }
        for (name, _, ext) in refused() {
            let r = result(&out, &format!("{via}.{name}"));
            assert_eq!(r["status"], 0x25, "{via}.{name}: {r}");
            assert_eq!(r["extended"], json!([ext]), "{via}.{name}: {r}");
            assert_eq!(r["data"], "", "{via}.{name}: {r}");
        }
        let r = result(&out, &format!("{via}.set_refused"));
        assert_eq!(
            (&r["status"], &r["extended"]),
            (&json!(0x25), &json!([0x0115])),
            "{via}: {r}"
        );
        let r = result(&out, &format!("{via}.after"));
        assert_eq!(r["status"], 0, "{via}: {r}");
        assert_eq!(r["data"], timeout_hex(120), "{via}: unchanged: {r}");
    }

    assert_eq!(result(&out, "set_exact")["status"], 0, "{out}");
    assert_eq!(
        result(&out, "after_exact")["data"],
        timeout_hex(300),
        "{out}"
    );

    let msp = &out["multiple"][0];
    assert_eq!(msp["status"], 0x1E, "an embedded service failed: {msp}");
    let got = msp["members"].as_array().expect("members");
    assert_eq!(got.len(), accepted().len() + refused().len(), "{msp}");
    for (i, (name, _)) in accepted().iter().enumerate() {
        assert_eq!(
            (&got[i]["status"], &got[i]["data"]),
            (&json!(0), &json!(vendor_hex)),
            "member {name}: {msp}"
        );
    }
    for (i, (name, _, ext)) in refused().iter().enumerate() {
        let m = &got[accepted().len() + i];
        assert_eq!(
            (&m["status"], &m["extended"]),
            (&json!(0x25), &json!([ext])),
            "member {name}: {msp}"
        );
    }
    crate::common::finish(rig);
}
