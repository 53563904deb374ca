//! LLDP (IEEE 802.1AB) data units: the TLVs of a received LLDPDU, checked and read in place
//! ([`LldpduRepr::parse`]), and the adapter's own LLDPDU written from [`LocalSystem`], with
//! the ODVA organizationally specific TLVs (OUI 00-21-6C) CIP Identification and CIP MAC
//! Address.
//!
//! The LLDPDU is the Ethernet payload of a frame of ethertype [`ETHERTYPE`] to the
//! nearest-bridge group address [`MULTICAST_MAC`]; the runtime writes and strips the Ethernet
//! header. Every TLV starts with a 16-bit big-endian header: type (7 bits) and information
//! string length (9 bits).
//!
//! A received LLDPDU is refused as a whole (802.1AB 9.2.7.7.1) when it does not start with
//! the Chassis ID, Port ID and Time To Live TLVs in that order, when one of these is too short
//! or too long, when a TLV runs past the end of the data, or when a mandatory TLV comes
//! twice. An optional TLV of the wrong length is skipped on its own; unknown TLVs are skipped.

use core::net::Ipv4Addr;

use super::{Error, Reader, Result, Writer};

/// The LLDP ethertype.
pub const ETHERTYPE: u16 = 0x88CC;
/// The nearest-bridge group address LLDPDUs are sent to.
pub const MULTICAST_MAC: [u8; 6] = [0x01, 0x80, 0xC2, 0x00, 0x00, 0x0E];
/// ODVA's organizationally unique identifier.
pub const ODVA_OUI: [u8; 3] = [0x00, 0x21, 0x6C];

/// TLV types (802.1AB table 8-1).
pub mod tlv {
    /// End Of LLDPDU.
    pub const END: u8 = 0;
    /// Chassis ID.
    pub const CHASSIS_ID: u8 = 1;
    /// Port ID.
    pub const PORT_ID: u8 = 2;
    /// Time To Live.
    pub const TTL: u8 = 3;
    /// Port Description.
    pub const PORT_DESCRIPTION: u8 = 4;
    /// System Name.
    pub const SYSTEM_NAME: u8 = 5;
    /// System Description.
    pub const SYSTEM_DESCRIPTION: u8 = 6;
    /// System Capabilities.
    pub const SYSTEM_CAPABILITIES: u8 = 7;
    /// Management Address.
    pub const MANAGEMENT_ADDRESS: u8 = 8;
    /// Organizationally Specific.
    pub const ORGANIZATIONAL: u8 = 127;
}

/// ODVA TLV subtypes (CIP Vol 2, the LLDP chapter).
pub mod odva {
    /// CIP Identification: vendor, device type, product code, revision, serial number.
    pub const CIP_IDENTIFICATION: u8 = 1;
    /// CIP MAC Address.
    pub const CIP_MAC_ADDRESS: u8 = 2;
    /// CIP Interface Label.
    pub const CIP_INTERFACE_LABEL: u8 = 3;
}

/// Chassis ID subtype: MAC address (802.1AB table 8-2).
pub const CHASSIS_MAC: u8 = 4;
/// Chassis ID subtype: interface name (802.1AB table 8-2).
pub const CHASSIS_INTERFACE_NAME: u8 = 6;
/// Port ID subtype: MAC address (802.1AB table 8-3).
pub const PORT_MAC: u8 = 3;
/// Port ID subtype: interface name (802.1AB table 8-3).
pub const PORT_INTERFACE_NAME: u8 = 5;
/// System capability bit: station only (802.1AB table 8-4).
pub const CAPABILITY_STATION: u16 = 1 << 7;
/// Management address subtype: IPv4 (IANA address family 1).
const ADDRESS_IPV4: u8 = 1;
/// Management address interface numbering subtype: ifIndex.
const IF_INDEX: u8 = 2;
/// Longest information string a TLV header can state.
const MAX_INFO: usize = 511;
/// Shortest and longest Chassis ID and Port ID information strings (subtype included).
const ID_LEN: core::ops::RangeInclusive<usize> = 2..=256;
/// Information length of the ODVA CIP Identification TLV: OUI, subtype, 12 bytes.
const CIP_IDENTIFICATION_LEN: usize = 16;
/// Information length of the ODVA CIP MAC Address TLV: OUI, subtype, 6 bytes.
const CIP_MAC_LEN: usize = 10;
/// Management addresses kept from one LLDPDU.
pub const MAX_ADDRESSES: usize = 2;

