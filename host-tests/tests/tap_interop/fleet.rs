//! A plant in one process: `enip-host --devices LIST` with 16 devices of all five shipped
//! profiles on 16 addresses of a veth pair, from a device list using every key (`count` runs,
//! serial numbers, product names, an NV file). pycomm3 reads each device's Identity object
//! (the list's serial number and product name, the profile's vendor and product code); the
//! PyPI `ethernetip` package then holds a Class 1 exclusive owner on every device at once
//! at 10 ms and counts each one's T->O data, and closes them.

use std::net::Ipv4Addr;
use std::time::Duration;

use enip_profiles::Profile;
use enip_stack::Device;
use host_tests::netns::Lab;
use host_tests::peers;
use host_tests::process::{LoggedChild, SIGTERM};
use serde_json::{json, Value};

use crate::common;

/// The peers' end of the veth pair.
const LINK: &str = "enipfl0";
/// The first device's address; the others follow.
const FIRST: [u8; 4] = [198, 18, 0, 10];
/// RPI of the owners, ms.
const RPI_MS: u32 = 10;
/// How long every owner runs at once, s.
const SECONDS: f64 = 2.0;
/// Bound for the peer program (16 identity reads, 16 Forward_Opens, the run, the closes).
const PEER_TIMEOUT: Duration = Duration::from_secs(90);
/// How long the fleet may take to open every device.
const START: Duration = Duration::from_secs(15);

/// A run of alike devices in the list: profile, count, first serial number, and the
/// exclusive owner's connection points (input, its size, output, its size, configuration).
struct Run {
    profile: &'static str,
    count: u32,
    serial: u32,
    owner: [u16; 5],
}

const RUNS: [Run; 5] = [
    Run {
        profile: "generic",
        count: 4,
        serial: 0x00F1_0001,
        owner: [100, 32, 150, 32, 151],
    },
    Run {
        profile: "position-servo",
        count: 3,
        serial: 0x00F2_0001,
        owner: [105, 36, 106, 8, 103],
    },
    Run {
        profile: "parker-ipa",
        count: 3,
        serial: 0x00F3_0001,
        owner: [101, 400, 102, 400, 3],
    },
    Run {
        profile: "ametek-pls",
        count: 3,
        serial: 0x00F4_0001,
        owner: [100, 34, 150, 14, 1],
    },
    Run {
        profile: "kollmorgen-akd",
        count: 3,
        serial: 0x00F5_0001,
        owner: [102, 64, 101, 64, 100],
    },
];

/// One device as the test expects it.
struct Expected {
    ip: Ipv4Addr,
    profile: &'static str,
    serial: u32,
    name: String,
    owner: [u16; 5],
}

/// The device list (the generic devices keep their settings in `nv`-1 to -4), and what each
/// device of it should be.
fn device_list(nv: &std::path::Path) -> (String, Vec<Expected>) {
    let mut list = String::from("# the fleet test's plant\n");
    let mut expected = Vec::new();
    let mut next = u32::from(Ipv4Addr::from(FIRST));
    for (i, run) in RUNS.iter().enumerate() {
        let first = Ipv4Addr::from(next);
        list += &format!(
            "\n[[device]]\nname = \"{p}-{{n}}\"\naddress = \"{first}\"\nprofile = \"{p}\"\n\
             count = {c}\nserial_number = {s:#x}\nproduct_name = \"plant {p} {{n}}\"\n",
            p = run.profile,
            c = run.count,
            s = run.serial
        );
        if i == 0 {
            list += &format!("nv_file = \"{}-{{n}}\"\n", nv.display());
        }
        for n in 0..run.count {
            expected.push(Expected {
                ip: Ipv4Addr::from(next + n),
                profile: run.profile,
                serial: run.serial + n,
                name: format!("plant {} {}", run.profile, n + 1),
                owner: run.owner,
            });
        }
        next += run.count;
    }
    (list, expected)
}

#[test]
#[ignore = "needs root and the Python peers"]
fn sixteen_devices_of_five_profiles_in_one_process() {
    let nv = common::scratch("fleet-nv");
    for n in 1..=4 {
        let _ = std::fs::remove_file(format!("{}-{n}", nv.display()));
    }
    let (list, expected) = device_list(&nv);
    assert_eq!(expected.len(), 16);
    let list_path = common::scratch("fleet.toml");
    std::fs::write(&list_path, list).expect("write the device list");
    let lab = Lab::create_veth(LINK).expect("veth lab");
    let cidrs: Vec<String> = expected.iter().map(|d| format!("{}/24", d.ip)).collect();
    lab.add_board_addresses(&cidrs).expect("board addresses");
    let mut cmd = lab.board_command(common::host_bin());
    cmd.arg("--devices").arg(&list_path).env("RUST_LOG", "info");
    let mut fleet = LoggedChild::spawn("enip-host --devices", cmd).expect("start the fleet");
    fleet
        .wait_for_line("kollmorgen-akd-3: listening on 198.18.0.25", START)
        .unwrap_or_else(|e| panic!("{e}"));

    let devices: Vec<Value> = expected
        .iter()
        .map(|d| {
            let [input, in_size, output, out_size, config] = d.owner;
            json!({"host": d.ip.to_string(), "input": input, "in_size": in_size,
                "output": output, "out_size": out_size, "config": config})
        })
        .collect();
    let input = json!({"rpi_ms": RPI_MS, "seconds": SECONDS, "devices": devices});
    let out = peers::run(lab.ns(), "fleet.py", &input, PEER_TIMEOUT)
        .unwrap_or_else(|e| panic!("fleet peer: {e}\nfleet log:\n{}", fleet.tail(40)));
    let results = out["devices"].as_array().expect("a result per device");
    assert_eq!(results.len(), expected.len());
    // At least half the datagrams due: the machine running the test is shared.
    let due = (SECONDS * 1000.0) as u64 / u64::from(RPI_MS);
    for (d, r) in expected.iter().zip(results) {
        let what = format!("{} ({}): {r}", d.ip, d.profile);
        let profile = Profile::from_name(d.profile).expect("a shipped profile");
        let identity = profile.identity();
        let id = &r["identity"];
        assert_eq!(id["serial_number"], format!("{:#010x}", d.serial), "{what}");
        assert_eq!(id["product_name"], d.name.as_str(), "{what}");
        assert_eq!(id["vendor_id"], identity.vendor_id.to_string(), "{what}");
        assert_eq!(
            id["product_code"],
            identity.product_code.to_string(),
            "{what}"
        );
        assert_eq!(r["forward_open"], 0, "{what}");
        let received = r["received"].as_u64().unwrap_or(0);
        eprintln!(
            "{} {:<15} {:#010x} {received:>4} T->O",
            d.ip, d.profile, d.serial
        );
        assert!(received >= due / 2, "{what}: {received} T->O of {due}");
        assert_eq!(r["forward_close"], 0, "{what}");
    }
    assert!(
        fleet.exited().is_none(),
        "the fleet ended:\n{}",
        fleet.tail(40)
    );
    let log = fleet.output();
    // Each device's lines carry its name: the Forward_Opens logged by the profiles' devices.
    assert!(log.contains("generic-1: listening on 198.18.0.10"), "{log}");
    assert!(
        !log.contains(" ERROR "),
        "errors in the fleet's log:\n{log}"
    );
    fleet.stop(SIGTERM, Duration::from_secs(3));
    // The generic devices' stores are files of their own.
    assert!(std::path::Path::new(&format!("{}-1", nv.display())).exists());
}
