//! What the 7500 PLS's EDS says beyond its tables (`eds/ametek-pls.eds`, written by
//! `enip_stack::eds` from the profile's own description).
//!
//! Connections: exclusive owner 150/100, input only 198/100 and listen only 199/100, with
//! the empty configuration assembly 1; cyclic trigger (the Generic Ethernet Module's);
//! INT members. Explicit messaging: class 0xC0 (PLS Status, attributes 1-3) and 0xC1 (PLS
//! Configuration, attributes 1-38), instance 1.

use enip_stack::eds::{EdsInfo, RpiRange, Triggers};

use super::assemblies::{CONFIG, INPUT, INPUT_ONLY_HEARTBEAT, LISTEN_ONLY_HEARTBEAT, OUTPUT};

/// The EDS choices of the profile.
pub const EDS: EdsInfo<'static> = EdsInfo {
    description: "Ametek 7500 UHS PLS Ethernet module (enip-rs simulation)",
    date: "12-01-2026",
    vendor_name: "AMETEK APT",
    product_type_name: "Generic Device",
    catalog: "7500",
    rpi_us: RpiRange {
        min: 1_000,
        max: 10_000_000,
        default: 10_000,
    },
    triggers: Triggers {
        cyclic: true,
        change_of_state: false,
        application: false,
    },
    assembly_names: &[
        (INPUT, "PLS input data (17 words)"),
        (OUTPUT, "PLS output data (7 words)"),
        (CONFIG, "Configuration (not used, no data)"),
        (INPUT_ONLY_HEARTBEAT, "Input only heartbeat"),
        (LISTEN_ONLY_HEARTBEAT, "Listen only heartbeat"),
    ],
    member_bits: 16,
    layouts: &[],
    params: &[],
};

#[cfg(test)]
mod tests {
    extern crate std;

    /// The committed file.
    const COMMITTED: &str = include_str!("../../../eds/ametek-pls.eds");

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
}
