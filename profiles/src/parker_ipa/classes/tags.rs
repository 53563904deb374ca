//! Tag services (Table 5, p.18-20): the path is an ANSI extended symbolic segment naming a
//! parameter, "P4012" (`91 05 'P4012' 00`), with no class or instance.
//!
//! - 0x4C CIP Data Table Read: UINT count; reply type 0x00C4 (DINT) and count DINTs, a
//!   float converted (R9.2). Count 0 or above 16: 0x20 (Table 8 case 3).
//! - 0x4D CIP Data Table Write: UINT type (0x00C4 DINT or 0x00CA REAL, else 0x20), UINT
//!   count, count x 4 bytes, converted to each parameter's type (R9.3). Count above 16: 0x15
//!   (case 4); count 0: 0x20; less data than count x 4: 0x13, more: 0x15.
//! - 0x48 Vendor Float Read: as 0x4C with type 0x00CA and REALs (R9.5, A8).
//! - 0x4E Vendor AND and OR Mask: DINT AND mask, DINT OR mask, as class 0x64's 0x54
//!   (fewer than 8 bytes 0x13).
//!
//! Names: 'P' or 'p' and 1-5 decimal digits up to 65535; anything else, or more segments
//! after the name, 0x04; a well-formed name of a parameter that does not exist 0x05; any
//! other service on a tag 0x08.

use enip_stack::cip::{CipError, CipResult, General, Request};
use enip_stack::wire::Writer;

use super::super::memory::Memory;
use super::super::params::Kind;
use super::class64::{masks, MAX_BLOCK};

/// CIP Data Table Read.
pub const READ_TAG: u8 = 0x4C;
/// CIP Data Table Write.
pub const WRITE_TAG: u8 = 0x4D;
/// Vendor Float Read.
pub const READ_FLOAT_TAG: u8 = 0x48;
/// Vendor AND and OR Mask.
pub const AND_OR_TAG: u8 = 0x4E;
/// CIP type code of a DINT.
pub const DINT: u16 = 0x00C4;
/// CIP type code of a REAL.
pub const REAL: u16 = 0x00CA;

/// Answers a request whose path is a tag; `None` if the path has no symbolic segment.
pub fn handle(memory: &mut Memory, req: &Request<'_>, w: &mut Writer<'_>) -> Option<CipResult> {
    let symbol = req.path.symbol?;
    Some(serve(memory, symbol, req, w))
}

fn err(g: General) -> CipError {
    CipError::new(g)
}

/// Parameter number of a tag: 'P' or 'p' then 1-5 digits, at most 65535.
pub fn parameter(name: &[u8]) -> Option<u32> {
    let (first, digits) = name.split_first()?;
    if !matches!(first, b'P' | b'p') || digits.is_empty() || digits.len() > 5 {
        return None;
    }
    let mut n: u32 = 0;
    for d in digits {
        if !d.is_ascii_digit() {
            return None;
        }
        n = n
            .saturating_mul(10)
            .saturating_add(u32::from(d.wrapping_sub(b'0')));
    }
    (n <= 0xFFFF).then_some(n)
}

fn serve(memory: &mut Memory, symbol: &[u8], req: &Request<'_>, w: &mut Writer<'_>) -> CipResult {
    let p = &req.path;
    let extra = p.class.is_some()
        || p.instance.is_some()
        || p.attribute.is_some()
        || p.member.is_some()
        || p.connection_point.is_some();
    let first = parameter(symbol)
        .filter(|_| !extra)
        .ok_or(err(General::PathSegmentError))?;
    match req.service {
        READ_TAG => read(memory, first, req.data, Kind::Long, DINT, w),
        READ_FLOAT_TAG => read(memory, first, req.data, Kind::Float, REAL, w),
        WRITE_TAG => write(memory, first, req.data),
        AND_OR_TAG => {
            let (and, or) = masks(req.data)?;
            memory.and_or(first, and, or)
        }
        _ => Err(err(General::ServiceNotSupported)),
    }
}

fn uint(data: &[u8], at: usize) -> CipResult<u16> {
    match data.get(at..at.saturating_add(2)) {
        Some(&[a, b]) => Ok(u16::from_le_bytes([a, b])),
        _ => Err(err(General::NotEnoughData)),
    }
}

/// 0x4C/0x48: the type word then `count` values as `kind`.
fn read(
    memory: &mut Memory,
    first: u32,
    data: &[u8],
    kind: Kind,
    code: u16,
    w: &mut Writer<'_>,
) -> CipResult {
    let n = usize::from(uint(data, 0)?);
    if n == 0 || n > MAX_BLOCK {
        return Err(err(General::InvalidParameter));
    }
    memory.check(first, n)?;
    w.u16(code)?;
    memory.read_block(first, n, kind, w)
}

/// 0x4D: type, count, values.
fn write(memory: &mut Memory, first: u32, data: &[u8]) -> CipResult {
    let kind = match uint(data, 0)? {
        DINT => Kind::Long,
        REAL => Kind::Float,
        _ => return Err(err(General::InvalidParameter)),
    };
    let n = usize::from(uint(data, 2)?);
    if n > MAX_BLOCK {
        return Err(err(General::TooMuchData));
    }
    if n == 0 {
        return Err(err(General::InvalidParameter));
    }
    let values = data.get(4..).unwrap_or(&[]);
    if values.len() < 4 * n {
        return Err(err(General::NotEnoughData));
    }
    if values.len() > 4 * n {
        return Err(err(General::TooMuchData));
    }
    memory.write_block(first, values, kind)
}
