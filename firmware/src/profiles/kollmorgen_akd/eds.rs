//! The EDS file of the profile, generated from its own tables (identity, assemblies, RPI
//! limits) and checked against the committed `kollmorgen_akd.eds`.
//!
//! One connection, as the manual configures it (p.10-11): exclusive owner, cyclic, command
//! 101 (64 bytes, run/idle header) with response 102 (64 bytes), configuration 100 (0
//! bytes), RPI 10 ms or more, T->O multicast or point-to-point. To rewrite the file after a
//! table change: `UPDATE_EDS=1 cargo test -p enip-firmware kollmorgen_akd::eds`.

extern crate std;

use std::fmt::Write as _;
use std::string::String;

use stack::AssemblyRole;

use super::assemblies::INFOS;
use super::{identity, MAX_RPI_US, MIN_RPI_US};

/// The committed file.
const COMMITTED: &str = include_str!("kollmorgen_akd.eds");

/// Trigger and transport: class 1, cyclic only, exclusive owner (bit 26).
const OWNER_CYCLIC: u32 = (1 << 26) | 0x0001_0002;
/// Connection parameters: fixed sizes, scheduled priority; O->T with the 32-bit run/idle
/// header, point-to-point; T->O modeless, point-to-point or multicast.
const OWNER_PARAMS: u32 = 0x4464_0405;

/// The manual's name of an assembly.
fn name(instance: u16) -> &'static str {
    match instance {
        100 => "Configuration (no data)",
        101 => "AKD command assembly",
        _ => "AKD response assembly",
    }
}

fn of_role(role: AssemblyRole) -> u16 {
    INFOS
        .iter()
        .find(|a| a.role == role)
        .map(|a| a.instance)
        .unwrap()
}

fn size(instance: u16) -> u16 {
    INFOS
        .iter()
        .find(|a| a.instance == instance)
        .map(|a| a.size)
        .unwrap()
}

/// Renders the whole EDS file.
fn render() -> String {
    let mut s = String::new();
    let i = identity::IDENTITY;
    s.push_str(
        "$ EDS of the Kollmorgen AKD EtherNet/IP profile (enip-rs).\n\
         $ Generated from firmware/src/profiles/kollmorgen_akd by its eds test: do not edit.\n\n",
    );
    s.push_str("[File]\n");
    s.push_str("        DescText = \"Kollmorgen AKD servo drive (enip-rs simulation)\";\n");
    s.push_str("        CreateDate = 12-01-2026;\n        CreateTime = 12:00:00;\n");
    s.push_str("        ModDate = 12-01-2026;\n        ModTime = 12:00:00;\n");
    s.push_str("        Revision = 1.0;\n\n[Device]\n");
    writeln!(s, "        VendCode = {};", i.vendor_id).unwrap();
    s.push_str("        VendName = \"Kollmorgen\";\n");
    writeln!(s, "        ProdType = {};", i.device_type).unwrap();
    s.push_str("        ProdTypeStr = \"Generic Device\";\n");
    writeln!(s, "        ProdCode = {};", i.product_code).unwrap();
    writeln!(s, "        MajRev = {};", i.revision.0).unwrap();
    writeln!(s, "        MinRev = {};", i.revision.1).unwrap();
    writeln!(s, "        ProdName = \"{}\";", i.product_name).unwrap();
    s.push_str("        Catalog = \"AKD-xxxxx-NBEI\";\n\n");
    s.push_str("[Device Classification]\n        Class1 = EtherNetIP;\n\n");
    s.push_str("[Params]\n");
    writeln!(
        s,
        "        Param1 = 0, , , 0x0000, 0xC8, 4, \"RPI\", \"microsecond\", \
         \"Requested packet interval\", {MIN_RPI_US}, {MAX_RPI_US}, {MIN_RPI_US}, , , , , , , , , ;\n"
    )
    .unwrap();
    s.push_str("[Assembly]\n        Object_Name = \"Assembly Object\";\n");
    s.push_str("        Object_Class_Code = 0x04;\n");
    for a in &INFOS {
        let n = a.instance;
        write!(
            s,
            "        Assem{n} = \"{}\", \"20 04 24 {n:02X} 30 03\", {}, 0x0000, , ",
            name(n),
            a.size
        )
        .unwrap();
        for _ in 0..a.size {
            s.push_str(", 8, ");
        }
        s.push_str(";\n");
    }
    s.push_str("\n[Connection Manager]\n");
    s.push_str("        Object_Name = \"Connection Manager Object\";\n");
    s.push_str("        Object_Class_Code = 0x06;\n");
    let (o, t, c) = (
        of_role(AssemblyRole::Output),
        of_role(AssemblyRole::Input),
        of_role(AssemblyRole::Config),
    );
    writeln!(
        s,
        "        Connection1 = 0x{OWNER_CYCLIC:08X}, 0x{OWNER_PARAMS:08X}, Param1, {}, Assem{o}, \
         Param1, {}, Assem{t}, , , , , \"Exclusive owner {o}/{t}\", \"\", \
         \"20 04 24 {c:02X} 2C {o:02X} 2C {t:02X}\";",
        size(o),
        size(t),
    )
    .unwrap();
    s
}

#[test]
fn generated_eds_matches_the_committed_file() {
    let eds = render();
    if std::env::var_os("UPDATE_EDS").is_some() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/src/profiles/kollmorgen_akd/kollmorgen_akd.eds"
        );
        std::fs::write(path, &eds).unwrap();
        return;
    }
    assert_eq!(eds, COMMITTED, "run with UPDATE_EDS=1 to regenerate");
}

#[test]
fn eds_declares_the_manual_sizes_and_connection() {
    for (instance, size) in [(100, 0), (101, 64), (102, 64)] {
        let line = std::format!("Assem{instance} = ");
        let entry = COMMITTED.lines().find(|l| l.contains(&line)).unwrap();
        assert!(entry.contains(&std::format!("\"20 04 24 {instance:02X} 30 03\", {size}, ")));
    }
    assert!(
        COMMITTED.contains("0x04010002, 0x44640405, Param1, 64, Assem101, Param1, 64, Assem102")
    );
    assert!(COMMITTED.contains("\"20 04 24 64 2C 65 2C 66\""));
    assert!(COMMITTED.contains("\"Requested packet interval\", 10000, "));
}
