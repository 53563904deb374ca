//! The Position Controller Supervisor object (class 0x24, instance 1), which the manual
//! lists among the supported objects (p.9) without describing it. The attributes are the
//! CIP Position Controller Supervisor's that the drive has something to report for: 1
//! number of attributes, 2 attribute list, 3 axis number (1), 5 general fault (Status Word
//! 1 bit 3), 6 command message type and 7 response message type (the type codes of the
//! last command assembly, bytes 2-3 bits 0-4). All are Get only: the AKD takes its command
//! and response types from every command assembly, so setting them would change nothing
//! (0x0E). Homing and the other optional attributes are the Position Controller's
//! (class 0x25) on this drive and are not repeated here (0x14).

use enip_stack::cip::object::{AttributeDef, ClassDef, DataType};
use enip_stack::cip::{CipResult, General};
use enip_stack::wire::Writer;

use super::super::assemblies::Command;
use super::super::state::State;

/// Class code.
pub const CLASS: u16 = 0x24;

/// Attribute IDs.
pub mod attr {
    /// Number of attributes.
    pub const COUNT: u16 = 1;
    /// Attribute list.
    pub const LIST: u16 = 2;
    /// Axis number (the instance).
    pub const AXIS: u16 = 3;
    /// General fault.
    pub const GENERAL_FAULT: u16 = 5;
    /// Command message type.
    pub const COMMAND_TYPE: u16 = 6;
    /// Response message type.
    pub const RESPONSE_TYPE: u16 = 7;
}

const ATTRIBUTES: [AttributeDef; 6] = [
    AttributeDef::get(attr::COUNT, DataType::Usint, "Number of Attributes"),
    AttributeDef::get(attr::LIST, DataType::Bytes(6), "Attribute List"),
    AttributeDef::get(attr::AXIS, DataType::Usint, "Axis Number"),
    AttributeDef::get(attr::GENERAL_FAULT, DataType::Bool, "General Fault"),
    AttributeDef::get(attr::COMMAND_TYPE, DataType::Usint, "Command Message Type"),
    AttributeDef::get(
        attr::RESPONSE_TYPE,
        DataType::Usint,
        "Response Message Type",
    ),
];

/// The class as the stack serves it: one instance, no Get_Attributes_All (like 0x25).
pub const CLASS_DEF: ClassDef = ClassDef {
    id: CLASS,
    name: "Position Controller Supervisor",
    revision: 1,
    max_instance: 1,
    attributes: &ATTRIBUTES,
    get_all: &[],
    optional_attributes: &[],
};

/// Writes attribute `id`'s value; `command` is the last command assembly.
pub fn read(state: &State, command: &[u8], id: u16, w: &mut Writer<'_>) -> CipResult {
    let cmd = Command(command);
    match id {
        attr::COUNT => w.u8(ATTRIBUTES.len() as u8)?,
        attr::LIST => {
            for a in &ATTRIBUTES {
                w.u8(a.id as u8)?;
            }
        }
        attr::AXIS => w.u8(1)?,
        attr::GENERAL_FAULT => w.u8(u8::from(state.drive.fault().is_some()))?,
        attr::COMMAND_TYPE => w.u8(cmd.command_type().1)?,
        attr::RESPONSE_TYPE => w.u8(cmd.response_type())?,
        _ => return Err(General::AttributeNotSupported.into()),
    }
    Ok(())
}
