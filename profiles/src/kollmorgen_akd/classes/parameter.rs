//! The Parameter object (class 0x0F; manual 7.3, p.25-26) as a declared class: instance =
//! the parameter's Appendix B index ([`super::super::params`]); attribute 1 the value, 5 the data
//! type code, 6 the data length.
//!
//! A value is read as exactly its data length. A write must carry exactly that length
//! (shorter 0x13, longer 0x15), except that a 64-bit parameter also takes a 32-bit value
//! (sign-extended for a signed one). Read-only parameters answer 0x0E to a write; a value a
//! parameter refuses 0x09; an unknown instance 0x16.
//!
//! Instances 1042 (EIP.CMDMAP) and 1043 (EIP.RSPMAP) are lists, not values of the table
//! ([`super::super::maps`]): [`get_map`] and [`set_map`] serve them.

use enip_stack::cip::object::{Access, AttributeDef, ClassDef, DataType};
use enip_stack::cip::{CipError, CipResult, General};
use enip_stack::wire::Writer;

use super::super::maps::{self, Maps, Which, LIST_LEN, LIST_TYPE, SLOTS};
use super::super::params::{self, id, Rule, View};
use super::super::state::State;
use super::super::storage::{Image, NvCopy, Parameters};

/// Class code.
pub const CLASS: u16 = 0x0F;
/// Attribute 1: the parameter value.
pub const VALUE: u16 = 1;
/// Attribute 5: the data type code.
pub const DATA_TYPE: u16 = 5;
/// Attribute 6: the data length.
pub const DATA_LENGTH: u16 = 6;

/// The class as the stack serves it.
pub const CLASS_DEF: ClassDef = ClassDef {
    id: CLASS,
    name: "Parameter",
    revision: 1,
    max_instance: params::id::EIP_RSPMAP as u32,
    attributes: &[
        AttributeDef::get_set(VALUE, DataType::Unsized, "Parameter Value"),
        AttributeDef::get(DATA_TYPE, DataType::Usint, "Data Type"),
        AttributeDef::get(DATA_LENGTH, DataType::Usint, "Data Length"),
    ],
    get_all: &[],
    optional_attributes: &[],
};

/// The access of attribute `id` on a parameter: the value of a read-only parameter is Get.
pub fn access(view: &View, id: u16, default: Access) -> Access {
    if id == VALUE && view.param.rule == Rule::ReadOnly {
        return Access::Get;
    }
    default
}

/// The value the instance reads, in its own length (commands read 0).
pub fn value(state: &State, view: &View) -> i64 {
    match view.param.rule {
        Rule::Command => 0,
        _ => state.param(view.param),
    }
}

/// Writes attribute `id` of the parameter `view`.
pub fn get(state: &State, view: &View, id: u16, w: &mut Writer<'_>) -> CipResult {
    match id {
        VALUE => {
            let bytes = value(state, view).to_le_bytes();
            w.bytes(bytes.get(..usize::from(view.data_len())).unwrap_or(&[]))?;
        }
        DATA_TYPE => w.u8(view.type_code())?,
        DATA_LENGTH => w.u8(view.data_len())?,
        _ => return Err(General::AttributeNotSupported.into()),
    }
    Ok(())
}

/// The value a write of `data` carries: exactly the data length, or 4 bytes for an 8-byte
/// parameter; sign-extended for signed parameters.
pub fn decode(view: &View, data: &[u8]) -> CipResult<i64> {
    let len = usize::from(view.data_len());
    let ok = data.len() == len || (len == 8 && data.len() == 4);
    if !ok {
        let g = if data.len() < len {
            General::NotEnoughData
        } else {
            General::TooMuchData
        };
        return Err(CipError::new(g));
    }
    let mut raw = [0u8; 8];
    for (dst, src) in raw.iter_mut().zip(data) {
        *dst = *src;
    }
    let bits = (data.len() as u32).saturating_mul(8);
    let unsigned = u64::from_le_bytes(raw);
    let signed = view.param.signed || view.low_word;
    Ok(if signed && (1..64).contains(&bits) {
        let shift = 64u32.saturating_sub(bits);
        ((unsigned << shift) as i64) >> shift
    } else {
        unsigned as i64
    })
}

/// Writes `value` to a parameter: commands execute (on any value), read-write ones are
/// stored, read-only ones answer 0x0E.
pub fn write(state: &mut State, nv: &mut NvCopy, view: &View, value: i64) -> CipResult {
    match view.param.rule {
        Rule::ReadOnly => Err(General::AttributeNotSettable.into()),
        Rule::Command => execute(state, nv, view.param.instance),
        Rule::ReadWrite => state.set_param(view.param, value),
    }
}

/// Executes command parameter `instance`; DRV.NVSAVE saves the read-write parameters to
/// `nv`.
fn execute(state: &mut State, nv: &mut NvCopy, instance: u16) -> CipResult {
    match instance {
        id::HOME_MOVE => state.home(),
        id::DRV_CLRFAULTS => {
            state.drive.clear_faults();
            Ok(())
        }
        id::DRV_NVSAVE => {
            let image = image(state);
            nv.save(Parameters(image))
                .map_err(|_| CipError::new(General::ResourceUnavailable))
        }
        id::MT_SET => state.tasks.set(),
        id::MT_LOAD => {
            state.tasks.load();
            Ok(())
        }
        // AIN.ZERO: the simulated analog input is always 0; nothing to zero.
        _ => Ok(()),
    }
}

/// The read-write parameters' values, in table order.
pub fn image(state: &State) -> Image {
    let mut image = [0; params::TABLE.len()];
    for (slot, p) in image.iter_mut().zip(params::TABLE.iter()) {
        if p.rule == Rule::ReadWrite {
            *slot = state.param(p);
        }
    }
    image
}

/// Reads attribute `attribute` of list `which` (EIP.CMDMAP or EIP.RSPMAP).
pub fn get_map(maps: &Maps, which: Which, attribute: u16, w: &mut Writer<'_>) -> CipResult {
    match attribute {
        VALUE => {
            for entry in maps.list(which) {
                w.bytes(&entry.to_le_bytes())?;
            }
        }
        DATA_TYPE => w.u8(LIST_TYPE)?,
        DATA_LENGTH => w.u8(LIST_LEN as u8)?,
        _ => return Err(General::AttributeNotSupported.into()),
    }
    Ok(())
}

/// Writes list `which` from `data` (14 bytes); every entry is checked before any is kept.
pub fn set_map(maps: &mut Maps, which: Which, data: &[u8]) -> CipResult {
    if data.len() != LIST_LEN {
        let g = if data.len() < LIST_LEN {
            General::NotEnoughData
        } else {
            General::TooMuchData
        };
        return Err(CipError::new(g));
    }
    let mut list = [0u16; SLOTS];
    for (slot, pair) in list.iter_mut().zip(data.chunks_exact(2)) {
        let mut bytes = [0u8; 2];
        for (dst, src) in bytes.iter_mut().zip(pair) {
            *dst = *src;
        }
        let value = u16::from_le_bytes(bytes);
        if value != 0 {
            maps::entry(which, value)?;
        }
        *slot = value;
    }
    match which {
        Which::Command => maps.command = list,
        Which::Response => maps.response = list,
    }
    Ok(())
}
