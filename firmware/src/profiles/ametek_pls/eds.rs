//! The EDS file of the profile, generated from its own tables (identity, assemblies and
//! their roles and sizes) and checked against the committed `ametek_pls.eds`.
//!
//! Connections: exclusive owner 150/100, input only 198/100 and listen only 199/100, with
//! the empty configuration assembly 1; cyclic trigger (the Generic Ethernet Module's). To
//! rewrite the file after a table change: `UPDATE_EDS=1 cargo test -p enip-firmware eds`.

extern crate std;

use std::fmt::Write as _;
use std::string::String;

use stack::AssemblyRole;

use super::assemblies::{self, CONFIG, INFOS};
use super::identity;

/// The committed file.
const COMMITTED: &str = include_str!("ametek_pls.eds");

/// Trigger and transport: class 1, cyclic, server.
const CLASS1_CYCLIC: u32 = 0x0001_0002;
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

/// Renders the whole EDS file.
fn render() -> String {
    let mut s = String::new();
    let i = identity::IDENTITY;
    s.push_str(
        "$ EDS of the Ametek 7500 PLS EtherNet/IP profile (enip-rs).\n\
         $ Generated from firmware/src/profiles/ametek_pls by its eds test: do not edit.\n\
         $ Explicit messaging: class 0xC0 (PLS Status, attributes 1-3) and 0xC1 (PLS\n\
         $ Configuration, attributes 1-38), instance 1.\n\n",
    );
    s.push_str("[File]\n");
    s.push_str(
        "        DescText = \"Ametek 7500 UHS PLS Ethernet module (enip-rs simulation)\";\n",
    );
    s.push_str("        CreateDate = 12-01-2026;\n        CreateTime = 12:00:00;\n");
    s.push_str("        ModDate = 12-01-2026;\n        ModTime = 12:00:00;\n");
    s.push_str("        Revision = 1.0;\n\n[Device]\n");
    writeln!(s, "        VendCode = {};", i.vendor_id).unwrap();
    s.push_str("        VendName = \"AMETEK APT\";\n");
    writeln!(s, "        ProdType = {};", i.device_type).unwrap();
    s.push_str("        ProdTypeStr = \"Generic Device\";\n");
    writeln!(s, "        ProdCode = {};", i.product_code).unwrap();
    writeln!(s, "        MajRev = {};", i.revision.0).unwrap();
    writeln!(s, "        MinRev = {};", i.revision.1).unwrap();
    writeln!(s, "        ProdName = \"{}\";", i.product_name).unwrap();
    s.push_str("        Catalog = \"7500\";\n\n");
    s.push_str("[Device Classification]\n        Class1 = EtherNetIP;\n\n");
    s.push_str("[Params]\n");
    s.push_str(
        "        Param1 = 0, , , 0x0000, 0xC8, 4, \"RPI\", \"microsecond\", \
         \"Requested packet interval\", 1000, 10000000, 10000, , , , , , , , , ;\n\n",
    );
    s.push_str("[Assembly]\n        Object_Name = \"Assembly Object\";\n");
    s.push_str("        Object_Class_Code = 0x04;\n");
    for a in &INFOS {
        let n = a.instance;
        write!(
            s,
            "        Assem{n} = \"{}\", \"20 04 24 {n:02X} 30 03\", {}, 0x0000, , ",
            assemblies::name(n),
            a.size
        )
        .unwrap();
        for _ in 0..a.size / 2 {
            s.push_str(", 16, ");
        }
        s.push_str(";\n");
    }
    s.push_str("\n[Connection Manager]\n");
    s.push_str("        Object_Name = \"Connection Manager Object\";\n");
    s.push_str("        Object_Class_Code = 0x06;\n");
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
    let input = INFOS
        .iter()
        .find(|a| a.role == AssemblyRole::Input)
        .unwrap();
    for (k, (role, kind, params, label)) in kinds.into_iter().enumerate() {
        let o = INFOS.iter().find(|a| a.role == role).unwrap();
        let (o_n, t_n) = (o.instance, input.instance);
        writeln!(
            s,
            "        Connection{} = 0x{:08X}, 0x{params:08X}, Param1, {}, Assem{o_n}, \
             Param1, {}, Assem{t_n}, , , , , \"{label} {o_n}/{t_n}\", \"\", \
             \"20 04 24 {CONFIG:02X} 2C {o_n:02X} 2C {t_n:02X}\";",
            k + 1,
            kind | CLASS1_CYCLIC,
            o.size,
            input.size,
        )
        .unwrap();
    }
    s
}

#[test]
fn generated_eds_matches_the_committed_file() {
    let eds = render();
    if std::env::var_os("UPDATE_EDS").is_some() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/src/profiles/ametek_pls/ametek_pls.eds"
        );
        std::fs::write(path, &eds).unwrap();
        return;
    }
    assert_eq!(eds, COMMITTED, "run with UPDATE_EDS=1 to regenerate");
}

#[test]
fn eds_declares_the_manual_sizes_and_connections() {
    for (instance, size) in [(1, 0), (100, 34), (150, 14)] {
        let line = std::format!("Assem{instance} = ");
        let entry = COMMITTED.lines().find(|l| l.contains(&line)).unwrap();
        assert!(entry.contains(&std::format!("\"20 04 24 {instance:02X} 30 03\", {size}, ")));
    }
    let owner = "0x04010002, 0x44640405, Param1, 14, Assem150, Param1, 34, Assem100";
    assert!(COMMITTED.contains(owner));
    assert!(COMMITTED.contains("\"20 04 24 01 2C 96 2C 64\""));
    assert!(COMMITTED.contains("ProdName = \"7500 PLS\";"));
}
