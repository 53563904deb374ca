//! The Class 0/1 I/O datagram on UDP 2222: a CPF of a sequenced address item (connection ID,
//! 32-bit encapsulation sequence number) and a connected data item (16-bit CIP sequence
//! count, optional 32-bit run/idle header, application data).

use super::bytes::{get_u16, get_u32, put_u16};
use super::cpf::item_type;
use super::{Error, Result, Writer};

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

/// The fixed front of an I/O datagram, parsed or to emit: the item count, the sequenced
/// address item, the connected data item's header and the 16-bit CIP sequence count. The
/// run/idle header (where used) and the application data follow it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IoDatagramRepr {
    /// Connection ID.
    pub connection_id: u32,
    /// 32-bit encapsulation sequence number.
    pub encap_sequence: u32,
    /// Bytes of the connected data item: sequence count, run/idle header, application data.
    pub connected_len: u16,
    /// 16-bit CIP sequence count.
    pub sequence: u16,
}

impl IoDatagramRepr {
    /// Parses a checked datagram (its connected data must hold the sequence count).
    pub fn parse<T: AsRef<[u8]>>(p: &Packet<T>) -> Result<IoDatagramRepr> {
        let data = p.connected_data();
        if data.len() < SEQUENCE_LEN {
            return Err(Error::Truncated);
        }
        Ok(IoDatagramRepr {
            connection_id: p.connection_id(),
            encap_sequence: p.encap_sequence(),
            connected_len: get_u16(p.buffer.as_ref(), field::DATA_LEN),
            sequence: get_u16(data, 0),
        })
    }
    /// Bytes [`Self::emit`] writes: [`HEADER_LEN`] + [`SEQUENCE_LEN`].
    pub const fn buffer_len(&self) -> usize {
        HEADER_LEN + SEQUENCE_LEN
    }
    /// Writes the datagram's front in one piece; the caller writes the rest of the connected
    /// data after it. Always inlined: the T->O producer's hot path builds it into a 20-byte
    /// chunk it already checked, where the writer's bounds check folds away.
    #[inline(always)]
    pub fn emit(&self, w: &mut Writer<'_>) -> Result<()> {
        let out = w.reserve(HEADER_LEN + SEQUENCE_LEN)?;
        if let Some(head) = out.first_chunk_mut::<{ HEADER_LEN + SEQUENCE_LEN }>() {
            *head = self.bytes();
        }
        Ok(())
    }
    /// The bytes [`Self::emit`] writes: the header, then the sequence count.
    fn bytes(&self) -> [u8; HEADER_LEN + SEQUENCE_LEN] {
        let mut out = [0; HEADER_LEN + SEQUENCE_LEN];
        if let Some((head, _)) = out.split_first_chunk_mut::<HEADER_LEN>() {
            *head = header(self.connection_id, self.encap_sequence, self.connected_len);
        }
        put_u16(&mut out, field::DATA, self.sequence);
        out
    }
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

    fn emit(repr: &IoDatagramRepr, data: &[u8], buf: &mut [u8]) -> usize {
        let mut w = Writer::new(buf);
        repr.emit(&mut w).unwrap();
        w.bytes(data).unwrap();
        w.len()
    }

    #[test]
    fn round_trip() {
        let repr = IoDatagramRepr {
            connection_id: 0xAABB_CCDD,
            encap_sequence: 5,
            connected_len: 6,
            sequence: 1,
        };
        let mut buf = [0u8; 24];
        assert_eq!(emit(&repr, &[1, 0, 0, 0], &mut buf), 24);
        let p = Packet::new_checked(&buf[..]).unwrap();
        assert_eq!(p.connection_id(), 0xAABB_CCDD);
        assert_eq!(p.encap_sequence(), 5);
        assert_eq!(p.connected_data(), &[1, 0, 1, 0, 0, 0]);
        assert_eq!(IoDatagramRepr::parse(&p), Ok(repr));
        assert_eq!(
            Packet::new_checked(&buf[..23]).unwrap_err(),
            Error::Malformed
        );
        assert_eq!(
            Packet::new_checked(&buf[..10]).unwrap_err(),
            Error::Truncated
        );
        let mut short = [0u8; HEADER_LEN + 1];
        assert_eq!(
            repr.emit(&mut Writer::new(&mut short)),
            Err(Error::Exhausted)
        );
        assert_eq!(short, [0; HEADER_LEN + 1]);
    }

    #[test]
    fn the_front_is_the_header_and_the_sequence_count() {
        let repr = IoDatagramRepr {
            connection_id: 0xAABB_CCDD,
            encap_sequence: 0x0102_0304,
            connected_len: 34,
            sequence: 0xBEEF,
        };
        let mut buf = [0u8; HEADER_LEN + SEQUENCE_LEN];
        let mut w = Writer::new(&mut buf);
        repr.emit(&mut w).unwrap();
        assert_eq!(w.len(), repr.buffer_len());
        assert_eq!(
            buf,
            [
                2, 0, 0x02, 0x80, 8, 0, 0xDD, 0xCC, 0xBB, 0xAA, 4, 3, 2, 1, 0xB1, 0, 34, 0, 0xEF,
                0xBE
            ]
        );
    }

    #[test]
    fn every_fixed_field_is_checked() {
        let repr = IoDatagramRepr {
            connection_id: 7,
            encap_sequence: 1,
            connected_len: 2,
            sequence: 0,
        };
        let mut good = [0u8; 20];
        emit(&repr, &[], &mut good);
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

    #[test]
    fn parse_needs_the_sequence_count() {
        let repr = IoDatagramRepr {
            connection_id: 7,
            encap_sequence: 1,
            connected_len: 0,
            sequence: 0,
        };
        let mut buf = [0u8; 20];
        emit(&repr, &[], &mut buf);
        let p = Packet::new_checked(&buf[..HEADER_LEN]).unwrap();
        assert_eq!(IoDatagramRepr::parse(&p), Err(Error::Truncated));
    }
}
