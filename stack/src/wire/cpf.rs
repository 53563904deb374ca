//! Common Packet Format: an item count followed by typed, length-prefixed items.

use core::net::Ipv4Addr;

use super::bytes::{get_u16, Reader, Writer};
use super::{Error, Result};

/// Most items accepted in one CPF.
pub const MAX_ITEMS: usize = 4;

/// CPF item type identifiers (Vol 2, table 2-6.3).
pub mod item_type {
    /// Null address (unconnected messages).
    pub const NULL_ADDRESS: u16 = 0x0000;
    /// CIP identity (ListIdentity reply).
    pub const LIST_IDENTITY: u16 = 0x000C;
    /// Connected address: a 32-bit connection identifier.
    pub const CONNECTED_ADDRESS: u16 = 0x00A1;
    /// Connected data (transport packet).
    pub const CONNECTED_DATA: u16 = 0x00B1;
    /// Unconnected data (a message router request or reply).
    pub const UNCONNECTED_DATA: u16 = 0x00B2;
    /// ListServices reply item.
    pub const LIST_SERVICES: u16 = 0x0100;
    /// Socket address, originator to target.
    pub const SOCKADDR_O_T: u16 = 0x8000;
    /// Socket address, target to originator.
    pub const SOCKADDR_T_O: u16 = 0x8001;
    /// Sequenced address: connection identifier and 32-bit sequence number.
    pub const SEQUENCED_ADDRESS: u16 = 0x8002;
}

/// Length an item of `type_id` must have, if its type fixes it.
const fn fixed_len(type_id: u16) -> Option<usize> {
    match type_id {
        item_type::NULL_ADDRESS => Some(0),
        item_type::CONNECTED_ADDRESS => Some(4),
        item_type::SEQUENCED_ADDRESS => Some(8),
        item_type::SOCKADDR_O_T | item_type::SOCKADDR_T_O => Some(SOCKADDR_LEN),
        _ => None,
    }
}

/// One CPF item, parsed (from [`Packet::items`]) or to emit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ItemRepr<'a> {
    /// Item type identifier.
    pub type_id: u16,
    /// Item data.
    pub data: &'a [u8],
}

impl<'a> ItemRepr<'a> {
    /// The item `type_id` with `data`.
    pub const fn new(type_id: u16, data: &'a [u8]) -> Self {
        ItemRepr { type_id, data }
    }
    /// Parses the item at the front of `r`.
    #[inline]
    pub fn parse(r: &mut Reader<'a>) -> Result<ItemRepr<'a>> {
        let header = ItemHeaderRepr::parse(r)?;
        let data = r.take(usize::from(header.len))?;
        Ok(ItemRepr {
            type_id: header.type_id,
            data,
        })
    }
    /// Bytes the item takes.
    pub const fn buffer_len(&self) -> usize {
        self.data.len().saturating_add(ITEM_HEADER_LEN)
    }
    /// Writes the whole item. Inlined: SendUnitData's connected address item, on the Class 3
    /// path, then costs no call.
    #[inline]
    pub fn emit(&self, w: &mut Writer<'_>) -> Result<()> {
        let len = u16::try_from(self.data.len()).map_err(|_| Error::Exhausted)?;
        ItemHeaderRepr {
            type_id: self.type_id,
            len,
        }
        .emit(w)?;
        w.bytes(self.data)
    }
}

/// Bytes of an item's type and length.
pub const ITEM_HEADER_LEN: usize = 4;

/// The type and length of a CPF item, for an item whose data the caller writes after it
/// (with [`Writer::patch_item_len`] once it knows the length).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ItemHeaderRepr {
    /// Item type identifier.
    pub type_id: u16,
    /// Length of the item's data.
    pub len: u16,
}

impl ItemHeaderRepr {
    /// The header of an item `type_id` with `len` bytes of data.
    pub const fn new(type_id: u16, len: u16) -> Self {
        ItemHeaderRepr { type_id, len }
    }
    /// Parses the item header at the front of `r`.
    #[inline]
    pub fn parse(r: &mut Reader<'_>) -> Result<ItemHeaderRepr> {
        Ok(ItemHeaderRepr {
            type_id: r.u16()?,
            len: r.u16()?,
        })
    }
    /// Bytes the header takes.
    pub const fn buffer_len(&self) -> usize {
        ITEM_HEADER_LEN
    }
    /// Writes the type and length.
    pub fn emit(&self, w: &mut Writer<'_>) -> Result<()> {
        w.u16(self.type_id)?;
        w.u16(self.len)
    }
}

/// A view over a whole CPF, validated item by item.
#[derive(Debug, Clone)]
pub struct Packet<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> Packet<T> {
    /// Wraps and validates a CPF: count within [`MAX_ITEMS`], every item inside the buffer,
    /// fixed-size items of their size, and no bytes left over.
    pub fn new_checked(buffer: T) -> Result<Self> {
        let mut r = Reader::new(buffer.as_ref());
        let count = r.u16()?;
        if usize::from(count) > MAX_ITEMS {
            return Err(Error::Malformed);
        }
        for _ in 0..count {
            let header = ItemHeaderRepr::parse(&mut r)?;
            let len = usize::from(header.len);
            if fixed_len(header.type_id).is_some_and(|f| f != len) {
                return Err(Error::Malformed);
            }
            r.take(len)?;
        }
        if r.remaining() != 0 {
            return Err(Error::Malformed);
        }
        Ok(Packet { buffer })
    }
    /// Number of items.
    pub fn item_count(&self) -> u16 {
        get_u16(self.buffer.as_ref(), 0)
    }
    /// The items in order.
    pub fn items(&self) -> Items<'_> {
        let mut r = Reader::new(self.buffer.as_ref());
        let left = r.u16().unwrap_or(0);
        Items { r, left }
    }
    /// The first item of `type_id`, if any.
    pub fn find(&self, type_id: u16) -> Option<ItemRepr<'_>> {
        self.items().find(|i| i.type_id == type_id)
    }
}

