//! The network stack's checksums, verified and filled by the link task in its place, on
//! boards that ask for it ([`super::NetDriver::with_link_checksums`] and
//! [`super::run_with_link_checksums`]; about 400 bytes of flash, which the smallest image
//! has not to spare, and none on a board that does not ask): the driver tells embassy-net
//! that the "hardware" does every one smoltcp would (IPv4 header, TCP, UDP, ICMP), and the
//! link task does what the board's driver leaves to software (`Pump`'s `sums`) with
//! [`super::checksum`]'s word-at-a-time sum ([`each`]): it verifies every frame it passes
//! to the stack (a bad one is dropped, as smoltcp would have dropped it) and fills every
//! frame the stack sends. Where the driver does a checksum itself, neither side computes
//! it. The rules are smoltcp 0.13's: the header
//! sum over the IPv4 header, TCP's and ICMP's over the whole IPv4 payload (the frame's
//! padding left out), UDP's over its own length, a zero UDP sum meaning none and a computed
//! zero sent as all ones. IGMP smoltcp sums itself whatever it is told. A frame that is not
//! well-formed IPv4, or too short for its protocol's header, is left to the stack, which
//! drops it as before.

use smoltcp::phy::{Checksum, ChecksumCapabilities};
use smoltcp::wire::{ETHERNET_HEADER_LEN, IPV4_HEADER_LEN};

use super::checksum::Sum;

/// The IPv4 ethertype.
const IPV4: [u8; 2] = [0x08, 0x00];
/// IP protocol numbers.
const ICMP: u8 = 1;
const TCP: u8 = 6;
const UDP: u8 = 17;
/// Offsets of the checksum fields: IPv4 header, TCP, UDP, ICMP headers.
const IPV4_SUM: usize = 10;
const TCP_SUM: usize = 16;
const UDP_SUM: usize = 6;
const ICMP_SUM: usize = 2;

/// Proof that the network stack was told its checksums are done for it
/// ([`super::NetDriver::with_link_checksums`]), which [`super::run_with_link_checksums`]
/// wants: the link task does them if, and only if, the stack does not.
#[derive(Debug)]
pub struct LinkChecksums(pub(crate) ());

/// Fills (`fill`) or verifies each checksum of `frame` that `sums` leaves to software: the
/// IPv4 header's, then TCP's, UDP's or ICMP's; false if one did not hold (true for a frame
/// whose checksums the stack would not check). One function for both ways, the frame's
/// layout read once. Never inlined: each frame to or from the stack calls it once.
#[inline(never)]
pub(crate) fn each(frame: &mut [u8], sums: &ChecksumCapabilities, fill: bool) -> bool {
    let software = |c: Checksum| if fill { c.tx() } else { c.rx() };
    let Some((eth, ip)) = frame.split_first_chunk_mut::<ETHERNET_HEADER_LEN>() else {
        return true;
    };
    let Some(&[version_ihl, _, l0, l1, _, _, _, _, _, protocol, ..]) =
        ip.first_chunk::<IPV4_HEADER_LEN>()
    else {
        return true;
    };
    // smoltcp's length checks: a header of at least 20 bytes within the total length, the
    // total length within the frame (the rest is padding).
    let header_len = usize::from(version_ihl & 0x0F).wrapping_mul(4);
    let total_len = usize::from(u16::from_be_bytes([l0, l1]));
    let Some(ip) = ip.get_mut(..total_len).filter(|_| {
        eth.get(12..) == Some(&IPV4[..]) && version_ihl >> 4 == 4 && header_len >= IPV4_HEADER_LEN
    }) else {
        return true;
    };
    let Some((header, payload)) = ip.split_at_mut_checked(header_len) else {
        return true;
    };
    if software(sums.ipv4) && !sum(header, IPV4_SUM, Sum::default(), fill) {
        return false;
    }
    let (at, len, check) = match protocol {
        TCP => (TCP_SUM, payload.len(), sums.tcp),
        UDP => {
            let Some(&[_, _, _, _, u0, u1, c0, c1]) = payload.first_chunk::<8>() else {
                return true;
            };
            if !fill && [c0, c1] == [0, 0] {
                // No checksum was sent.
                return true;
            }
            (UDP_SUM, usize::from(u16::from_be_bytes([u0, u1])), sums.udp)
        }
        ICMP => (ICMP_SUM, payload.len(), sums.icmpv4),
        _ => return true,
    };
    // A UDP length below the header or beyond the payload: the stack drops the datagram.
    let Some(bytes) = payload
        .get_mut(..len)
        .filter(|_| len >= 8 && software(check))
    else {
        return true;
    };
    // The pseudo-header of TCP and UDP: the addresses, the protocol and the length.
    let start = match header.first_chunk::<IPV4_HEADER_LEN>() {
        Some(&[.., s0, s1, s2, s3, d0, d1, d2, d3]) if protocol != ICMP => {
            let [l0, l1] = (len as u16).to_be_bytes();
            Sum::default()
                .add_word([s0, s1, s2, s3])
                .add_word([d0, d1, d2, d3])
                .add_word([0, protocol, l0, l1])
        }
        _ => Sum::default(),
    };
    sum(bytes, at, start, fill)
}

