//! What the block's EDS says beyond the device itself: names, the configuration assembly's
//! fields and channel 1's attributes as parameters (`io-block-host --eds` prints it).

use enip_stack::cip::object::DataType;
use enip_stack::eds::{EdsInfo, Layout, Member, Param};

use crate::{CHANNEL_CLASS, CONFIG, INPUTS, INPUT_ONLY, LISTEN_ONLY, OUTPUTS};

/// The block's EDS choices.
pub const EDS: EdsInfo<'static> = EdsInfo {
    description: "enip-rs example: 16-channel digital I/O block",
    date: "12-03-2026",
    vendor_name: "enip-rs",
    product_type_name: "General Purpose Discrete I/O",
    catalog: "IO-BLOCK-16",
    assembly_names: &[
        (INPUTS, "Inputs"),
        (OUTPUTS, "Outputs"),
        (CONFIG, "Configuration"),
        (INPUT_ONLY, "Input only heartbeat"),
        (LISTEN_ONLY, "Listen only heartbeat"),
    ],
    // The inputs and outputs: one bit per channel.
    member_bits: 1,
    layouts: &[Layout {
        instance: CONFIG,
        members: &[Member::Param(0), Member::Param(1), Member::Param(2)],
    }],
    params: &[
        Param::new("Input filter", DataType::Usint, 0, 100, 0).units("ms"),
        Param::new("Safe-state mode", DataType::Usint, 0, 1, 0)
            .help("0: apply the safe-state outputs, 1: hold the last outputs"),
        Param::new("Safe-state outputs", DataType::Word, 0, 0xFFFF, 0).help("bit n: channel n"),
        Param::new("Channel 1 debounce", DataType::Usint, 0, 100, 0)
            .units("ms")
            .attribute(CHANNEL_CLASS, 1, 1),
        Param::new("Channel 1 edges", DataType::Udint, 0, 0xFFFF_FFFF, 0)
            .attribute(CHANNEL_CLASS, 1, 2)
            .read_only(),
    ],
    ..EdsInfo::DEFAULT
};

#[cfg(test)]
mod tests {
    extern crate std;

    #[test]
    fn configuration_fields_and_channel_attributes_are_parameters() {
        let mut eds = std::string::String::new();
        enip_stack::eds::write_eds(&mut eds, &crate::IoBlock::new(), &super::EDS).unwrap();
        assert!(eds.contains(
            "Assem151 = \"Configuration\", \"20 04 24 97 30 03\", 4, 0x0000, , , \
             8, Param2, 8, Param3, 16, Param4;"
        ));
        assert!(eds.contains(
            "Param6 = 0, 6, \"20 70 24 01 30 02\", 0x0010, 0xC8, 4, \"Channel 1 edges\""
        ));
        // 16 one-bit members of the inputs and outputs.
        let inputs = eds.lines().find(|l| l.contains("Assem100 =")).unwrap();
        assert_eq!(inputs.matches(", 1, ").count(), 16);
    }
}
