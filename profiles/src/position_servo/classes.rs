//! The System940 object (class 0x64, 7.2): instance = variable ID; attributes 0/1 integer,
//! 2/3 REAL, 4/5 string, the even ones the RAM copy, the odd ones the EPM copy. Declared as
//! a [`ClassDef`]: the stack serves every service and status rule, this module only converts
//! values.
//!
//! Attributes 1, 3 and 5 are "write-only" in the manual's sense: reading them gives
//! attributes 0, 2 and 4 (the RAM copy). Writing the EPM copy also writes the RAM copy
//! (PM94H201: "this change is done both in the user program's RAM memory as well as in the
//! EPM"); writing the RAM copy leaves the EPM alone. Strings carry a 4-byte length header
//! (the number of ASCII bytes after it) and hold the value in decimal (hexadecimal `0x...` is
//! accepted for unsigned words).
//!
//! Services: Get/Set_Attribute_Single, Get/Set_Attribute_List, and Get_Attributes_All
//! (attributes 0, 2 and 4 in that order); the class (instance 0) answers its attributes 1-7
//! (revision 1, highest instance 275). Statuses: unknown variable 0x16, unknown attribute
//! 0x14, read-only variable (or EPM write of a variable without an EPM copy) 0x0E, value
//! out of range 0x09, wrong data length 0x13/0x15, action refused by the drive 0x10.

use core::fmt::Write as _;

use enip_stack::cip::object::{Access, AttributeDef, ClassDef, DataType};
use enip_stack::cip::{CipError, CipResult, General};
use enip_stack::device::AttributeRef;
use enip_stack::wire::Writer;

use super::params::{self, Format, Value, Variable, Variables};

/// Class code of the System940 object.
pub const CLASS: u16 = 0x64;
/// Longest decimal text of a value (a negative subnormal REAL).
const MAX_TEXT: usize = 48;
/// Longest text a write may carry.
const MAX_TEXT_IN: u16 = 64;

/// The System940 class as the stack serves it.
pub const CLASS_DEF: ClassDef = ClassDef {
    id: CLASS,
    name: "System940",
    revision: 1,
    max_instance: params::TABLE[params::COUNT - 1].id as u32,
    attributes: &[
        AttributeDef::get_set(0, DataType::Dint, "Value as integer (RAM)"),
        AttributeDef::get_set(1, DataType::Dint, "Value as integer (RAM and EPM)"),
        AttributeDef::get_set(2, DataType::Real, "Value as REAL (RAM)"),
        AttributeDef::get_set(3, DataType::Real, "Value as REAL (RAM and EPM)"),
        AttributeDef::get_set(
            4,
            DataType::CountedBytes { max: MAX_TEXT_IN },
            "Value as text (RAM)",
        ),
        AttributeDef::get_set(
            5,
            DataType::CountedBytes { max: MAX_TEXT_IN },
            "Value as text (RAM and EPM)",
        ),
    ],
    get_all: &[0, 2, 4],
    optional_attributes: &[],
};

/// How an attribute presents the value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Encoding {
    Integer,
    Real,
    Text,
}

/// The encoding of attribute `id`, and whether it addresses the EPM copy.
fn encoding(id: u16) -> (Encoding, bool) {
    let kind = match id / 2 {
        0 => Encoding::Integer,
        1 => Encoding::Real,
        _ => Encoding::Text,
    };
    (kind, id % 2 == 1)
}

/// The variable instance `instance` names.
pub fn variable(instance: u32) -> Option<&'static Variable> {
    u16::try_from(instance)
        .ok()
        .and_then(params::find)
        .map(|(_, v)| v)
}

/// Read-only variables, and the EPM attributes of variables without an EPM copy, are Get.
pub fn access(at: &AttributeRef<'_>) -> Access {
    let (_, epm) = encoding(at.attribute.id);
    match variable(at.instance) {
        Some(var) if var.writable(epm).is_ok() => Access::GetSet,
        _ => Access::Get,
    }
}

/// Writes variable `var`'s RAM value in the encoding of attribute `id`.
pub fn get(vars: &Variables, var: &Variable, id: u16, w: &mut Writer<'_>) -> CipResult {
    let raw = vars.raw(var.id);
    match encoding(id).0 {
        Encoding::Integer => w.u32(var.int_bits(raw))?,
        Encoding::Real => w.bytes(&var.real(raw).to_le_bytes())?,
        Encoding::Text => {
            let text = text(var, raw)?;
            w.u32(text.len() as u32)?;
            w.bytes(text.as_bytes())?;
        }
    }
    Ok(())
}

/// Decodes the value of a Set of attribute `id` (exactly its bytes); with the EPM flag.
pub fn decode(var: &Variable, id: u16, value: &[u8]) -> CipResult<(Value, bool)> {
    let (kind, epm) = encoding(id);
    let four = || <[u8; 4]>::try_from(value.get(..4).unwrap_or(&[])).map_err(|_| not_enough());
    let decoded = match kind {
        Encoding::Integer => Value::Integer(u32::from_le_bytes(four()?)),
        Encoding::Real => Value::Real(f32::from_le_bytes(four()?)),
        Encoding::Text => parse(var, value.get(4..).unwrap_or(&[]))?,
    };
    Ok((decoded, epm))
}

fn not_enough() -> CipError {
    CipError::new(General::NotEnoughData)
}

/// The decimal text of native bits `raw`.
fn text(var: &Variable, raw: u32) -> CipResult<heapless::String<MAX_TEXT>> {
    let mut s = heapless::String::new();
    let written = match var.format {
        Format::Int => write!(s, "{}", raw as i32),
        Format::Word => write!(s, "{}", raw),
        Format::Real => write!(s, "{}", f32::from_bits(raw)),
    };
    written.map_err(|_| CipError::new(General::ReplyDataTooLarge))?;
    Ok(s)
}

/// Parses decimal (or `0x` hexadecimal for words) ASCII text into a value for `var`.
fn parse(var: &Variable, body: &[u8]) -> CipResult<Value> {
    let invalid = || CipError::new(General::InvalidAttributeValue);
    let text = core::str::from_utf8(body).map_err(|_| invalid())?.trim();
    let integer = match var.format {
        Format::Int => text.parse::<i32>().ok().map(|i| i as u32),
        Format::Word => match text.strip_prefix("0x").or(text.strip_prefix("0X")) {
            Some(hex) => u32::from_str_radix(hex, 16).ok(),
            None => text.parse::<u32>().ok(),
        },
        Format::Real => None,
    };
    match integer {
        Some(bits) => Ok(Value::Integer(bits)),
        None => text.parse::<f32>().map(Value::Real).map_err(|_| invalid()),
    }
}
