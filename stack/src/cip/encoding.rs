//! Encoders for CIP elementary types used by attribute values.

use crate::wire::{Result, Writer};

/// SHORT_STRING: one length byte and the characters (truncated at 255).
pub(crate) fn short_string(w: &mut Writer<'_>, s: &[u8]) -> Result<()> {
    let s = s.get(..s.len().min(255)).unwrap_or(&[]);
    w.u8(s.len() as u8)?;
    w.bytes(s)
}

/// STRING as the TCP/IP object uses it: a 16-bit length, the characters, a pad byte if odd.
pub(crate) fn padded_string(w: &mut Writer<'_>, s: &[u8]) -> Result<()> {
    let s = s.get(..s.len().min(usize::from(u16::MAX))).unwrap_or(&[]);
    w.u16(s.len() as u16)?;
    w.bytes(s)?;
    if s.len() % 2 == 1 {
        w.u8(0)?;
    }
    Ok(())
}

/// An IPv4 address as a CIP UDINT (198.18.0.2 is 0xC6120002).
pub(crate) fn ip(w: &mut Writer<'_>, a: core::net::Ipv4Addr) -> Result<()> {
    w.u32(u32::from(a))
}