/// The CIP identity an ODVA CIP Identification TLV carries (little-endian on the wire, as
/// in an electronic key with serial number).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CipIdentification {
    /// Vendor ID.
    pub vendor_id: u16,
    /// Device type.
    pub device_type: u16,
    /// Product code.
    pub product_code: u16,
    /// Major revision (7 bits; bit 7 is reserved and sent as 0).
    pub major_revision: u8,
    /// Minor revision.
    pub minor_revision: u8,
    /// Serial number.
    pub serial_number: u32,
}

impl CipIdentification {
    /// Reads the 12 bytes after the OUI and subtype.
    fn parse(bytes: &[u8]) -> Result<Self> {
        let mut r = Reader::new(bytes);
        Ok(CipIdentification {
            vendor_id: r.u16()?,
            device_type: r.u16()?,
            product_code: r.u16()?,
            major_revision: r.u8()? & 0x7F,
            minor_revision: r.u8()?,
            serial_number: r.u32()?,
        })
    }

    /// Writes the 12 bytes after the OUI and subtype.
    pub fn emit(&self, w: &mut Writer<'_>) -> Result<()> {
        w.u16(self.vendor_id)?;
        w.u16(self.device_type)?;
        w.u16(self.product_code)?;
        w.u8(self.major_revision & 0x7F)?;
        w.u8(self.minor_revision)?;
        w.u32(self.serial_number)
    }
}

/// One TLV: its type and information string.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Tlv<'a> {
    /// TLV type (0-127).
    pub kind: u8,
    /// Information string.
    pub info: &'a [u8],
}

/// Reads the next TLV from `r`; `Truncated` if its header or information runs past the end.
fn next_tlv<'a>(r: &mut Reader<'a>) -> Result<Tlv<'a>> {
    let head = r.array::<2>()?;
    let head = u16::from_be_bytes(head);
    let kind = (head >> 9) as u8;
    let len = usize::from(head & 0x01FF);
    let info = r.take(len)?;
    Ok(Tlv { kind, info })
}

/// A received LLDPDU, checked, its fields borrowed from the data.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct LldpduRepr<'a> {
    /// The Chassis ID and Port ID TLVs as received, headers included: the sender's MSAP
    /// identifier (802.1AB 8.5.1) in one slice.
    pub msap: &'a [u8],
    /// Chassis ID subtype.
    pub chassis_subtype: u8,
    /// Chassis ID (after the subtype).
    pub chassis_id: &'a [u8],
    /// Port ID subtype.
    pub port_subtype: u8,
    /// Port ID (after the subtype).
    pub port_id: &'a [u8],
    /// Time To Live in seconds (0: the sender is shutting down).
    pub ttl: u16,
    /// Port Description.
    pub port_description: Option<&'a [u8]>,
    /// System Name.
    pub system_name: Option<&'a [u8]>,
    /// System Capabilities: (supported, enabled).
    pub capabilities: Option<(u16, u16)>,
    /// The first IPv4 management addresses.
    pub addresses: heapless::Vec<Ipv4Addr, MAX_ADDRESSES>,
    /// ODVA CIP Identification.
    pub cip_identification: Option<CipIdentification>,
    /// ODVA CIP MAC Address.
    pub cip_mac: Option<[u8; 6]>,
    /// ODVA CIP Interface Label.
    pub cip_interface_label: Option<&'a [u8]>,
}

impl<'a> LldpduRepr<'a> {
    /// Checks and reads an LLDPDU (the Ethernet payload, padding allowed after the End TLV
    /// or the data's end).
    pub fn parse(data: &'a [u8]) -> Result<Self> {
        let mut r = Reader::new(data);
        let chassis = mandatory(&mut r, tlv::CHASSIS_ID, ID_LEN)?;
        let port = mandatory(&mut r, tlv::PORT_ID, ID_LEN)?;
        let msap_len = data.len().saturating_sub(r.remaining());
        let ttl = mandatory(&mut r, tlv::TTL, 2..=MAX_INFO)?;
        let (chassis_subtype, chassis_id) = chassis.split_first().ok_or(Error::Truncated)?;
        let (port_subtype, port_id) = port.split_first().ok_or(Error::Truncated)?;
        let mut pdu = LldpduRepr {
            msap: data.get(..msap_len).unwrap_or_default(),
            chassis_subtype: *chassis_subtype,
            chassis_id,
            port_subtype: *port_subtype,
            port_id,
            ttl: Reader::new(ttl).array::<2>().map(u16::from_be_bytes)?,
            ..LldpduRepr::default()
        };
        // Each TLV takes at least its 2-byte header: bounded by the data's length.
        while r.remaining() > 0 {
            let t = next_tlv(&mut r)?;
            match t.kind {
                tlv::END => break,
                tlv::CHASSIS_ID | tlv::PORT_ID | tlv::TTL => return Err(Error::Malformed),
                _ => pdu.optional(t),
            }
        }
        Ok(pdu)
    }

