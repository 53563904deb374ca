//! The ListIdentity CIP identity item (type 0x000C) and the ListServices item (type 0x0100).

use core::net::Ipv4Addr;

use super::cpf::SockAddrRepr;
use super::{Error, Reader, Result, Writer};

/// A parsed or to-be-emitted CIP identity item.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IdentityRepr<'a> {
    /// Encapsulation protocol version (1).
    pub protocol_version: u16,
    /// Where the device listens: its IP address and TCP port.
    pub socket: SockAddrRepr,
    /// Vendor ID.
    pub vendor_id: u16,
    /// Device type.
    pub device_type: u16,
    /// Product code.
    pub product_code: u16,
    /// Major and minor revision.
    pub revision: (u8, u8),
    /// Identity status word.
    pub status: u16,
    /// Serial number.
    pub serial_number: u32,
    /// Product name (at most 255 bytes).
    pub product_name: &'a [u8],
    /// Identity state.
    pub state: u8,
}

impl<'a> IdentityRepr<'a> {
    /// Parses an identity item's data.
    pub fn parse(data: &'a [u8]) -> Result<IdentityRepr<'a>> {
        let mut r = Reader::new(data);
        let protocol_version = r.u16()?;
        let socket = SockAddrRepr::parse(r.take(16)?)?;
        let vendor_id = r.u16()?;
        let device_type = r.u16()?;
        let product_code = r.u16()?;
        let revision = (r.u8()?, r.u8()?);
        let status = r.u16()?;
        let serial_number = r.u32()?;
        let n = usize::from(r.u8()?);
        let product_name = r.take(n)?;
        let state = r.u8()?;
        if r.remaining() != 0 {
            return Err(Error::Malformed);
        }
        Ok(IdentityRepr {
            protocol_version,
            socket,
            vendor_id,
            device_type,
            product_code,
            revision,
            status,
            serial_number,
            product_name,
            state,
        })
    }
    /// Bytes the item data takes.
    pub fn buffer_len(&self) -> usize {
        self.product_name
            .len()
            .saturating_add(2 + 16 + 2 + 2 + 2 + 2 + 2 + 4 + 1 + 1)
    }
    /// Writes the item data.
    pub fn emit(&self, w: &mut Writer<'_>) -> Result<()> {
        let name_len = u8::try_from(self.product_name.len()).map_err(|_| Error::Malformed)?;
        w.u16(self.protocol_version)?;
        self.socket.emit(w)?;
        w.u16(self.vendor_id)?;
        w.u16(self.device_type)?;
        w.u16(self.product_code)?;
        w.u8(self.revision.0)?;
        w.u8(self.revision.1)?;
        w.u16(self.status)?;
        w.u32(self.serial_number)?;
        w.u8(name_len)?;
        w.bytes(self.product_name)?;
        w.u8(self.state)
    }
}

/// Capability flag: CIP encapsulation over TCP.
pub const CAPABILITY_CIP_TCP: u16 = 1 << 5;
/// Capability flag: CIP Class 0/1 over UDP.
pub const CAPABILITY_CIP_UDP_CLASS01: u16 = 1 << 8;

/// A ListServices item.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ServiceRepr {
    /// Protocol version (1).
    pub protocol_version: u16,
    /// Capability flags.
    pub capability: u16,
    /// Service name, NUL padded ("Communications").
    pub name: [u8; 16],
}

impl ServiceRepr {
    /// The "Communications" service of an adapter doing CIP over TCP and Class 0/1 over UDP.
    pub const fn communications() -> Self {
        ServiceRepr {
            protocol_version: 1,
            capability: CAPABILITY_CIP_TCP | CAPABILITY_CIP_UDP_CLASS01,
            name: *b"Communications\0\0",
        }
    }
    /// Parses an item's data.
    pub fn parse(data: &[u8]) -> Result<ServiceRepr> {
        let mut r = Reader::new(data);
        let s = ServiceRepr {
            protocol_version: r.u16()?,
            capability: r.u16()?,
            name: r.array()?,
        };
        if r.remaining() != 0 {
            return Err(Error::Malformed);
        }
        Ok(s)
    }
    /// Bytes the item data takes.
    pub const fn buffer_len(&self) -> usize {
        20
    }
    /// Writes the item data.
    pub fn emit(&self, w: &mut Writer<'_>) -> Result<()> {
        w.u16(self.protocol_version)?;
        w.u16(self.capability)?;
        w.bytes(&self.name)
    }
}

/// The address a ListIdentity reply advertises.
pub const fn listen_socket(ip: Ipv4Addr) -> SockAddrRepr {
    SockAddrRepr {
        addr: ip,
        port: super::encap::ENCAP_PORT,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identity_round_trip() {
        let id = IdentityRepr {
            protocol_version: 1,
            socket: listen_socket(Ipv4Addr::new(198, 18, 0, 2)),
            vendor_id: 1,
            device_type: 12,
            product_code: 65001,
            revision: (2, 3),
            status: 0x30,
            serial_number: 0x1234_5678,
            product_name: b"Test",
            state: 3,
        };
        let mut buf = [0u8; 64];
        let mut w = Writer::new(&mut buf);
        id.emit(&mut w).unwrap();
        assert_eq!(w.len(), id.buffer_len());
        let n = w.len();
        assert_eq!(IdentityRepr::parse(&buf[..n]), Ok(id));
        assert!(IdentityRepr::parse(&buf[..n - 1]).is_err());
    }

    #[test]
    fn services_round_trip() {
        let s = ServiceRepr::communications();
        let mut buf = [0u8; 20];
        s.emit(&mut Writer::new(&mut buf)).unwrap();
        assert_eq!(ServiceRepr::parse(&buf), Ok(s));
        assert_eq!(&buf[..4], &[1, 0, 0x20, 0x01]);
    }
}
