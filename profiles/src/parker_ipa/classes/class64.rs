//! Class 0x64 (100) "ACR Parameter" (p.22-27, Table 6): instance = P number, attribute
//! ignored (present, absent or any value). Services 0x50 Write Float(s), 0x51 Read Float(s),
//! 0x52 Write Long(s), 0x53 Read Long(s), 0x54 AND and OR, on P(instance)..P(instance+n-1)
//! with type conversion (p.23).
//!
//! Statuses (Table 8, digest R8.1): a read of more than 16 (or fewer than 1) 0x20; a write
//! of more than 16 values 0x15; write data that is empty or not a multiple of 4, a count
//! shorter than 4 bytes, or masks shorter than 8 bytes 0x13; a parameter of the range that
//! does not exist 0x05; any other service 0x08. Extra bytes after a count or the two masks
//! are ignored (the manual: the Source Length "must be at least 8"). A refused request
//! writes nothing.

use enip_stack::cip::object::{AttributeDef, ClassDef, DataType};
use enip_stack::cip::{CipError, CipResult, General, Request};
use enip_stack::wire::Writer;

use super::super::memory::Memory;
use super::super::params::{Kind, COUNT};

/// Class code.
pub const CLASS: u16 = 0x64;
/// Write Float(s).
pub const WRITE_FLOATS: u8 = 0x50;
/// Read Float(s).
pub const READ_FLOATS: u8 = 0x51;
/// Write Long(s).
pub const WRITE_LONGS: u8 = 0x52;
/// Read Long(s).
pub const READ_LONGS: u8 = 0x53;
/// AND and OR.
pub const AND_OR: u8 = 0x54;
/// Most parameters one request reads or writes (Table 8 cases 3 and 4).
pub const MAX_BLOCK: usize = 16;

/// The class as the stack lists it (class attributes at instance 0); its instances only
/// answer the vendor services.
pub const CLASS_DEF: ClassDef = ClassDef {
    id: CLASS,
    name: "ACR Parameter",
    revision: 1,
    max_instance: 0xFFFF,
    attributes: &[AttributeDef::get(1, DataType::Dint, "Value (ignored)")],
    get_all: &[],
    optional_attributes: &[],
};

/// Answers a request to class 0x64; `None` leaves a non-vendor service on the class
/// (instance 0) to the stack.
pub fn handle(memory: &mut Memory, req: &Request<'_>, w: &mut Writer<'_>) -> Option<CipResult> {
    let instance = req.path.instance_or_point()?;
    Some(match req.service {
        WRITE_FLOATS => write(memory, instance, req.data, Kind::Float),
        WRITE_LONGS => write(memory, instance, req.data, Kind::Long),
        READ_FLOATS => read(memory, instance, req.data, Kind::Float, w),
        READ_LONGS => read(memory, instance, req.data, Kind::Long, w),
        AND_OR => and_or(memory, instance, req.data),
        _ if instance == 0 => return None,
        _ => Err(General::ServiceNotSupported.into()),
    })
}

fn err(g: General) -> CipError {
    CipError::new(g)
}

/// The DINT count at the start of a read request: fewer than 4 bytes 0x13, below 1 or
/// above `max` 0x20.
pub fn count(data: &[u8], max: usize) -> CipResult<usize> {
    let n = match data.get(..4) {
        Some(&[b0, b1, b2, b3]) => i32::from_le_bytes([b0, b1, b2, b3]),
        _ => return Err(err(General::NotEnoughData)),
    };
    usize::try_from(n)
        .ok()
        .filter(|&n| (1..=max).contains(&n))
        .ok_or(err(General::InvalidParameter))
}

/// 0x51/0x53: `n` values from P(first) converted to `kind`.
fn read(memory: &mut Memory, first: u32, data: &[u8], kind: Kind, w: &mut Writer<'_>) -> CipResult {
    let n = count(data, MAX_BLOCK)?;
    memory.read_block(first, n, kind, w)
}

/// 0x50/0x52: the values in `data` (each 4 bytes of `kind`) to P(first)...
fn write(memory: &mut Memory, first: u32, data: &[u8], kind: Kind) -> CipResult {
    if data.is_empty() || !data.len().is_multiple_of(4) {
        return Err(err(General::NotEnoughData));
    }
    if data.len() / 4 > MAX_BLOCK {
        return Err(err(General::TooMuchData));
    }
    memory.write_block(first, data, kind)
}

/// The AND and OR masks at the start of `data`; fewer than 8 bytes 0x13 (Table 8 case 5).
pub fn masks(data: &[u8]) -> CipResult<(i32, i32)> {
    match data.get(..8) {
        Some(&[a0, a1, a2, a3, o0, o1, o2, o3]) => Ok((
            i32::from_le_bytes([a0, a1, a2, a3]),
            i32::from_le_bytes([o0, o1, o2, o3]),
        )),
        _ => Err(err(General::NotEnoughData)),
    }
}

/// 0x54: P(instance) = (P AND mask1) OR mask2, computed on the long (a float parameter is
/// converted to long and back, R8.1).
fn and_or(memory: &mut Memory, p: u32, data: &[u8]) -> CipResult {
    let (and, or) = masks(data)?;
    memory.and_or(p, and, or)
}

/// Number of existing parameters (class attribute 3).
pub const INSTANCES: u32 = COUNT as u32;
