//! The Class 0/1 I/O datagram on UDP 2222: a CPF of a sequenced address item (connection ID,
//! 32-bit encapsulation sequence number) and a connected data item (16-bit CIP sequence
//! count, optional 32-bit run/idle header, application data).

use super::bytes::{get_u16, get_u32, put_u16};
use super::cpf::item_type;
use super::{Error, Result};

/// UDP port of Class 0/1 implicit I/O.
pub const IO_PORT: u16 = 2222;
/// Bytes before the connected data item's data: count, address item, data item header.
pub const HEADER_LEN: usize = 2 + 4 + 8 + 4;
/// Bytes of the 16-bit CIP sequence count.
pub const SEQUENCE_LEN: usize = 2;
/// Bytes of the run/idle header.
pub const RUN_IDLE_LEN: usize = 4;

mod field {
    /// The item count, then the address item's type at 2.
    pub const COUNT: usize = 0;
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
        // The item count and the address item's type in one read.
        let count_and_type = 2 | u32::from(item_type::SEQUENCED_ADDRESS) << 16;
        if get_u32(b, field::COUNT) != count_and_type
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
    let (head, _) = buf
        .split_first_chunk_mut::<HEADER_LEN>()
        .ok_or(Error::Exhausted)?;
    *head = header(connection_id, encap_sequence, len);
    Ok(())
}

/// The first [`HEADER_LEN`] + [`SEQUENCE_LEN`] bytes of a datagram: its header for
/// `data_len` bytes of connected data (sequence count included), then the sequence count.
pub fn sequenced_header(
    connection_id: u32,
    encap_sequence: u32,
    data_len: u16,
    sequence: u16,
) -> [u8; HEADER_LEN + SEQUENCE_LEN] {
    let mut out = [0; HEADER_LEN + SEQUENCE_LEN];
    if let Some((head, _)) = out.split_first_chunk_mut::<HEADER_LEN>() {
        *head = header(connection_id, encap_sequence, data_len);
    }
    put_u16(&mut out, field::DATA, sequence);
    out
}

/// The datagram header: the item count, the sequenced address item and the connected data
/// item's header for `data_len` bytes.
fn header(connection_id: u32, encap_sequence: u32, data_len: u16) -> [u8; HEADER_LEN] {
    let [c0, c1, c2, c3] = connection_id.to_le_bytes();
    let [e0, e1, e2, e3] = encap_sequence.to_le_bytes();
    let [l0, l1] = data_len.to_le_bytes();
    let [a0, a1] = item_type::SEQUENCED_ADDRESS.to_le_bytes();
    let [d0, d1] = item_type::CONNECTED_DATA.to_le_bytes();
    [
        2, 0, a0, a1, 8, 0, c0, c1, c2, c3, e0, e1, e2, e3, d0, d1, l0, l1,
    ]
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

    #[test]
    fn sequenced_header_is_the_header_and_the_sequence_count() {
        let h = sequenced_header(0xAABB_CCDD, 0x0102_0304, 34, 0xBEEF);
        assert_eq!(
            h,
            [
                2, 0, 0x02, 0x80, 8, 0, 0xDD, 0xCC, 0xBB, 0xAA, 4, 3, 2, 1, 0xB1, 0, 34, 0, 0xEF,
                0xBE
            ]
        );
        let mut buf = [0u8; HEADER_LEN + 34];
        emit_header(&mut buf, 0xAABB_CCDD, 0x0102_0304, 34).unwrap();
        assert_eq!(buf[..HEADER_LEN], h[..HEADER_LEN]);
    }

    #[test]
    fn every_fixed_field_is_checked() {
        let mut good = [0u8; 20];
        emit_header(&mut good, 7, 1, 2).unwrap();
        assert!(Packet::new_checked(&good[..]).is_ok());
        // Item count, address item type (both bytes), address length, data item type.
        for at in [0, 1, 2, 3, 4, 14, 15] {
            let mut bad = good;
            bad[at] ^= 0x40;
            assert_eq!(
                Packet::new_checked(&bad[..]).unwrap_err(),
                Error::Malformed,
                "byte {at}"
            );
        }
    }
}