    /// Takes in one optional TLV; a malformed one is ignored (802.1AB 9.2.7.7.2).
    fn optional(&mut self, t: Tlv<'a>) {
        let text = (t.info.len() <= 255).then_some(t.info);
        match t.kind {
            tlv::PORT_DESCRIPTION => self.port_description = self.port_description.or(text),
            tlv::SYSTEM_NAME => self.system_name = self.system_name.or(text),
            tlv::SYSTEM_CAPABILITIES => {
                if let [a, b, c, d] = *t.info {
                    let caps = (u16::from_be_bytes([a, b]), u16::from_be_bytes([c, d]));
                    self.capabilities = self.capabilities.or(Some(caps));
                }
            }
            tlv::MANAGEMENT_ADDRESS => {
                if let Some(ip) = management_ipv4(t.info) {
                    // Beyond the room kept, further addresses are left out.
                    let _ = self.addresses.push(ip);
                }
            }
            tlv::ORGANIZATIONAL => self.organizational(t.info),
            _ => {}
        }
    }

    /// An organizationally specific TLV: the ODVA ones are read, others skipped.
    fn organizational(&mut self, info: &'a [u8]) {
        let Some((head, body)) = info.split_first_chunk::<4>() else {
            return;
        };
        let [a, b, c, subtype] = *head;
        if [a, b, c] != ODVA_OUI {
            return;
        }
        match subtype {
            odva::CIP_IDENTIFICATION if info.len() == CIP_IDENTIFICATION_LEN => {
                if let Ok(id) = CipIdentification::parse(body) {
                    self.cip_identification = self.cip_identification.or(Some(id));
                }
            }
            odva::CIP_MAC_ADDRESS if info.len() == CIP_MAC_LEN => {
                if let Ok(mac) = <[u8; 6]>::try_from(body) {
                    self.cip_mac = self.cip_mac.or(Some(mac));
                }
            }
            odva::CIP_INTERFACE_LABEL if body.len() <= 64 => {
                self.cip_interface_label = self.cip_interface_label.or(Some(body));
            }
            _ => {}
        }
    }

    /// The sender's MAC address as the LLDP Data Table object takes it: the CIP MAC Address
    /// TLV's, else the Chassis ID's or the Port ID's when of the MAC address subtype, else
    /// all zero.
    pub fn neighbor_mac(&self) -> [u8; 6] {
        let mac = |subtype: u8, want: u8, id: &[u8]| {
            (subtype == want)
                .then(|| <[u8; 6]>::try_from(id).ok())
                .flatten()
        };
        self.cip_mac
            .or_else(|| mac(self.chassis_subtype, CHASSIS_MAC, self.chassis_id))
            .or_else(|| mac(self.port_subtype, PORT_MAC, self.port_id))
            .unwrap_or_default()
    }
}

/// Reads a mandatory TLV of type `kind` whose information length lies in `len`.
fn mandatory<'a>(
    r: &mut Reader<'a>,
    kind: u8,
    len: core::ops::RangeInclusive<usize>,
) -> Result<&'a [u8]> {
    let t = next_tlv(r)?;
    if t.kind != kind || !len.contains(&t.info.len()) {
        return Err(Error::Malformed);
    }
    Ok(t.info)
}

