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

/// One CPF item.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Item<'a> {
    /// Item type identifier.
    pub type_id: u16,
    /// Item data.
    pub data: &'a [u8],
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
            let type_id = r.u16()?;
            let len = usize::from(r.u16()?);
            if fixed_len(type_id).is_some_and(|f| f != len) {
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
    pub fn find(&self, type_id: u16) -> Option<Item<'_>> {
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
    type Item = Item<'a>;
    fn next(&mut self) -> Option<Item<'a>> {
        if self.left == 0 {
            return None;
        }
        self.left = self.left.saturating_sub(1);
        let type_id = self.r.u16().ok()?;
        let len = usize::from(self.r.u16().ok()?);
        let data = self.r.take(len).ok()?;
        Some(Item { type_id, data })
    }
}

/// Writes an item header (type and length); the caller writes `len` data bytes after it.
pub fn emit_item_header(w: &mut Writer<'_>, type_id: u16, len: u16) -> Result<()> {
    w.u16(type_id)?;
    w.u16(len)
}

/// Writes a whole item.
pub fn emit_item(w: &mut Writer<'_>, type_id: u16, data: &[u8]) -> Result<()> {
    let len = u16::try_from(data.len()).map_err(|_| Error::Exhausted)?;
    emit_item_header(w, type_id, len)?;
    w.bytes(data)
}

/// Length of a socket address item's data.
pub const SOCKADDR_LEN: usize = 16;

/// A socket address item (big-endian `sockaddr_in`): where the peer wants I/O sent.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SockAddr {
    /// IPv4 address.
    pub addr: Ipv4Addr,
    /// UDP port.
    pub port: u16,
}

impl SockAddr {
    /// Parses the 16 data bytes of a socket address item (family must be AF_INET).
    pub fn parse(data: &[u8]) -> Result<SockAddr> {
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
        Ok(SockAddr { addr, port })
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
        let items: heapless::Vec<Item<'_>, 4> = p.items().collect();
        assert_eq!(items.len(), 2);
        assert_eq!(
            items[1],
            Item {
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
    fn sockaddr_round_trip() {
        let s = SockAddr {
            addr: Ipv4Addr::new(198, 18, 0, 1),
            port: 2222,
        };
        let mut buf = [0u8; 16];
        let mut w = Writer::new(&mut buf);
        s.emit(&mut w).unwrap();
        assert_eq!(&buf[..8], &[0, 2, 0x08, 0xAE, 198, 18, 0, 1]);
        assert_eq!(SockAddr::parse(&buf), Ok(s));
    }
}
