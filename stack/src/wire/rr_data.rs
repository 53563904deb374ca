//! The SendRRData / SendUnitData data part: interface handle, timeout, then a CPF.

use super::bytes::{get_u16, get_u32};
use super::{Error, Result, Writer};

/// Bytes before the CPF.
pub const PREFIX_LEN: usize = 6;

/// A view over SendRRData or SendUnitData data.
#[derive(Debug, Clone)]
pub struct Packet<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> Packet<T> {
    /// Wraps data that holds at least the interface handle and timeout.
    pub fn new_checked(buffer: T) -> Result<Self> {
        if buffer.as_ref().len() < PREFIX_LEN {
            return Err(Error::Truncated);
        }
        Ok(Packet { buffer })
    }
    /// Interface handle (0 for CIP).
    pub fn interface_handle(&self) -> u32 {
        get_u32(self.buffer.as_ref(), 0)
    }
    /// Timeout in seconds (SendRRData only; zero in SendUnitData).
    pub fn timeout(&self) -> u16 {
        get_u16(self.buffer.as_ref(), 4)
    }
    /// The Common Packet Format that follows.
    pub fn cpf(&self) -> &[u8] {
        self.buffer.as_ref().get(PREFIX_LEN..).unwrap_or(&[])
    }
}

/// Writes the interface handle and timeout of a reply.
pub fn emit_prefix(w: &mut Writer<'_>, interface_handle: u32, timeout: u16) -> Result<()> {
    w.u32(interface_handle)?;
    w.u16(timeout)
}