impl<'a> Packet<&'a [u8]> {
    /// The items in order, borrowing the underlying buffer rather than the view.
    pub fn into_items(self) -> Items<'a> {
        let mut r = Reader::new(self.buffer);
        let left = r.u16().unwrap_or(0);
        Items { r, left }
    }
}

/// Iterator over the items of a checked CPF.
#[derive(Debug, Clone)]
pub struct Items<'a> {
    r: Reader<'a>,
    left: u16,
}

impl<'a> Iterator for Items<'a> {
    type Item = ItemRepr<'a>;
    #[inline]
    fn next(&mut self) -> Option<ItemRepr<'a>> {
        if self.left == 0 {
            return None;
        }
        self.left = self.left.saturating_sub(1);
        ItemRepr::parse(&mut self.r).ok()
    }
}

/// Length of a socket address item's data.
pub const SOCKADDR_LEN: usize = 16;

/// The data of a socket address item (big-endian `sockaddr_in`): where the peer wants I/O
/// sent.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SockAddrRepr {
    /// IPv4 address.
    pub addr: Ipv4Addr,
    /// UDP port.
    pub port: u16,
}

impl SockAddrRepr {
    /// Parses the 16 data bytes of a socket address item (family must be AF_INET).
    pub fn parse(data: &[u8]) -> Result<SockAddrRepr> {
        if data.len() != SOCKADDR_LEN {
            return Err(Error::Truncated);
        }
        let mut r = Reader::new(data);
        let family = u16::from_be_bytes(r.array()?);
        let port = u16::from_be_bytes(r.array()?);
        let addr = Ipv4Addr::from(r.array::<4>()?);
        if family != 2 {
            return Err(Error::Malformed);
        }
        Ok(SockAddrRepr { addr, port })
    }
    /// Bytes the item data takes.
    pub const fn buffer_len(&self) -> usize {
        SOCKADDR_LEN
    }
    /// Writes the 16 data bytes.
    pub fn emit(&self, w: &mut Writer<'_>) -> Result<()> {
        w.bytes(&2u16.to_be_bytes())?;
        w.bytes(&self.port.to_be_bytes())?;
        w.bytes(&self.addr.octets())?;
        w.zeros(8)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_null_and_unconnected() {
        let buf = [2, 0, 0, 0, 0, 0, 0xB2, 0, 2, 0, 0x0E, 0x03];
        let p = Packet::new_checked(&buf[..]).unwrap();
        let items: heapless::Vec<ItemRepr<'_>, 4> = p.items().collect();
        assert_eq!(items.len(), 2);
        assert_eq!(
            items[1],
            ItemRepr {
                type_id: item_type::UNCONNECTED_DATA,
                data: &[0x0E, 3]
            }
        );
    }

    #[test]
    fn rejects_bad_counts_and_lengths() {
        // count says 2, one item present
        assert_eq!(
            Packet::new_checked(&[2u8, 0, 0, 0, 0, 0][..]).unwrap_err(),
            Error::Truncated
        );
        // item length beyond buffer
        assert_eq!(
            Packet::new_checked(&[1u8, 0, 0xB2, 0, 9, 0, 1][..]).unwrap_err(),
            Error::Truncated
        );
        // null address with data
        assert_eq!(
            Packet::new_checked(&[1u8, 0, 0, 0, 1, 0, 1][..]).unwrap_err(),
            Error::Malformed
        );
        // trailing garbage
        assert_eq!(
            Packet::new_checked(&[0u8, 0, 1][..]).unwrap_err(),
            Error::Malformed
        );
        // too many items
        assert_eq!(
            Packet::new_checked(&[200u8, 0][..]).unwrap_err(),
            Error::Malformed
        );
    }

    #[test]
    fn items_round_trip() {
        let mut buf = [0u8; 16];
        let mut w = Writer::new(&mut buf);
        w.u16(2).unwrap();
        let null = ItemRepr {
            type_id: item_type::NULL_ADDRESS,
            data: &[],
        };
        null.emit(&mut w).unwrap();
        let data = ItemRepr {
            type_id: item_type::UNCONNECTED_DATA,
            data: &[0x0E, 3],
        };
        data.emit(&mut w).unwrap();
        assert_eq!(w.len(), 2 + null.buffer_len() + data.buffer_len());
        let n = w.len();
        let p = Packet::new_checked(&buf[..n]).unwrap();
        assert!(p.items().eq([null, data]));
        assert_eq!(p.find(item_type::UNCONNECTED_DATA), Some(data));
    }

    #[test]
    fn sockaddr_round_trip() {
        let s = SockAddrRepr {
            addr: Ipv4Addr::new(198, 18, 0, 1),
            port: 2222,
        };
        let mut buf = [0u8; 16];
        let mut w = Writer::new(&mut buf);
        s.emit(&mut w).unwrap();
        assert_eq!(&buf[..8], &[0, 2, 0x08, 0xAE, 198, 18, 0, 1]);
        assert_eq!(SockAddrRepr::parse(&buf), Ok(s));
        assert_eq!(s.buffer_len(), buf.len());
    }
}
