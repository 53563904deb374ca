//! What the IPA's EDS says beyond its tables (`eds/parker-ipa.eds`, written by
//! `enip_stack::eds` from the profile's own description).
//!
//! One connection, as the manual's RSLogix set-up (p.11): exclusive owner of output 102 with
//! input 101 and configuration point 3, cyclic or application triggered, O->T point-to-point
//! with the 32-bit run/idle header, T->O point-to-point or multicast, RPI 1 ms (Table 4) to
//! the stack's maximum, 10 ms by default (the manual's CIP report). Each assembly is 100
//! DINT members (400 bytes, R3.8; an EDS cannot say which groups fill them).

use enip_stack::config::MAX_RPI_US;
use enip_stack::eds::{EdsInfo, RpiRange, Triggers};

use super::assemblies::{CONFIG, INPUT, OUTPUT};
use super::MIN_RPI_US;

/// Default RPI: 10 ms, as in the manual's CIP report (p.4).
const DEFAULT_RPI_US: u32 = 10_000;

/// The EDS choices of the profile.
pub const EDS: EdsInfo<'static> = EdsInfo {
    description: "Parker IPA Controller (enip-rs simulation)",
    date: "12-01-2026",
    vendor_name: "Parker Hannifin/Compumotor Division",
    product_type_name: "Generic Device",
    catalog: "IPA",
    rpi_us: RpiRange {
        min: MIN_RPI_US,
        max: MAX_RPI_US,
        default: DEFAULT_RPI_US,
    },
    triggers: Triggers {
        cyclic: true,
        change_of_state: false,
        application: true,
    },
    assembly_names: &[
        (INPUT, "IPA sends to PLC (produced groups)"),
        (OUTPUT, "IPA reads from PLC (consumed groups)"),
        (CONFIG, "Configuration (no data)"),
    ],
    member_bits: 32,
    layouts: &[],
    params: &[],
};

#[cfg(test)]
mod tests {
    /// The committed file.
    const COMMITTED: &str = include_str!("../../../eds/parker-ipa.eds");

    #[test]
    fn eds_declares_the_rslogix_set_up() {
        let owner = "0x04050002, 0x44640405, Param1, 400, Assem102, Param1, 400, Assem101";
        assert!(COMMITTED.contains(owner));
        assert!(COMMITTED.contains("\"20 04 24 03 2C 66 2C 65\""));
        assert!(
            COMMITTED.contains("Assem3 = \"Configuration (no data)\", \"20 04 24 03 30 03\", 0,")
        );
        assert!(COMMITTED.contains("1000, 10000000, 10000"));
        assert!(COMMITTED.contains("VendCode = 620;"));
        assert!(COMMITTED.contains("ProdName = \"IPA Controller\";"));
    }
}
