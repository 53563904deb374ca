//! The EDS file's choices for the generic profile (`eds/generic.eds`).

use enip_stack::eds::{EdsInfo, RpiRange, Triggers};

use super::assemblies::{CONFIG, EXPLICIT, INPUT, OUTPUT};

/// The EDS choices of the generic profile (`eds/generic.eds`).
pub const EDS: EdsInfo<'static> = EdsInfo {
    description: "enip-rs generic adapter (OpENer sample application assemblies)",
    date: "12-01-2026",
    vendor_name: "enip-rs",
    product_type_name: "Communications Adapter",
    catalog: "ENIP-RS-GENERIC",
    rpi_us: RpiRange {
        min: enip_stack::config::MIN_RPI_US,
        max: enip_stack::config::MAX_RPI_US,
        default: 10_000,
    },
    triggers: Triggers::ALL,
    assembly_names: &[
        (INPUT, "Input (echo of the outputs)"),
        (OUTPUT, "Output"),
        (CONFIG, "Configuration"),
        (EXPLICIT, "Explicit messaging scratch"),
    ],
    member_bits: 0,
    layouts: &[],
    params: &[],
};
