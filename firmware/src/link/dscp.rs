//! DSCP marking of the explicit-messaging packets the network stack sends: smoltcp has no
//! per-socket DS field, so on their way from embassy-net to the driver the link task
//! rewrites the DS field of every IPv4 packet of TCP or UDP from port 44818 (the ECN bits
//! kept) to the QoS object's explicit DSCP, and refreshes the IPv4 header checksum where
//! software fills it (the TCP and UDP checksums do not cover the DS field). Class 1 T->O
//! packets get their connection's DSCP where the link task writes their headers
//! ([`super::route::Headers`]).

use enip_stack::config::ENCAP_PORT;
use smoltcp::phy::ChecksumCapabilities;
use smoltcp::wire::{ETHERNET_HEADER_LEN, IPV4_HEADER_LEN};

use super::checksum::Sum;

/// The IPv4 ethertype.
const IPV4: [u8; 2] = [0x08, 0x00];
/// IP protocol numbers of TCP and UDP.
const TCP: u8 = 6;
const UDP: u8 = 17;
/// Offset of the header checksum in the IPv4 header.
const CHECKSUM: usize = 10;

/// Marks `frame` with `dscp` if it is an IPv4 packet of TCP or UDP from port 44818 (the first
/// fragment, the one with the ports); `fill` says which checksums software fills. Anything
/// else, malformed or cut short included, is left as it is. Read on the bytes, not through
/// smoltcp's packet views: this runs for every frame the network stack sends.
pub(crate) fn mark_explicit(frame: &mut [u8], dscp: u8, fill: &ChecksumCapabilities) {
    if frame.get(12..ETHERNET_HEADER_LEN) != Some(&IPV4[..]) {
        return;
    }
    let Some(ip) = frame.get_mut(ETHERNET_HEADER_LEN..) else {
        return;
    };
    let &[version_ihl, tos, len_hi, len_lo, _, _, frag_hi, frag_lo, _, protocol, ..] = &*ip else {
        return;
    };
    let header_len = usize::from(version_ihl & 0x0F).wrapping_mul(4);
    // The source port; no overflow, the header is 60 bytes at most.
    let port = header_len..header_len.wrapping_add(2);
    let total_len = usize::from(u16::from_be_bytes([len_hi, len_lo]));
    let first_fragment = u16::from_be_bytes([frag_hi, frag_lo]) & 0x1FFF == 0;
    let marked = ((dscp & 0x3F) << 2) | (tos & 0x03);
    if version_ihl >> 4 != 4
        || header_len < IPV4_HEADER_LEN
        || !(port.end..=ip.len()).contains(&total_len)
        || !matches!(protocol, TCP | UDP)
        || !first_fragment
        || marked == tos
        || ip.get(port) != Some(&ENCAP_PORT.to_be_bytes()[..])
    {
        return;
    }
    let Some(header) = ip.get_mut(..header_len) else {
        return;
    };
    if let Some(b) = header.get_mut(1) {
        *b = marked;
    }
    if fill.ipv4.tx() {
        if let Some(sum) = header.get_mut(CHECKSUM..CHECKSUM + 2) {
            sum.fill(0);
        }
        let sum = Sum::default().add(header).checksum();
        if let Some(to) = header.get_mut(CHECKSUM..CHECKSUM + 2) {
            to.copy_from_slice(&sum);
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::link::test_frames::{ipv4_frame, ipv4_mut, tcp_segment, ME, PEER};
    use smoltcp::phy::Checksum;
    use smoltcp::wire::{IpAddress, IpProtocol, Ipv4Packet, TcpPacket, UdpPacket, UdpRepr};
    use std::vec::Vec;

    /// The highest DSCP.
    const MAX: u8 = 63;

    /// A frame from `ME`:`src_port` to the peer, TCP or UDP, as smoltcp sends it, with the
    /// ECN bits set to 0b01.
    fn frame(tcp: bool, src_port: u16, payload: &[u8]) -> Vec<u8> {
        let sums = ChecksumCapabilities::default();
        let tcp_repr = tcp_segment(src_port, payload);
        let (len, protocol) = if tcp {
            (tcp_repr.buffer_len(), IpProtocol::Tcp)
        } else {
            (8 + payload.len(), IpProtocol::Udp)
        };
        let mut f = ipv4_frame(protocol, len, 0, &sums);
        let mut ip = ipv4_mut(&mut f);
        ip.set_ecn(1);
        ip.fill_checksum();
        let (src, dst) = (IpAddress::Ipv4(ME), IpAddress::Ipv4(PEER));
        if tcp {
            tcp_repr.emit(
                &mut TcpPacket::new_unchecked(ip.payload_mut()),
                &src,
                &dst,
                &sums,
            );
        } else {
            UdpRepr {
                src_port,
                dst_port: 50000,
            }
            .emit(
                &mut UdpPacket::new_unchecked(ip.payload_mut()),
                &src,
                &dst,
                payload.len(),
                |b| b.copy_from_slice(payload),
                &sums,
            );
        }
        f
    }

    fn ip(f: &[u8]) -> Ipv4Packet<&[u8]> {
        Ipv4Packet::new_checked(&f[ETHERNET_HEADER_LEN..]).unwrap()
    }

    #[test]
    fn tcp_and_udp_from_44818_get_the_dscp_with_good_checksums() {
        for tcp in [true, false] {
            let mut f = frame(tcp, ENCAP_PORT, b"reply");
            mark_explicit(&mut f, 27, &ChecksumCapabilities::default());
            let p = ip(&f);
            assert_eq!((p.dscp(), p.ecn()), (27, 1), "tcp {tcp}");
            assert!(p.verify_checksum());
            let (src, dst) = (IpAddress::Ipv4(ME), IpAddress::Ipv4(PEER));
            if tcp {
                let t = TcpPacket::new_checked(p.payload()).unwrap();
                assert!(t.verify_checksum(&src, &dst));
            } else {
                let u = UdpPacket::new_checked(p.payload()).unwrap();
                assert!(u.verify_checksum(&src, &dst));
            }
        }
    }

    #[test]
    fn every_dscp_from_every_dscp_keeps_the_header_checksum_right() {
        let sums = ChecksumCapabilities::default();
        for from in 0..=MAX {
            let mut f = frame(false, ENCAP_PORT, b"x");
            mark_explicit(&mut f, from, &sums);
            for to in 0..=MAX {
                let mut g = f.clone();
                mark_explicit(&mut g, to, &sums);
                let p = ip(&g);
                assert_eq!((p.dscp(), p.ecn()), (to, 1), "{from} -> {to}");
                assert!(p.verify_checksum(), "{from} -> {to}");
            }
        }
    }

    #[test]
    fn the_header_checksum_is_left_to_hardware_that_fills_it() {
        let mut f = frame(true, ENCAP_PORT, b"x");
        let before = ip(&f).checksum();
        let mut offloaded = ChecksumCapabilities::default();
        offloaded.ipv4 = Checksum::None;
        mark_explicit(&mut f, 20, &offloaded);
        assert_eq!((ip(&f).dscp(), ip(&f).checksum()), (20, before));
    }

    #[test]
    fn other_traffic_and_malformed_frames_are_left_alone() {
        let sums = ChecksumCapabilities::default();
        for original in [frame(true, 80, b"web"), frame(false, 2222, b"io")] {
            let mut f = original.clone();
            mark_explicit(&mut f, 27, &sums);
            assert_eq!(f, original);
        }
        // A later fragment: its first bytes are data, not ports.
        let mut fragment = frame(false, ENCAP_PORT, b"data");
        {
            let mut p = Ipv4Packet::new_unchecked(&mut fragment[ETHERNET_HEADER_LEN..]);
            p.set_frag_offset(8);
            p.fill_checksum();
        }
        let original = fragment.clone();
        mark_explicit(&mut fragment, 27, &sums);
        assert_eq!(fragment, original);
        // Every truncation: nothing panics, and nothing shorter than its IPv4 length is marked.
        let whole = frame(true, ENCAP_PORT, b"0123456789");
        for len in 0..whole.len() {
            let mut f = whole[..len].to_vec();
            mark_explicit(&mut f, 27, &sums);
            assert_eq!(f, whole[..len], "{len} bytes");
        }
    }
}
