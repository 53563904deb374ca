//! The Parameter object (class 0x0F; manual 7.3, p.25-26) as a declared class: instance =
//! the parameter's Appendix B index ([`super::super::params`]); attribute 1 the value, 5 the data
//! type code, 6 the data length.
//!
//! A value is read as exactly its data length. A write must carry exactly that length
//! (shorter 0x13, longer 0x15), except that a 64-bit parameter also takes a 32-bit value
//! (sign-extended for a signed one). Read-only parameters answer 0x0E to a write; a value a
//! parameter refuses 0x09; an unknown instance 0x16.
//!
//! Instances 1042 (EIP.CMDMAP) and 1043 (EIP.RSPMAP) are lists, not values of the table:
//! [`super::super::maps`] serves them.

use enip_stack::cip::object::{Access, AttributeDef, ClassDef, DataType};
use enip_stack::cip::{CipError, CipResult, General};
use enip_stack::wire::Writer;

use super::super::params::{self, Rule, View};
use super::super::state::State;

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
        _ => params::read(state, view.param),
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
