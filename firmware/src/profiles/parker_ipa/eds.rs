//! The EDS file of the profile, generated from its own tables (identity, connection points,
//! sizes, RPI limit) and checked against the committed `parker_ipa.eds`.
//!
//! One connection, as the manual's RSLogix set-up (p.11): exclusive owner of output 102 with
//! input 101 and configuration point 3, cyclic or application triggered, O->T point-to-point
//! with the 32-bit run/idle header, T->O point-to-point or multicast, RPI 1 ms (Table 4) to
//! the stack's maximum, 10 ms by default (the manual's CIP report). Each assembly is 100
//! DINT members (400 bytes, R3.8; an EDS cannot say which groups fill them). To rewrite the
//! file after a table change: `UPDATE_EDS=1 cargo test -p enip-firmware parker_ipa::eds`.

extern crate std;

use std::fmt::Write as _;
use std::string::String;

use stack::config::MAX_RPI_US;
use stack::{AssemblyInfo, AssemblyRole};

use super::assemblies::{CONFIG, INFOS, INPUT, OUTPUT};
use super::{identity, MIN_RPI_US};

/// The committed file.
const COMMITTED: &str = include_str!("parker_ipa.eds");

/// Trigger and transport: exclusive owner, class 1, cyclic and application triggered.
const OWNER_CYCLIC_APPLICATION: u32 = 0x0405_0002;
/// Connection parameters: fixed sizes, scheduled priority; O->T with the 32-bit run/idle
/// header, point-to-point; T->O modeless, point-to-point or multicast.
const OWNER_PARAMS: u32 = 0x4464_0405;
/// Default RPI: 10 ms, as in the manual's CIP report (p.4).
const DEFAULT_RPI_US: u32 = 10_000;

fn name(instance: u16) -> &'static str {
    match instance {
        INPUT => "IPA sends to PLC (produced groups)",
        OUTPUT => "IPA reads from PLC (consumed groups)",
        _ => "Configuration (no data)",
    }
}

fn info(instance: u16) -> AssemblyInfo {
    *INFOS.iter().find(|a| a.instance == instance).unwrap()
}

/// Renders the whole EDS file.
fn render() -> String {
    let mut s = String::new();
    let i = identity::IDENTITY;
    s.push_str(
        "$ EDS of the Parker IPA / ACR9000 EtherNet/IP profile (enip-rs).\n\
         $ Generated from firmware/src/profiles/parker_ipa by its eds test: do not edit.\n\n",
    );
    s.push_str("[File]\n");
    s.push_str("        DescText = \"Parker IPA Controller (enip-rs simulation)\";\n");
    s.push_str("        CreateDate = 12-01-2026;\n        CreateTime = 12:00:00;\n");
    s.push_str("        ModDate = 12-01-2026;\n        ModTime = 12:00:00;\n");
    s.push_str("        Revision = 1.0;\n\n[Device]\n");
    writeln!(s, "        VendCode = {};", i.vendor_id).unwrap();
    s.push_str("        VendName = \"Parker Hannifin/Compumotor Division\";\n");
    writeln!(s, "        ProdType = {};", i.device_type).unwrap();
    s.push_str("        ProdTypeStr = \"Generic Device\";\n");
    writeln!(s, "        ProdCode = {};", i.product_code).unwrap();
    writeln!(s, "        MajRev = {};", i.revision.0).unwrap();
    writeln!(s, "        MinRev = {};", i.revision.1).unwrap();
    writeln!(s, "        ProdName = \"{}\";", i.product_name).unwrap();
    s.push_str("        Catalog = \"IPA\";\n\n");
    s.push_str("[Device Classification]\n        Class1 = EtherNetIP;\n\n");
    s.push_str("[Params]\n");
    writeln!(
        s,
        "        Param1 = 0, , , 0x0000, 0xC8, 4, \"RPI\", \"microsecond\", \
         \"Requested packet interval\", {MIN_RPI_US}, {MAX_RPI_US}, {DEFAULT_RPI_US}, \
         , , , , , , , , ;\n"
    )
    .unwrap();
    s.push_str("[Assembly]\n        Object_Name = \"Assembly Object\";\n");
    s.push_str("        Object_Class_Code = 0x04;\n");
    for n in [CONFIG, INPUT, OUTPUT] {
        let a = info(n);
        write!(
            s,
            "        Assem{n} = \"{}\", \"20 04 24 {n:02X} 30 03\", {}, 0x0000, , ",
            name(n),
            a.size
        )
        .unwrap();
        for _ in 0..a.size / 4 {
            s.push_str(", 32, ");
        }
        s.push_str(";\n");
    }
    s.push_str("\n[Connection Manager]\n");
    s.push_str("        Object_Name = \"Connection Manager Object\";\n");
    s.push_str("        Object_Class_Code = 0x06;\n");
    let (o, t) = (info(OUTPUT), info(INPUT));
    assert_eq!(
        (o.role, t.role),
        (AssemblyRole::Output, AssemblyRole::Input)
    );
    writeln!(
        s,
        "        Connection1 = 0x{OWNER_CYCLIC_APPLICATION:08X}, 0x{OWNER_PARAMS:08X}, Param1, {}, \
         Assem{OUTPUT}, Param1, {}, Assem{INPUT}, , , , , \"Exclusive owner {OUTPUT}/{INPUT}\", \
         \"\", \"20 04 24 {CONFIG:02X} 2C {OUTPUT:02X} 2C {INPUT:02X}\";",
        o.size, t.size
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
            "/src/profiles/parker_ipa/parker_ipa.eds"
        );
        std::fs::write(path, &eds).unwrap();
        return;
    }
    assert_eq!(eds, COMMITTED, "run with UPDATE_EDS=1 to regenerate");
}

#[test]
fn eds_declares_the_rslogix_set_up() {
    let owner = "0x04050002, 0x44640405, Param1, 400, Assem102, Param1, 400, Assem101";
    assert!(COMMITTED.contains(owner));
    assert!(COMMITTED.contains("\"20 04 24 03 2C 66 2C 65\""));
    assert!(COMMITTED.contains("Assem3 = \"Configuration (no data)\", \"20 04 24 03 30 03\", 0,"));
    assert!(COMMITTED.contains("1000, 10000000, 10000"));
    assert!(COMMITTED.contains("VendCode = 620;"));
    assert!(COMMITTED.contains("ProdName = \"IPA Controller\";"));
}
