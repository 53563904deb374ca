//! The Class 0/1 I/O datagram on UDP 2222: a CPF of a sequenced address item (connection ID,
//! 32-bit encapsulation sequence number) and a connected data item (16-bit CIP sequence
//! count, optional 32-bit run/idle header, application data).

use super::bytes::{get_u16, get_u32, put_u16, put_u32};
use super::cpf::item_type;
use super::{Error, Result};

/// Bytes before the connected data item's data: count, address item, data item header.
pub const HEADER_LEN: usize = 2 + 4 + 8 + 4;
/// Bytes of the 16-bit CIP sequence count.
pub const SEQUENCE_LEN: usize = 2;
/// Bytes of the run/idle header.
pub const RUN_IDLE_LEN: usize = 4;

mod field {
    pub const COUNT: usize = 0;
    pub const ADDR_TYPE: usize = 2;
    pub const ADDR_LEN: usize = 4;
    pub const CONNECTION_ID: usize = 6;
    pub const ENCAP_SEQUENCE: usize = 10;
    pub const DATA_TYPE: usize = 14;
    pub const DATA_LEN: usize = 16;
    pub const DATA: usize = 18;
}

/// A view over an I/O datagram.
#[derive(Debug, Clone)]
pub struct Packet<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> Packet<T> {
    /// Wraps a datagram that has exactly the two expected items and whose data item fills it.
    pub fn new_checked(buffer: T) -> Result<Self> {
        let p = Packet { buffer };
        let b = p.buffer.as_ref();
        if b.len() < HEADER_LEN {
            return Err(Error::Truncated);
        }
        if get_u16(b, field::COUNT) != 2
            || get_u16(b, field::ADDR_TYPE) != item_type::SEQUENCED_ADDRESS
            || get_u16(b, field::ADDR_LEN) != 8
            || get_u16(b, field::DATA_TYPE) != item_type::CONNECTED_DATA
            || usize::from(get_u16(b, field::DATA_LEN)) != b.len().saturating_sub(HEADER_LEN)
        {
            return Err(Error::Malformed);
        }
        Ok(p)
    }
    /// Connection ID.
    pub fn connection_id(&self) -> u32 {
        get_u32(self.buffer.as_ref(), field::CONNECTION_ID)
    }
    /// 32-bit encapsulation sequence number.
    pub fn encap_sequence(&self) -> u32 {
        get_u32(self.buffer.as_ref(), field::ENCAP_SEQUENCE)
    }
    /// The connected data item's data (sequence count, run/idle header, application data).
    pub fn connected_data(&self) -> &[u8] {
        self.buffer.as_ref().get(field::DATA..).unwrap_or(&[])
    }
}

/// Writes the datagram header for `data_len` bytes of connected data (sequence count
/// included) into `buf`; the caller writes the connected data at [`HEADER_LEN`].
pub fn emit_header(
    buf: &mut [u8],
    connection_id: u32,
    encap_sequence: u32,
    data_len: usize,
) -> Result<()> {
    let len = u16::try_from(data_len).map_err(|_| Error::Exhausted)?;
    if buf.len() < HEADER_LEN.saturating_add(data_len) {
        return Err(Error::Exhausted);
    }
    put_u16(buf, field::COUNT, 2);
    put_u16(buf, field::ADDR_TYPE, item_type::SEQUENCED_ADDRESS);
    put_u16(buf, field::ADDR_LEN, 8);
    put_u32(buf, field::CONNECTION_ID, connection_id);
    put_u32(buf, field::ENCAP_SEQUENCE, encap_sequence);
    put_u16(buf, field::DATA_TYPE, item_type::CONNECTED_DATA);
    put_u16(buf, field::DATA_LEN, len);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip() {
        let mut buf = [0u8; 24];
        emit_header(&mut buf, 0xAABB_CCDD, 5, 6).unwrap();
        buf[18..24].copy_from_slice(&[1, 0, 1, 0, 0, 0]);
        let p = Packet::new_checked(&buf[..]).unwrap();
        assert_eq!(p.connection_id(), 0xAABB_CCDD);
        assert_eq!(p.encap_sequence(), 5);
        assert_eq!(p.connected_data(), &[1, 0, 1, 0, 0, 0]);
        assert_eq!(
            Packet::new_checked(&buf[..23]).unwrap_err(),
            Error::Malformed
        );
        assert_eq!(
            Packet::new_checked(&buf[..10]).unwrap_err(),
            Error::Truncated
        );
        assert!(emit_header(&mut buf, 1, 1, 7).is_err());
    }
}
