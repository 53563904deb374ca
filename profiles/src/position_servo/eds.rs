//! What the PositionServo's EDS says beyond its tables: names, catalog number, RPI range and
//! triggers (table 9: cyclic and application triggered). The file itself is
//! `eds/position-servo.eds`, written by `enip_stack::eds` from the profile's own description.

use enip_stack::eds::{EdsInfo, RpiRange, Triggers};

/// The EDS choices of the profile.
pub const EDS: EdsInfo<'static> = EdsInfo {
    description: "Lenze PositionServo EnetIP 940 (enip-rs simulation)",
    date: "11-22-2026",
    vendor_name: "Lenze AC Tech",
    product_type_name: "Generic Device",
    catalog: "E94P",
    rpi_us: RpiRange {
        min: 1_000,
        max: 10_000_000,
        // 4.4: "5.0 milliseconds or greater".
        default: 5_000,
    },
    triggers: Triggers {
        cyclic: true,
        change_of_state: false,
        application: true,
    },
    // Table 14's names, and the heartbeat points'.
    assembly_names: &[
        (103, "Configuration (no data)"),
        (104, "PositionServo Status and IO Assembly"),
        (105, "PositionServo universal monitor"),
        (106, "PositionServo basic control"),
        (108, "PositionServo extended control"),
        (109, "PositionServo keep alive"),
        (198, "Input only heartbeat"),
        (199, "Listen only heartbeat"),
    ],
    // Every assembly is a list of 32-bit variables (5.5).
    member_bits: 32,
    layouts: &[],
    params: &[],
};

#[cfg(test)]
mod tests {
    extern crate std;

    /// The committed file.
    const COMMITTED: &str = include_str!("../../../eds/position-servo.eds");

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
}