/// The IPv4 address of a Management Address TLV, if it carries one and is well formed.
fn management_ipv4(info: &[u8]) -> Option<Ipv4Addr> {
    let mut r = Reader::new(info);
    let addr_len = usize::from(r.u8().ok()?);
    let addr = r.take(addr_len).ok()?;
    // Interface numbering subtype and number, then the OID string.
    r.take(5).ok()?;
    let oid_len = usize::from(r.u8().ok()?);
    r.take(oid_len).ok()?;
    match *addr {
        [ADDRESS_IPV4, a, b, c, d] if r.remaining() == 0 => Some(Ipv4Addr::new(a, b, c, d)),
        _ => None,
    }
}

/// What the adapter announces about itself.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LocalSystem<'a> {
    /// The interface's MAC address: the Chassis ID and the CIP MAC Address.
    pub mac: [u8; 6],
    /// The Port ID (interface name).
    pub port_id: &'a [u8],
    /// Time To Live in seconds.
    pub ttl: u16,
    /// System Name (the host name); left out when empty.
    pub system_name: &'a [u8],
    /// System Description (the product name); left out when empty.
    pub system_description: &'a [u8],
    /// The management address; left out when unspecified.
    pub ip: Ipv4Addr,
    /// ifIndex of the interface the management address belongs to.
    pub if_index: u32,
    /// The CIP identity.
    pub identity: CipIdentification,
}

impl LocalSystem<'_> {
    /// Writes the whole LLDPDU: mandatory TLVs, System Name, System Description, System
    /// Capabilities, Management Address, the ODVA CIP Identification and CIP MAC Address
    /// TLVs, End.
    pub fn emit(&self, w: &mut Writer<'_>) -> Result<()> {
        self.emit_mandatory(w, self.ttl)?;
        for (kind, text) in [
            (tlv::SYSTEM_NAME, self.system_name),
            (tlv::SYSTEM_DESCRIPTION, self.system_description),
        ] {
            if !text.is_empty() {
                let text = text.get(..255).unwrap_or(text);
                header(w, kind, text.len())?;
                w.bytes(text)?;
            }
        }
        header(w, tlv::SYSTEM_CAPABILITIES, 4)?;
        w.bytes(&CAPABILITY_STATION.to_be_bytes())?;
        w.bytes(&CAPABILITY_STATION.to_be_bytes())?;
        if !self.ip.is_unspecified() {
            header(w, tlv::MANAGEMENT_ADDRESS, 12)?;
            w.bytes(&[5, ADDRESS_IPV4])?;
            w.bytes(&self.ip.octets())?;
            w.u8(IF_INDEX)?;
            w.bytes(&self.if_index.to_be_bytes())?;
            w.u8(0)?; // no OID
        }
        header(w, tlv::ORGANIZATIONAL, CIP_IDENTIFICATION_LEN)?;
        w.bytes(&ODVA_OUI)?;
        w.u8(odva::CIP_IDENTIFICATION)?;
        self.identity.emit(w)?;
        header(w, tlv::ORGANIZATIONAL, CIP_MAC_LEN)?;
        w.bytes(&ODVA_OUI)?;
        w.u8(odva::CIP_MAC_ADDRESS)?;
        w.bytes(&self.mac)?;
        header(w, tlv::END, 0)
    }

    /// Writes the shutdown LLDPDU: the mandatory TLVs with a Time To Live of 0, then End.
    pub fn emit_shutdown(&self, w: &mut Writer<'_>) -> Result<()> {
        self.emit_mandatory(w, 0)?;
        header(w, tlv::END, 0)
    }

    fn emit_mandatory(&self, w: &mut Writer<'_>, ttl: u16) -> Result<()> {
        header(w, tlv::CHASSIS_ID, 7)?;
        w.u8(CHASSIS_MAC)?;
        w.bytes(&self.mac)?;
        let port = self.port_id.get(..255).unwrap_or(self.port_id);
        header(w, tlv::PORT_ID, port.len().saturating_add(1))?;
        w.u8(PORT_INTERFACE_NAME)?;
        w.bytes(port)?;
        header(w, tlv::TTL, 2)?;
        w.bytes(&ttl.to_be_bytes())
    }
}

/// Writes a TLV header.
fn header(w: &mut Writer<'_>, kind: u8, len: usize) -> Result<()> {
    let len = u16::try_from(len)
        .ok()
        .filter(|l| usize::from(*l) <= MAX_INFO)
        .ok_or(Error::Malformed)?;
    w.bytes(&((u16::from(kind & 0x7F) << 9) | len).to_be_bytes())
}

#[cfg(test)]
mod tests;
