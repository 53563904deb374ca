//! An own device, as a device author writes it outside this workspace: a 4-input / 2-output
//! analog module (16-bit channels) with a configuration assembly, and its EDS choices.
//! `cargo xtask test` builds it in a cargo project of its own from the README's
//! `[dependencies]` and `main` ("Build your own device") and checks the EDS it prints.

use enip_stack::cip::object::DataType;
use enip_stack::cip::{CipError, CipResult, General};
use enip_stack::eds::{EdsInfo, Layout, Member, Param};
use enip_stack::{AssemblyInfo, AssemblyRole, Device, IdentityInfo};

const IDENTITY: IdentityInfo = IdentityInfo {
    vendor_id: 0xFFFF,
    device_type: 0x0A, // general purpose analog I/O
    product_code: 42,
    revision: (1, 1),
    serial_number: 0x0000_4242,
    product_name: "Analog 4/2 module",
};
const INPUTS: u16 = 100;
const OUTPUTS: u16 = 150;
const CONFIG: u16 = 151;
const ASSEMBLIES: [AssemblyInfo; 5] = [
    AssemblyInfo {
        instance: INPUTS,
        role: AssemblyRole::Input,
        size: 8,
        run_idle_header: false,
    },
    AssemblyInfo {
        instance: OUTPUTS,
        role: AssemblyRole::Output,
        size: 4,
        run_idle_header: true,
    },
    AssemblyInfo {
        instance: CONFIG,
        role: AssemblyRole::Config,
        size: 4,
        run_idle_header: false,
    },
    AssemblyInfo {
        instance: 152,
        role: AssemblyRole::InputOnlyHeartbeat,
        size: 0,
        run_idle_header: false,
    },
    AssemblyInfo {
        instance: 153,
        role: AssemblyRole::ListenOnlyHeartbeat,
        size: 0,
        run_idle_header: false,
    },
];

/// The EDS: 16-bit channels, the configuration assembly field by field.
pub const EDS: EdsInfo<'static> = EdsInfo {
    description: "Analog 4/2 module",
    vendor_name: "Example Automation",
    catalog: "AN-42",
    member_bits: 16,
    layouts: &[Layout {
        instance: CONFIG,
        members: &[Member::Param(0), Member::Param(1), Member::Param(2)],
    }],
    params: &[
        Param::new("Input filter", DataType::Usint, 0, 100, 10).units("ms"),
        Param::new("Input range", DataType::Usint, 0, 2, 0)
            .help("0: 0-10 V, 1: +-10 V, 2: 4-20 mA"),
        Param::new("Input offset", DataType::Int, -1000, 1000, 0),
    ],
    ..EdsInfo::DEFAULT
};

/// The module: outputs loop back to inputs 0 and 1, scaled by the configuration.
pub struct Analog {
    inputs: [i16; 4],
    outputs: [i16; 2],
    config: [u8; 4],
}

impl Analog {
    /// At power-up: outputs 0, filter 10 ms, range 0-10 V, no offset.
    pub fn new() -> Self {
        Analog {
            inputs: [0; 4],
            outputs: [0; 2],
            config: [10, 0, 0, 0],
        }
    }
}

impl Device for Analog {
    fn identity(&self) -> &IdentityInfo {
        &IDENTITY
    }
    fn assemblies(&self) -> &[AssemblyInfo] {
        &ASSEMBLIES
    }
    // `out` is exactly the assembly's size.
    fn read_assembly(&mut self, instance: u16, out: &mut [u8]) -> CipResult<usize> {
        let mut w = enip_stack::wire::Writer::new(out);
        match instance {
            INPUTS => self.inputs.iter().try_for_each(|v| w.i16(*v)),
            OUTPUTS => self.outputs.iter().try_for_each(|v| w.i16(*v)),
            CONFIG => w.bytes(&self.config),
            _ => return Err(General::ObjectDoesNotExist.into()),
        }
        .map_err(|_| General::ReplyDataTooLarge)?;
        Ok(w.len())
    }
    // Heartbeat assemblies never come here; `data` is exactly the assembly's size.
    fn write_assembly(&mut self, instance: u16, data: &[u8]) -> CipResult {
        match (instance, data) {
            (OUTPUTS, &[a0, a1, b0, b1]) => {
                self.outputs = [i16::from_le_bytes([a0, a1]), i16::from_le_bytes([b0, b1])];
                let offset = i16::from_le_bytes([self.config[2], self.config[3]]);
                self.inputs[0] = self.outputs[0].saturating_add(offset);
                self.inputs[1] = self.outputs[1].saturating_add(offset);
            }
            // The one configuration check: refuses a Forward_Open with 0x01/0x0110 and the
            // offending byte, a Set with 0x09.
            (CONFIG, &[filter, range, o0, o1]) => {
                let bad = |byte| Err(CipError::connection(0x0110).with_additional(0x0110, byte));
                let offset = i16::from_le_bytes([o0, o1]);
                match () {
                    _ if filter > 100 => return bad(0),
                    _ if range > 2 => return bad(1),
                    _ if !(-1000..=1000).contains(&offset) => return bad(2),
                    _ => self.config = [filter, range, o0, o1],
                }
            }
            _ => return Err(General::AttributeNotSettable.into()),
        }
        Ok(())
    }
}
