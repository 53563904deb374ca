//! What the AKD's EDS says beyond its tables (`eds/kollmorgen-akd.eds`, written by
//! `enip_stack::eds` from the profile's own description): one exclusive-owner connection of
//! command 101 and response 102 with configuration 100, cyclic, RPI from the drive's 10 ms
//! floor; byte members, as the seed page lays the assemblies out byte by byte.

use enip_stack::eds::{EdsInfo, RpiRange, Triggers};

use super::assemblies::{COMMAND, CONFIG, RESPONSE};
use super::{MAX_RPI_US, MIN_RPI_US};

/// The EDS choices of the profile.
pub const EDS: EdsInfo<'static> = EdsInfo {
    description: "Kollmorgen AKD servo drive (enip-rs simulation)",
    date: "12-01-2026",
    vendor_name: "Kollmorgen",
    product_type_name: "Generic Device",
    catalog: "AKD-xxxxx-NBEI",
    rpi_us: RpiRange {
        min: MIN_RPI_US,
        max: MAX_RPI_US,
        default: MIN_RPI_US,
    },
    triggers: Triggers {
        cyclic: true,
        change_of_state: false,
        application: false,
    },
    assembly_names: &[
        (CONFIG, "Configuration (no data)"),
        (COMMAND, "AKD command assembly"),
        (RESPONSE, "AKD response assembly"),
    ],
    member_bits: 8,
    layouts: &[],
    params: &[],
};

#[cfg(test)]
mod tests {
    extern crate std;

    /// The committed file.
    const COMMITTED: &str = include_str!("../../../eds/kollmorgen-akd.eds");

    #[test]
    fn eds_declares_the_manual_sizes_and_connection() {
        for (instance, size) in [(100, 0), (101, 64), (102, 64)] {
            let line = std::format!("Assem{instance} = ");
            let entry = COMMITTED.lines().find(|l| l.contains(&line)).unwrap();
            assert!(entry.contains(&std::format!("\"20 04 24 {instance:02X} 30 03\", {size}, ")));
        }
        assert!(COMMITTED
            .contains("0x04010002, 0x44640405, Param1, 64, Assem101, Param1, 64, Assem102"));
        assert!(COMMITTED.contains("\"20 04 24 64 2C 65 2C 66\""));
        assert!(COMMITTED.contains("\"Requested packet interval\", 10000, "));
    }
}
