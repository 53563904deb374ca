//! The SendRRData / SendUnitData data part: interface handle, timeout, then a CPF.

use super::bytes::{get_u16, get_u32};
use super::cpf::{item_type, ItemHeaderRepr, ItemRepr};
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

/// The interface handle and timeout before the CPF, parsed or to emit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RrDataRepr {
    /// Interface handle (0 for CIP).
    pub interface_handle: u32,
    /// Timeout in seconds (SendRRData only; zero in SendUnitData and in replies).
    pub timeout: u16,
}

impl RrDataRepr {
    /// The prefix of a reply, and of a SendUnitData request: CIP, no timeout.
    pub const CIP: RrDataRepr = RrDataRepr {
        interface_handle: 0,
        timeout: 0,
    };
    /// Parses the prefix of checked data.
    pub fn parse<T: AsRef<[u8]>>(p: &Packet<T>) -> RrDataRepr {
        RrDataRepr {
            interface_handle: p.interface_handle(),
            timeout: p.timeout(),
        }
    }
    /// Bytes the prefix takes.
    pub const fn buffer_len(&self) -> usize {
        PREFIX_LEN
    }
    /// Writes the prefix (the caller writes the CPF after it).
    pub fn emit(&self, w: &mut Writer<'_>) -> Result<()> {
        w.u32(self.interface_handle)?;
        w.u16(self.timeout)
    }
}

/// Writes the data part of a SendUnitData frame, request or reply, up to its message: the CIP
/// prefix, the connected address item of `connection_id`, then the connected data item's
/// header and `sequence` count. Returns where that item's data begins, for
/// [`Writer::patch_item_len`] once the message after it is written.
pub fn emit_connected(w: &mut Writer<'_>, connection_id: u32, sequence: u16) -> Result<usize> {
    RrDataRepr::CIP.emit(w)?;
    w.u16(2)?;
    ItemRepr::new(item_type::CONNECTED_ADDRESS, &connection_id.to_le_bytes()).emit(w)?;
    ItemHeaderRepr::new(item_type::CONNECTED_DATA, 0).emit(w)?;
    let at = w.len();
    w.u16(sequence)?;
    Ok(at)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prefix_round_trip() {
        let r = RrDataRepr {
            interface_handle: 0,
            timeout: 10,
        };
        let mut buf = [0u8; PREFIX_LEN + 2];
        let mut w = Writer::new(&mut buf);
        r.emit(&mut w).unwrap();
        w.u16(0).unwrap();
        assert_eq!(w.len(), r.buffer_len() + 2);
        let p = Packet::new_checked(&buf[..]).unwrap();
        assert_eq!(RrDataRepr::parse(&p), r);
        assert_eq!(p.cpf(), &[0, 0]);
        assert_eq!(
            Packet::new_checked(&buf[..5]).unwrap_err(),
            Error::Truncated
        );
    }
}
