//! The EDS file of the profile, generated from its own tables (identity, assemblies and
//! their roles and sizes) and checked against the committed `position_servo.eds`.
//!
//! Connections: every output assembly with every input assembly as exclusive owner, and the
//! two heartbeat points with every input assembly as input only and listen only; cyclic and
//! application-triggered (table 9). To rewrite the file after a table change:
//! `UPDATE_EDS=1 cargo test -p enip-firmware eds`.

extern crate std;

use std::fmt::Write as _;
use std::string::String;

use stack::AssemblyRole;

use super::assemblies::{Assembly, ASSEMBLIES};
use super::identity;

/// The committed file.
const COMMITTED: &str = include_str!("position_servo.eds");

/// Trigger and transport: class 1, cyclic and application triggered, server.
const CLASS1_CYCLIC_APPLICATION: u32 = 0x0005_0002;
/// Transport types (bits 24-26).
const EXCLUSIVE_OWNER: u32 = 1 << 26;
const INPUT_ONLY: u32 = 1 << 25;
const LISTEN_ONLY: u32 = 1 << 24;
/// Connection parameters: fixed sizes, scheduled priority; O->T with the 32-bit run/idle
/// header (or heartbeat) point-to-point; T->O modeless, point-to-point or multicast.
const OWNER_PARAMS: u32 = 0x4464_0405;
const HEARTBEAT_PARAMS: u32 = 0x4464_0305;
/// Listen only: T->O multicast only.
const LISTEN_PARAMS: u32 = 0x4424_0305;

/// Table 14's name of an assembly (and the heartbeat points').
fn name(instance: u16) -> &'static str {
    match instance {
        103 => "Configuration (no data)",
        104 => "PositionServo Status and IO Assembly",
        105 => "PositionServo universal monitor",
        106 => "PositionServo basic control",
        108 => "PositionServo extended control",
        109 => "PositionServo keep alive",
        198 => "Input only heartbeat",
        _ => "Listen only heartbeat",
    }
}

fn of_role(role: AssemblyRole) -> impl Iterator<Item = &'static Assembly> {
    ASSEMBLIES.iter().filter(move |a| a.info.role == role)
}

fn config() -> u16 {
    of_role(AssemblyRole::Config)
        .map(|a| a.info.instance)
        .next()
        .unwrap()
}

/// Renders the whole EDS file.
fn render() -> String {
    let mut s = String::new();
    let i = identity::IDENTITY;
    s.push_str(
        "$ EDS of the Lenze (AC Tech) PositionServo EtherNet/IP profile (enip-rs).\n\
         $ Generated from firmware/src/profiles/position_servo by its eds test: do not edit.\n\n",
    );
    s.push_str("[File]\n");
    s.push_str("        DescText = \"Lenze PositionServo EnetIP 940 (enip-rs simulation)\";\n");
    s.push_str("        CreateDate = 11-22-2026;\n        CreateTime = 12:00:00;\n");
    s.push_str("        ModDate = 11-22-2026;\n        ModTime = 12:00:00;\n");
    s.push_str("        Revision = 1.0;\n\n[Device]\n");
    writeln!(s, "        VendCode = {};", i.vendor_id).unwrap();
    s.push_str("        VendName = \"Lenze AC Tech\";\n");
    writeln!(s, "        ProdType = {};", i.device_type).unwrap();
    s.push_str("        ProdTypeStr = \"Generic Device\";\n");
    writeln!(s, "        ProdCode = {};", i.product_code).unwrap();
    writeln!(s, "        MajRev = {};", i.revision.0).unwrap();
    writeln!(s, "        MinRev = {};", i.revision.1).unwrap();
    writeln!(s, "        ProdName = \"{}\";", i.product_name).unwrap();
    s.push_str("        Catalog = \"E94P\";\n\n");
    s.push_str("[Device Classification]\n        Class1 = EtherNetIP;\n\n");
    s.push_str("[Params]\n");
    s.push_str(
        "        Param1 = 0, , , 0x0000, 0xC8, 4, \"RPI\", \"microsecond\", \
         \"Requested packet interval\", 1000, 10000000, 5000, , , , , , , , , ;\n\n",
    );
    s.push_str("[Assembly]\n        Object_Name = \"Assembly Object\";\n");
    s.push_str("        Object_Class_Code = 0x04;\n");
    for a in &ASSEMBLIES {
        let n = a.info.instance;
        write!(
            s,
            "        Assem{n} = \"{}\", \"20 04 24 {n:02X} 30 03\", {}, 0x0000, , ",
            name(n),
            a.info.size
        )
        .unwrap();
        for _ in a.words {
            s.push_str(", 32, ");
        }
        s.push_str(";\n");
    }
    s.push_str("\n[Connection Manager]\n");
    s.push_str("        Object_Name = \"Connection Manager Object\";\n");
    s.push_str("        Object_Class_Code = 0x06;\n");
    let mut k = 0;
    let kinds = [
        (
            AssemblyRole::Output,
            EXCLUSIVE_OWNER,
            OWNER_PARAMS,
            "Exclusive owner",
        ),
        (
            AssemblyRole::InputOnlyHeartbeat,
            INPUT_ONLY,
            HEARTBEAT_PARAMS,
            "Input only",
        ),
        (
            AssemblyRole::ListenOnlyHeartbeat,
            LISTEN_ONLY,
            LISTEN_PARAMS,
            "Listen only",
        ),
    ];
    for (role, kind, params, label) in kinds {
        for o in of_role(role) {
            for t in of_role(AssemblyRole::Input) {
                k += 1;
                let (o_n, t_n) = (o.info.instance, t.info.instance);
                writeln!(
                    s,
                    "        Connection{k} = 0x{:08X}, 0x{params:08X}, Param1, {}, Assem{o_n}, \
                     Param1, {}, Assem{t_n}, , , , , \"{label} {o_n}/{t_n}\", \"\", \
                     \"20 04 24 {:02X} 2C {o_n:02X} 2C {t_n:02X}\";",
                    kind | CLASS1_CYCLIC_APPLICATION,
                    o.info.size,
                    t.info.size,
                    config()
                )
                .unwrap();
            }
        }
    }
    s
}

#[test]
fn generated_eds_matches_the_committed_file() {
    let eds = render();
    if std::env::var_os("UPDATE_EDS").is_some() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/src/profiles/position_servo/position_servo.eds"
        );
        std::fs::write(path, &eds).unwrap();
        return;
    }
    assert_eq!(eds, COMMITTED, "run with UPDATE_EDS=1 to regenerate");
}

#[test]
fn eds_declares_the_manual_sizes_and_connections() {
    for (instance, size) in [(103, 0), (104, 8), (105, 36), (106, 8), (108, 24), (109, 4)] {
        let line = std::format!("Assem{instance} = ");
        let entry = COMMITTED.lines().find(|l| l.contains(&line)).unwrap();
        assert!(entry.contains(&std::format!("\"20 04 24 {instance:02X} 30 03\", {size}, ")));
    }
    let owner = "0x04050002, 0x44640405, Param1, 8, Assem106, Param1, 36, Assem105";
    assert!(COMMITTED.contains(owner));
    assert!(COMMITTED.contains("\"20 04 24 67 2C 6A 2C 69\""));
    let connections = COMMITTED
        .lines()
        .filter(|l| l.trim_start().starts_with("Connection"))
        .count();
    // Outputs 106, 108, 109 and the two heartbeat points, each with inputs 104 and 105.
    assert_eq!(connections, (3 + 2) * 2);
    assert!(COMMITTED.contains("ProdName = \"EnetIP 940\";"));
}
