//! RegisterSession command data: protocol version and option flags.

use super::bytes::{get_u16, put_u16};
use super::{Error, Result, Writer};

/// Length of the RegisterSession data.
pub const LEN: usize = 4;
/// The only encapsulation protocol version defined.
pub const PROTOCOL_VERSION: u16 = 1;

/// A view over RegisterSession data.
#[derive(Debug, Clone)]
pub struct Packet<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> Packet<T> {
    /// Wraps exactly four bytes of data.
    pub fn new_checked(buffer: T) -> Result<Self> {
        match buffer.as_ref().len() {
            LEN => Ok(Packet { buffer }),
            n if n < LEN => Err(Error::Truncated),
            _ => Err(Error::Malformed),
        }
    }
    /// Requested protocol version.
    pub fn protocol_version(&self) -> u16 {
        get_u16(self.buffer.as_ref(), 0)
    }
    /// Option flags (none are defined; must be zero).
    pub fn options(&self) -> u16 {
        get_u16(self.buffer.as_ref(), 2)
    }
}

/// RegisterSession data, parsed or to emit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RegisterSessionRepr {
    /// Protocol version.
    pub protocol_version: u16,
    /// Option flags.
    pub options: u16,
}

impl RegisterSessionRepr {
    /// Parses checked data.
    pub fn parse<T: AsRef<[u8]>>(p: &Packet<T>) -> RegisterSessionRepr {
        RegisterSessionRepr {
            protocol_version: p.protocol_version(),
            options: p.options(),
        }
    }
    /// Bytes the data takes.
    pub const fn buffer_len(&self) -> usize {
        LEN
    }
    /// Writes the data.
    pub fn emit(&self, w: &mut Writer<'_>) -> Result<()> {
        let buf = w.reserve(LEN)?;
        put_u16(buf, 0, self.protocol_version);
        put_u16(buf, 2, self.options);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_length_only() {
        assert!(Packet::new_checked(&[1u8, 0, 0, 0][..]).is_ok());
        assert_eq!(
            Packet::new_checked(&[1u8, 0][..]).unwrap_err(),
            Error::Truncated
        );
        assert_eq!(
            Packet::new_checked(&[1u8, 0, 0, 0, 0][..]).unwrap_err(),
            Error::Malformed
        );
        let r = RegisterSessionRepr::parse(&Packet::new_checked(&[1u8, 0, 2, 0][..]).unwrap());
        assert_eq!(
            r,
            RegisterSessionRepr {
                protocol_version: 1,
                options: 2
            }
        );
        let mut out = [0u8; LEN];
        r.emit(&mut Writer::new(&mut out)).unwrap();
        assert_eq!((out, r.buffer_len()), ([1, 0, 2, 0], LEN));
    }
}
