//! The ARP messages of Address Conflict Detection: the 28-byte ARP PDU for IPv4 over
//! Ethernet (RFC 826) read from a received frame, and the probe and announcement frames
//! (RFC 5227 sections 2.1.1 and 2.3) written whole, Ethernet header included.

use core::net::Ipv4Addr;

/// Bytes of an ARP PDU for IPv4 over Ethernet.
pub const ARP_PDU_LEN: usize = 28;
/// Bytes of an Ethernet header.
const ETHERNET_HEADER_LEN: usize = 14;
/// Bytes of a whole ARP frame (Ethernet header and PDU, no padding or CRC).
pub const ARP_FRAME_LEN: usize = ETHERNET_HEADER_LEN + ARP_PDU_LEN;
/// The Ethernet type of ARP.
pub const ETHERTYPE_ARP: u16 = 0x0806;
/// ARP operation: request.
pub const OP_REQUEST: u16 = 1;
/// ARP operation: reply.
pub const OP_REPLY: u16 = 2;
/// Hardware type, protocol type, hardware and protocol address sizes of IPv4 over Ethernet.
const HEADER: [u8; 6] = [0x00, 0x01, 0x08, 0x00, 6, 4];

/// One received ARP PDU for IPv4 over Ethernet, with its raw bytes (TCP/IP attribute 11
/// keeps them).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Arp {
    /// Operation: [`OP_REQUEST`] or [`OP_REPLY`] (others are kept as they came).
    pub op: u16,
    /// Sender hardware address.
    pub sender_mac: [u8; 6],
    /// Sender protocol address (0.0.0.0 in a probe).
    pub sender_ip: Ipv4Addr,
    /// Target hardware address.
    pub target_mac: [u8; 6],
    /// Target protocol address.
    pub target_ip: Ipv4Addr,
    /// The PDU as received.
    pub raw: [u8; ARP_PDU_LEN],
}

impl Arp {
    /// Reads the ARP PDU at the start of `payload` (an Ethernet frame's payload of type
    /// [`ETHERTYPE_ARP`]); `None` unless it is IPv4 over Ethernet and whole.
    pub fn parse(payload: &[u8]) -> Option<Arp> {
        let raw: [u8; ARP_PDU_LEN] = payload.get(..ARP_PDU_LEN)?.try_into().ok()?;
        if raw.get(..6)? != HEADER {
            return None;
        }
        let mac = |r: core::ops::Range<usize>| -> Option<[u8; 6]> { raw.get(r)?.try_into().ok() };
        let ip = |r: core::ops::Range<usize>| -> Option<Ipv4Addr> {
            let b: [u8; 4] = raw.get(r)?.try_into().ok()?;
            Some(Ipv4Addr::from(b))
        };
        Some(Arp {
            op: u16::from_be_bytes([*raw.get(6)?, *raw.get(7)?]),
            sender_mac: mac(8..14)?,
            sender_ip: ip(14..18)?,
            target_mac: mac(18..24)?,
            target_ip: ip(24..28)?,
            raw,
        })
    }

    /// Reads the ARP PDU of a whole Ethernet `frame`; `None` if it carries none.
    pub fn from_frame(frame: &[u8]) -> Option<Arp> {
        let ethertype = frame.get(12..ETHERNET_HEADER_LEN)?;
        if ethertype != ETHERTYPE_ARP.to_be_bytes() {
            return None;
        }
        Arp::parse(frame.get(ETHERNET_HEADER_LEN..)?)
    }
}

/// What Address Conflict Detection sends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ArpFrame {
    /// A probe: a request with sender address 0.0.0.0 asking for the address under test.
    Probe,
    /// An announcement: a request with sender and target address both the one claimed.
    Announcement,
}

impl ArpFrame {
    /// Writes this frame from `mac` about `ip` into `buf` (broadcast, [`ARP_FRAME_LEN`]
    /// bytes); the bytes written, 0 if `buf` is too short.
    pub fn write(self, mac: [u8; 6], ip: Ipv4Addr, buf: &mut [u8]) -> usize {
        let Some(out) = buf.get_mut(..ARP_FRAME_LEN) else {
            return 0;
        };
        let sender_ip = match self {
            ArpFrame::Probe => Ipv4Addr::UNSPECIFIED,
            ArpFrame::Announcement => ip,
        };
        let parts: [&[u8]; 9] = [
            &[0xFF; 6],
            &mac,
            &ETHERTYPE_ARP.to_be_bytes(),
            &HEADER,
            &OP_REQUEST.to_be_bytes(),
            &mac,
            &sender_ip.octets(),
            &[0; 6],
            &ip.octets(),
        ];
        let mut at = 0usize;
        for part in parts {
            let end = at.saturating_add(part.len());
            if let Some(slot) = out.get_mut(at..end) {
                slot.copy_from_slice(part);
            }
            at = end;
        }
        ARP_FRAME_LEN
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MAC: [u8; 6] = [2, 0x45, 0x4E, 0x49, 0x50, 1];
    const IP: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 2);

    #[test]
    fn probe_and_announcement_round_trip() {
        let mut buf = [0u8; 60];
        assert_eq!(ArpFrame::Probe.write(MAC, IP, &mut buf), ARP_FRAME_LEN);
        assert_eq!(buf[..6], [0xFF; 6]);
        let probe = Arp::from_frame(&buf).unwrap();
        assert_eq!(probe.op, OP_REQUEST);
        assert_eq!(
            (
                probe.sender_mac,
                probe.sender_ip,
                probe.target_mac,
                probe.target_ip
            ),
            (MAC, Ipv4Addr::UNSPECIFIED, [0; 6], IP)
        );
        assert_eq!(probe.raw[..], buf[14..42]);
        ArpFrame::Announcement.write(MAC, IP, &mut buf);
        let announce = Arp::from_frame(&buf).unwrap();
        assert_eq!((announce.sender_ip, announce.target_ip), (IP, IP));
    }

    #[test]
    fn refuses_short_or_foreign_pdus() {
        let mut buf = [0u8; ARP_FRAME_LEN];
        assert_eq!(ArpFrame::Probe.write(MAC, IP, &mut buf[..41]), 0);
        ArpFrame::Probe.write(MAC, IP, &mut buf);
        assert!(Arp::from_frame(&buf[..41]).is_none());
        let mut ipv6 = buf;
        ipv6[16] = 0x86;
        assert!(Arp::from_frame(&ipv6).is_none());
        let mut not_arp = buf;
        not_arp[13] = 0x00;
        assert!(Arp::from_frame(&not_arp).is_none());
    }
}
