//! The System940 object (class 0x64, 7.2): instance = variable ID; attributes 0/1 integer,
//! 2/3 REAL, 4/5 string, the even ones the RAM copy, the odd ones the EPM copy.
//!
//! Attributes 1, 3 and 5 are write-only: reading them gives attributes 0, 2 and 4. Writing
//! the EPM copy also writes the RAM copy (PM94H201: "this change is done both in the user
//! program's RAM memory as well as in the EPM"); writing the RAM copy leaves the EPM alone.
//! Strings carry a 4-byte length header (the number of ASCII bytes after it) and hold the
//! value in decimal (hexadecimal `0x...` is accepted for unsigned words).
//!
//! Services: Get_Attribute_Single, Set_Attribute_Single and Get_Attributes_All (attributes
//! 0, 2 and 4 in that order); the class (instance 0) answers Get_Attribute_Single of its
//! revision (1) and maximum instance (2). Statuses: unknown variable 0x16, unknown attribute
//! 0x14, read-only variable (or EPM write of a variable without an EPM copy) 0x0E, value
//! out of range 0x09, wrong data length 0x13/0x15, action refused by the drive 0x10.

use core::fmt::Write as _;

use stack::cip::service::{GET_ATTRIBUTES_ALL, GET_ATTRIBUTE_SINGLE, SET_ATTRIBUTE_SINGLE};
use stack::cip::{CipError, CipResult, General, Request};
use stack::wire::Writer;

use super::storage::EpmStorage;
use super::variables::{self, Format, Value, Variable, Variables};
use super::PositionServo;

/// Class code of the System940 object.
pub const CLASS: u16 = 0x64;
/// Class revision (class attribute 1).
const REVISION: u16 = 1;
/// Longest decimal text of a value (a negative subnormal REAL).
const MAX_TEXT: usize = 48;

/// How an attribute presents the value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Encoding {
    Integer,
    Real,
    Text,
}

/// The encoding of attribute `id`, and whether it addresses the EPM copy.
fn attribute(id: Option<u32>) -> CipResult<(Encoding, bool)> {
    match id {
        None => Err(General::PathDestinationUnknown.into()),
        Some(0) => Ok((Encoding::Integer, false)),
        Some(1) => Ok((Encoding::Integer, true)),
        Some(2) => Ok((Encoding::Real, false)),
        Some(3) => Ok((Encoding::Real, true)),
        Some(4) => Ok((Encoding::Text, false)),
        Some(5) => Ok((Encoding::Text, true)),
        Some(_) => Err(General::AttributeNotSupported.into()),
    }
}

/// Handles a request to class 0x64.
pub fn handle<S: EpmStorage>(
    servo: &mut PositionServo<S>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    let instance = req
        .path
        .instance_or_point()
        .ok_or(CipError::new(General::PathDestinationUnknown))?;
    if instance == 0 {
        return class(req, w);
    }
    let var = u16::try_from(instance)
        .ok()
        .and_then(variables::find)
        .map(|(_, v)| v)
        .ok_or(CipError::new(General::ObjectDoesNotExist))?;
    match req.service {
        GET_ATTRIBUTE_SINGLE => {
            let (encoding, _) = attribute(req.path.attribute)?;
            no_data(req)?;
            get(servo.variables(), var, encoding, w)
        }
        SET_ATTRIBUTE_SINGLE => {
            let (encoding, epm) = attribute(req.path.attribute)?;
            var.writable(epm)?;
            let value = decode(var, encoding, req.data)?;
            servo.write(var.id, value, epm)
        }
        GET_ATTRIBUTES_ALL => {
            no_data(req)?;
            [Encoding::Integer, Encoding::Real, Encoding::Text]
                .into_iter()
                .try_for_each(|e| get(servo.variables(), var, e, w))
        }
        _ => Err(General::ServiceNotSupported.into()),
    }
}

fn no_data(req: &Request<'_>) -> CipResult {
    if req.data.is_empty() {
        Ok(())
    } else {
        Err(General::TooMuchData.into())
    }
}

/// Class attributes: revision and maximum instance.
fn class(req: &Request<'_>, w: &mut Writer<'_>) -> CipResult {
    if req.service != GET_ATTRIBUTE_SINGLE {
        return Err(General::ServiceNotSupported.into());
    }
    no_data(req)?;
    let max_instance = variables::TABLE.last().map_or(0, |v| v.id);
    match req.path.attribute {
        Some(1) => w.u16(REVISION)?,
        Some(2) => w.u16(max_instance)?,
        None => return Err(General::PathDestinationUnknown.into()),
        Some(_) => return Err(General::AttributeNotSupported.into()),
    }
    Ok(())
}

/// Writes variable `var`'s RAM value in `encoding`.
fn get(vars: &Variables, var: &Variable, encoding: Encoding, w: &mut Writer<'_>) -> CipResult {
    let raw = vars.raw(var.id);
    match encoding {
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

/// Decodes Set_Attribute_Single data in `encoding` for variable `var`.
fn decode(var: &Variable, encoding: Encoding, data: &[u8]) -> CipResult<Value> {
    match encoding {
        Encoding::Integer => Ok(Value::Integer(u32::from_le_bytes(exactly_4(data)?))),
        Encoding::Real => Ok(Value::Real(f32::from_le_bytes(exactly_4(data)?))),
        Encoding::Text => {
            let header = data.get(..4).ok_or(CipError::new(General::NotEnoughData))?;
            let len = u32::from_le_bytes(exactly_4(header)?) as usize;
            let body = data.get(4..).unwrap_or(&[]);
            match body.len().cmp(&len) {
                core::cmp::Ordering::Less => Err(General::NotEnoughData.into()),
                core::cmp::Ordering::Greater => Err(General::TooMuchData.into()),
                core::cmp::Ordering::Equal => parse(var, body),
            }
        }
    }
}

fn exactly_4(data: &[u8]) -> CipResult<[u8; 4]> {
    match data.len() {
        0..=3 => Err(General::NotEnoughData.into()),
        4 => <[u8; 4]>::try_from(data).map_err(|_| General::NotEnoughData.into()),
        _ => Err(General::TooMuchData.into()),
    }
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
