//! Class 0x65 (101) "ACR Group" (p.27-29, Table 6): 0x53 Read Group and 0x34 Write Binary
//! Command(s).
//!
//! Read Group: instance = group code x 256 + index; the data is a DINT block size 1-8
//! (else 0x20, Table 8 case 6); a group code 0x80-0xBF is invalid (0x05, case 7; "valid:
//! code < 0x80 or >= 0xC0"). Element k is P(instance + 256k) (R8.3, A25: the axis stride
//! for every code), each in its own type (REAL or DINT, p.28); a missing element 0x05.
//! The group code is checked before the block size (the path before the data).
//!
//! Write Binary: the bytes of ACR binary packets feed the command stream a Class 3
//! connection owns, so it needs one (Table 8 case 2, "No Class 3 connection exists": 0x10
//! over UCMM, R8.6). Over a Class 3 connection the commands run ([`super::binary`]); the
//! instance is ignored; no reply data. Any other service 0x08.

use enip_stack::cip::context::RequestContext;
use enip_stack::cip::object::ClassDef;
use enip_stack::cip::{CipError, CipResult, General, Request};
use enip_stack::wire::Writer;

use super::super::memory::put;
use super::super::memory::Memory;
use super::super::params::{self, AXIS_STRIDE};
use super::binary;
use super::class64::count;

/// Class code.
pub const CLASS: u16 = 0x65;
/// Read Group.
pub const READ_GROUP: u8 = 0x53;
/// Write Binary Command(s).
pub const WRITE_BINARY: u8 = 0x34;
/// Most elements of a group read.
pub const MAX_GROUP_BLOCK: usize = 8;
/// Invalid group codes (p.28).
pub const INVALID_CODES: core::ops::RangeInclusive<u32> = 0x80..=0xBF;

/// The class as the stack lists it; its instances only answer the vendor services.
pub const CLASS_DEF: ClassDef = ClassDef {
    id: CLASS,
    name: "ACR Group",
    revision: 1,
    max_instance: 0xFFFF,
    attributes: &[],
    get_all: &[],
    optional_attributes: &[],
};

/// Answers a request to class 0x65; `None` leaves a non-vendor service on the class
/// (instance 0) to the stack.
pub fn handle(
    memory: &mut Memory,
    binary_bytes: &mut u32,
    cx: &RequestContext,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> Option<CipResult> {
    let instance = req.path.instance_or_point()?;
    Some(match req.service {
        READ_GROUP => read_group(memory, instance, req.data, w),
        WRITE_BINARY if !cx.is_connected() => Err(CipError::new(General::DeviceStateConflict)),
        WRITE_BINARY => binary::execute(memory, req.data).map(|()| {
            *binary_bytes = binary_bytes.wrapping_add(req.data.len() as u32);
        }),
        _ if instance == 0 => return None,
        _ => Err(General::ServiceNotSupported.into()),
    })
}

/// 0x53: `n` elements P(instance + 256k), each in its native type.
fn read_group(memory: &Memory, instance: u32, data: &[u8], w: &mut Writer<'_>) -> CipResult {
    if INVALID_CODES.contains(&(instance >> 8)) {
        return Err(CipError::new(General::PathDestinationUnknown));
    }
    let n = count(data, MAX_GROUP_BLOCK)?;
    let elements = (0..n as u32).map(|k| instance.saturating_add(k.saturating_mul(AXIS_STRIDE)));
    let mut values = [None; MAX_GROUP_BLOCK];
    for (slot, p) in values.iter_mut().zip(elements) {
        *slot = Some(
            memory
                .get(p)
                .ok_or(CipError::new(General::PathDestinationUnknown))?,
        );
    }
    for value in values.iter().flatten() {
        let kind = match value {
            params::Value::Long(_) => params::Kind::Long,
            params::Value::Float(_) => params::Kind::Float,
        };
        put(w, *value, kind)?;
    }
    Ok(())
}