/// Fills (`fill`) the checksum field at `at` of `bytes` with their checksum (`start` added;
/// the field zero while they are summed), or verifies that they sum to all ones; false if
/// not. A computed UDP zero goes out as all ones (UDP's zero means no checksum); a field
/// not within `bytes` is left alone.
fn sum(bytes: &mut [u8], at: usize, start: Sum, fill: bool) -> bool {
    if !fill {
        return start.add(bytes).is_valid();
    }
    let Some(field) = bytes.get_mut(at..at.wrapping_add(2)) else {
        return true;
    };
    field.fill(0);
    let sum = start.add(bytes).checksum();
    let sum = if at == UDP_SUM && sum == [0, 0] {
        [0xFF, 0xFF]
    } else {
        sum
    };
    if let Some(field) = bytes.get_mut(at..at.wrapping_add(2)) {
        field.copy_from_slice(&sum);
    }
    true
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::link::test_frames::{ipv4_frame, ipv4_mut, tcp_segment, ME, PEER};
    use smoltcp::wire::{
        EthernetFrame, Icmpv4Packet, Icmpv4Repr, IpAddress, IpProtocol, Ipv4Packet, Ipv4Repr,
        TcpPacket, TcpRepr, UdpPacket, UdpRepr,
    };
    use std::vec::Vec;

    /// The link task's look at a frame on its way to the stack.
    fn verify(frame: &mut [u8], sums: &ChecksumCapabilities) -> bool {
        each(frame, sums, false)
    }

    /// The link task's work on a frame the stack sends.
    fn fill(frame: &mut [u8], sums: &ChecksumCapabilities) {
        each(frame, sums, true);
    }

    /// What smoltcp computes with every checksum in software.
    fn software() -> ChecksumCapabilities {
        ChecksumCapabilities::default()
    }

    /// The kinds of IPv4 packets smoltcp sends and accepts here.
    #[derive(Clone, Copy, Debug)]
    enum Kind {
        Tcp,
        Udp,
        Icmp,
        /// IGMP, summed by smoltcp itself: protocol 2, eight bytes.
        Igmp,
    }

    const KINDS: [Kind; 4] = [Kind::Tcp, Kind::Udp, Kind::Icmp, Kind::Igmp];

    /// A frame from `ME` to the peer as smoltcp emits it with `sums`, with `pad` bytes of
    /// Ethernet padding behind it.
    fn frame(kind: Kind, payload: &[u8], sums: &ChecksumCapabilities, pad: usize) -> Vec<u8> {
        let tcp = tcp_segment(44818, payload);
        let icmp = Icmpv4Repr::EchoReply {
            ident: 0x1234,
            seq_no: 5,
            data: payload,
        };
        let (len, protocol) = match kind {
            Kind::Tcp => (tcp.buffer_len(), IpProtocol::Tcp),
            Kind::Udp => (8 + payload.len(), IpProtocol::Udp),
            Kind::Icmp => (icmp.buffer_len(), IpProtocol::Icmp),
            Kind::Igmp => (8, IpProtocol::Igmp),
        };
        let mut f = ipv4_frame(protocol, len, pad, sums);
        let mut ip = ipv4_mut(&mut f);
        let (src, dst) = (IpAddress::Ipv4(ME), IpAddress::Ipv4(PEER));
        let payload_mut = &mut ip.payload_mut()[..len];
        match kind {
            Kind::Tcp => tcp.emit(&mut TcpPacket::new_unchecked(payload_mut), &src, &dst, sums),
            Kind::Udp => UdpRepr {
                src_port: 44818,
                dst_port: 50000,
            }
            .emit(
                &mut UdpPacket::new_unchecked(payload_mut),
                &src,
                &dst,
                payload.len(),
                |b| b.copy_from_slice(payload),
                sums,
            ),
            Kind::Icmp => icmp.emit(&mut Icmpv4Packet::new_unchecked(payload_mut), sums),
            // A membership report with smoltcp's own checksum.
            Kind::Igmp => payload_mut.copy_from_slice(&[0x16, 0, 0xFA, 0x04, 239, 192, 1, 0]),
        }
        f
    }

    /// Whether smoltcp takes `frame` in with `sums`: the IPv4 header, then the TCP, UDP or
    /// ICMP packet parsed as its interface does.
    fn smoltcp_accepts(frame: &[u8], sums: &ChecksumCapabilities) -> bool {
        let Ok(eth) = EthernetFrame::new_checked(frame) else {
            return false;
        };
        let Ok(ip) = Ipv4Packet::new_checked(eth.payload()) else {
            return false;
        };
        let Ok(repr) = Ipv4Repr::parse(&ip, sums) else {
            return false;
        };
        let (src, dst) = (
            IpAddress::Ipv4(repr.src_addr),
            IpAddress::Ipv4(repr.dst_addr),
        );
        match repr.next_header {
            IpProtocol::Tcp => TcpPacket::new_checked(ip.payload())
                .and_then(|p| TcpRepr::parse(&p, &src, &dst, sums).map(|_| ()))
                .is_ok(),
            IpProtocol::Udp => UdpPacket::new_checked(ip.payload())
                .and_then(|p| UdpRepr::parse(&p, &src, &dst, sums).map(|_| ()))
                .is_ok(),
            IpProtocol::Icmp => Icmpv4Packet::new_checked(ip.payload())
                .and_then(|p| Icmpv4Repr::parse(&p, sums).map(|_| ()))
                .is_ok(),
            _ => true,
        }
    }

    #[test]
    fn filled_frames_are_the_ones_smoltcp_sums_itself() {
        for kind in KINDS {
            for payload in [&b""[..], b"x", b"a reply of odd length", &[0xFF; 100]] {
                for pad in [0, 7] {
                    let mut ours = frame(kind, payload, &ChecksumCapabilities::ignored(), pad);
                    fill(&mut ours, &software());
                    let theirs = frame(kind, payload, &software(), pad);
                    assert_eq!(ours, theirs, "{kind:?} {} bytes, pad {pad}", payload.len());
                    assert!(verify(&mut ours, &software()) && smoltcp_accepts(&ours, &software()));
                }
            }
        }
    }

    #[test]
    fn a_frame_marked_with_the_explicit_dscp_is_filled_right() {
        // As the link task sends the stack's frames: marked (no sum refreshed), then filled.
        let mut f = frame(Kind::Tcp, b"reply", &ChecksumCapabilities::ignored(), 0);
        super::super::dscp::mark_explicit(&mut f, 27, &ChecksumCapabilities::ignored());
        fill(&mut f, &software());
        assert_eq!(Ipv4Packet::new_checked(&f[14..]).unwrap().dscp(), 27);
        assert!(smoltcp_accepts(&f, &software()));
    }

    #[test]
    fn a_udp_sum_of_zero_is_sent_as_all_ones() {
        let mut f = frame(Kind::Udp, &[0, 0], &software(), 0);
        // Two payload bytes equal to the checksum of the rest make the sum zero.
        let at = f.len() - 2;
        let sum = [f[at - 2], f[at - 1]];
        assert_ne!(sum, [0xFF, 0xFF]);
        f[at..].copy_from_slice(&sum);
        fill(&mut f, &software());
        assert_eq!(&f[at - 2..at], &[0xFF, 0xFF]);
        assert!(verify(&mut f, &software()) && smoltcp_accepts(&f, &software()));
    }

    #[test]
    fn what_the_driver_does_is_left_to_it() {
        for kind in KINDS {
            let blank = frame(kind, b"data", &ChecksumCapabilities::ignored(), 0);
            let mut f = blank.clone();
            fill(&mut f, &ChecksumCapabilities::ignored());
            assert_eq!(f, blank, "{kind:?}");
            assert!(verify(&mut f, &ChecksumCapabilities::ignored()), "{kind:?}");
        }
        // The header offloaded, TCP's in software.
        let mut split = software();
        split.ipv4 = Checksum::None;
        let mut f = frame(Kind::Tcp, b"data", &ChecksumCapabilities::ignored(), 0);
        fill(&mut f, &split);
        assert_eq!(Ipv4Packet::new_checked(&f[14..]).unwrap().checksum(), 0);
        let mut good = f.clone();
        Ipv4Packet::new_unchecked(&mut good[14..]).fill_checksum();
        assert!(smoltcp_accepts(&good, &software()));
    }

    #[test]
    fn a_frame_is_dropped_exactly_when_smoltcp_would_drop_it_for_its_checksum() {
        // Every byte of every kind of frame corrupted in turn (and a UDP datagram without a
        // checksum): the link task drops a frame just when smoltcp, summing in software,
        // would have dropped it and, told the sums are done, would not.
        let mut frames: Vec<Vec<u8>> = KINDS
            .iter()
            .map(|k| frame(*k, b"request data", &software(), 3))
            .collect();
        let mut unsummed = frame(Kind::Udp, b"no sum", &software(), 0);
        let at = 14 + 20 + 6;
        unsummed[at..at + 2].fill(0);
        frames.push(unsummed);
        let mut offloaded = software();
        offloaded.tcp = Checksum::Tx;
        offloaded.udp = Checksum::None;
        for sums in [software(), offloaded] {
            for good in &frames {
                for at in 0..good.len() {
                    for flip in [0x01, 0x80, 0xFF] {
                        let mut f = good.clone();
                        f[at] ^= flip;
                        let link = verify(&mut f, &sums);
                        let stack_after = smoltcp_accepts(&f, &ChecksumCapabilities::ignored());
                        assert_eq!(
                            smoltcp_accepts(&f, &sums),
                            link && stack_after,
                            "byte {at} ^ {flip:#x} of {good:x?}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn anything_else_goes_to_the_stack_and_nothing_panics() {
        let whole = frame(Kind::Tcp, b"0123456789", &software(), 0);
        for len in 0..whole.len() {
            let mut f = whole[..len].to_vec();
            assert!(verify(&mut f, &software()), "{len} bytes");
            fill(&mut f, &software());
            assert_eq!(f, whole[..len], "{len} bytes");
        }
        // ARP: not IPv4.
        let mut arp = whole.clone();
        arp[12..14].copy_from_slice(&[0x08, 0x06]);
        arp[30] ^= 0xFF;
        assert!(verify(&mut arp, &software()));
    }
}
