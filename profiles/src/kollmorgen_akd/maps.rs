//! EIP.CMDMAP and EIP.RSPMAP: the two lists that say which parameters map type 2 (the
//! dynamic map, [`super::dynamic_map`]) carries in bytes 36-63 of the command and response
//! assemblies, served as two instances of the Parameter object (class 0x0F).
//!
//! - Instances: EIP.CMDMAP **1042**, EIP.RSPMAP **1043**, project instances after the last
//!   of the profile's table (1041), as for every parameter whose Appendix B index no
//!   retrieved copy gives.
//! - Value (attribute 1): [`SLOTS`] UINTs, 14 bytes, LSB first: entry k is the Parameter
//!   instance (Appendix B numbering, [`super::params`]) carried in slot k, bytes
//!   36 + 4k .. 40 + 4k; 0 leaves the slot empty. Attribute 5 is 0xC7 (UINT, the type of an
//!   entry), attribute 6 is 14. Power-up: all 0 (the manual's default value).
//! - A write must be exactly 14 bytes (shorter 0x13, longer 0x15). Every entry must be an
//!   instance the slot can carry, else the write answers 0x09 and changes nothing:
//!   EIP.RSPMAP takes read-write and read-only parameters, EIP.CMDMAP read-write ones only;
//!   commands (HOME.MOVE...), unknown instances and the lists themselves are refused.
//! - The lists are RAM only: DRV.NVSAVE does not store them (its image holds one 64-bit
//!   value per parameter of the table).

use enip_stack::cip::{CipError, CipResult, General};

use super::params::{self, id, Rule, View};

/// Slots of the dynamic map: 28 bytes of 4-byte values.
pub const SLOTS: usize = 7;
/// Bytes of a list's value: one UINT per slot.
pub const LIST_LEN: usize = 2 * SLOTS;
/// Attribute 5 of a list: UINT, the type of one entry.
pub const LIST_TYPE: u8 = 0xC7;

/// Which list an instance is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Which {
    /// EIP.CMDMAP: the command assembly's bytes 36-63.
    Command,
    /// EIP.RSPMAP: the response assembly's bytes 36-63.
    Response,
}

/// The list instance `instance` addresses, if it is one.
pub fn which(instance: u32) -> Option<Which> {
    match u16::try_from(instance).ok()? {
        id::EIP_CMDMAP => Some(Which::Command),
        id::EIP_RSPMAP => Some(Which::Response),
        _ => None,
    }
}

/// How many list instances there are.
pub const INSTANCES: u32 = 2;

/// The two lists: Parameter instances per slot, 0 for an empty slot.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Maps {
    /// EIP.CMDMAP.
    pub command: [u16; SLOTS],
    /// EIP.RSPMAP.
    pub response: [u16; SLOTS],
}

impl Maps {
    /// Power-up: every slot empty.
    pub const fn new() -> Self {
        Maps {
            command: [0; SLOTS],
            response: [0; SLOTS],
        }
    }
    /// The list `which`.
    pub fn list(&self, which: Which) -> &[u16; SLOTS] {
        match which {
            Which::Command => &self.command,
            Which::Response => &self.response,
        }
    }
}

/// The parameter a non-empty entry of list `which` carries, or 0x09 when the slot cannot
/// carry `entry`.
pub fn entry(which: Which, entry: u16) -> CipResult<View> {
    let view = params::view(u32::from(entry)).ok_or(invalid())?;
    match (which, view.param.rule) {
        (_, Rule::ReadWrite) | (Which::Response, Rule::ReadOnly) => Ok(view),
        _ => Err(invalid()),
    }
}

fn invalid() -> CipError {
    CipError::new(General::InvalidAttributeValue)
}
