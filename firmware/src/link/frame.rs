//! Ethernet frames as the link task sees them: which received frames are O->T datagrams
//! for this adapter (IPv4, UDP port 2222, not fragmented, checksums good) and who sent
//! them, and an ARP request (the T->O datagrams' headers are [`super::route`]'s). Parsing
//! and writing are smoltcp's `wire` codecs, length-checked; the checksums are
//! [`super::checksum`]'s.

use core::net::{Ipv4Addr, SocketAddrV4};
use core::ops::Range;

use embassy_net_driver::TxToken;
use enip_stack::config::IO_PORT;
use enip_stack::NetworkConfig;
use smoltcp::phy::ChecksumCapabilities;

use super::checksum::Sum;
use smoltcp::wire::{
    ArpOperation, ArpPacket, ArpRepr, EthernetAddress, EthernetFrame, EthernetProtocol,
    EthernetRepr, ETHERNET_HEADER_LEN, IPV4_HEADER_LEN, UDP_HEADER_LEN,
};

/// Bytes in front of a T->O datagram's payload: Ethernet, IPv4 (no options) and UDP headers.
pub(crate) const HEADERS_LEN: usize = ETHERNET_HEADER_LEN + IPV4_HEADER_LEN + UDP_HEADER_LEN;
/// Bytes of an ARP request for an IPv4 address over Ethernet.
pub(crate) const ARP_REQUEST_LEN: usize = ETHERNET_HEADER_LEN + 28;

/// What a received frame holds for the link task.
#[derive(Debug, Default, PartialEq, Eq)]
pub(crate) struct Seen {
    /// The sender's IPv4 address and the MAC address it came from, for a frame addressed to
    /// this adapter's IPv4 address (an IPv4 packet or an ARP message) whose header checksum
    /// held: where T->O data for that address goes next, once the frame is taken in.
    pub sender: Option<(Ipv4Addr, [u8; 6])>,
    /// An O->T datagram: its source and where its UDP payload lies in the frame.
    pub o_t: Option<(SocketAddrV4, Range<usize>)>,
}

/// The ethertype of IPv4.
pub(crate) const IPV4: [u8; 2] = [0x08, 0x00];
/// The ethertype of ARP.
const ARP: [u8; 2] = [0x08, 0x06];
/// The IP protocol number of UDP.
pub(crate) const UDP: u8 = 17;

/// True if `frame` is an Ethernet frame of IPv4 (by its ethertype alone).
pub(crate) fn is_ipv4(frame: &[u8]) -> bool {
    frame.get(12..ETHERNET_HEADER_LEN) == Some(&IPV4[..])
}

/// The IP protocol number of ICMP.
const ICMP: u8 = 1;
/// The IP protocol number of TCP.
pub(crate) const TCP: u8 = 6;
/// The ICMP type of an echo request.
const ECHO_REQUEST: u8 = 8;

/// True if the IPv4 frame `frame` is one the network stack must not see at the adapter `me`:
/// a TCP segment to `me` that the link task did not take: a fragment (it takes whole
/// segments only, and the stack, without TCP or reassembly, would answer each with
/// "protocol unreachable") or one from a source [`tcp_source`] refuses (a "land" SYN, a
/// broadcast source); or an ICMP echo request to another address, a broadcast or multicast one
/// (RFC 1122 3.2.2.6 lets a host drop it: every device of a link answering one forged
/// request is an amplifier).
pub(crate) fn kept_from_stack(frame: &[u8], me: &NetworkConfig) -> bool {
    let Some(packet) = frame.get(ETHERNET_HEADER_LEN..).filter(|_| is_ipv4(frame)) else {
        return false;
    };
    let Some(&[ihl, _, _, _, _, _, f0, f1, _, protocol, _, _, s0, s1, s2, s3, d0, d1, d2, d3]) =
        packet.first_chunk::<IPV4_HEADER_LEN>()
    else {
        return false;
    };
    let to_me = Ipv4Addr::new(d0, d1, d2, d3) == me.ip;
    match protocol {
        // More fragments (0x2000) or a fragment offset.
        TCP => {
            to_me
                && (u16::from_be_bytes([f0, f1]) & 0x3FFF != 0
                    || !tcp_source(Ipv4Addr::new(s0, s1, s2, s3), me))
        }
        ICMP => {
            let header_len = usize::from(ihl & 0x0F).wrapping_mul(4);
            !to_me && packet.get(header_len) == Some(&ECHO_REQUEST)
        }
        _ => false,
    }
}

/// True if a TCP segment to the interface `me` may come from `src`: a host's address (RFC
/// 1122 3.2.1.3, 4.2.3.10: not zero, broadcast, multicast or loopback, and not the
/// broadcast or network address of `me`'s own subnet; a /31 link has neither, RFC 3021),
/// and not `me`'s own (a "land" SYN would have us answer ourselves). Another subnet's
/// addresses are judged by their own mask, which only their router knows.
pub(crate) fn tcp_source(src: Ipv4Addr, me: &NetworkConfig) -> bool {
    is_host(src)
        && src != me.ip
        && !src.is_loopback()
        && !me.is_broadcast(src)
        && !me.is_network_address(src)
}

/// Looks at `frame` for an adapter at `me`; `verify` says which checksums the driver left
/// to software. Anything that is not a well-formed O->T datagram for `me` has `o_t` `None`
/// and goes to the network stack, which deals with it as before. Read on the bytes, each
/// field once, the deciding ones first (this runs for every frame). (Never inlined:
/// `cargo xtask bench` shows its share of a cycle.)
#[inline(never)]
pub(crate) fn inspect(frame: &[u8], me: Ipv4Addr, verify: &ChecksumCapabilities) -> Seen {
    let Some((eth, packet)) = frame.split_first_chunk::<ETHERNET_HEADER_LEN>() else {
        return Seen::default();
    };
    let &[_, _, _, _, _, _, m0, m1, m2, m3, m4, m5, t0, t1] = eth;
    let mac = EthernetAddress([m0, m1, m2, m3, m4, m5]);
    match [t0, t1] {
        IPV4 => inspect_ipv4(packet, mac, me, verify),
        ARP => Seen {
            sender: arp_sender(packet, mac, me),
            o_t: None,
        },
        _ => Seen::default(),
    }
}

/// The IPv4 part of [`inspect`]: the lengths as smoltcp's checked views take them (a
/// header of at least 20 bytes within the total length, the total length within the
/// frame; a UDP length from 8 up to the IPv4 payload's).
fn inspect_ipv4(
    packet: &[u8],
    mac: EthernetAddress,
    me: Ipv4Addr,
    verify: &ChecksumCapabilities,
) -> Seen {
    let Some(h) = packet.first_chunk::<IPV4_HEADER_LEN>() else {
        return Seen::default();
    };
    let &[ihl, _, l0, l1, _, _, f0, f1, _, protocol, _, _, s0, s1, s2, s3, d0, d1, d2, d3] = h;
    let header_len = usize::from(ihl & 0x0F).wrapping_mul(4);
    let total_len = usize::from(u16::from_be_bytes([l0, l1]));
    if Ipv4Addr::new(d0, d1, d2, d3) != me
        || ihl >> 4 != 4
        || header_len < IPV4_HEADER_LEN
        || header_len > total_len
        || total_len > packet.len()
    {
        return Seen::default();
    }
    let header = packet.get(..header_len).unwrap_or(&[]);
    if verify.ipv4.rx() && !Sum::default().add(header).is_valid() {
        return Seen::default();
    }
    let src = Ipv4Addr::new(s0, s1, s2, s3);
    let sender = (is_unicast(mac) && is_host(src)).then_some((src, mac.0));
    // More fragments (0x2000) or a fragment offset: not the whole datagram.
    let unfragmented = u16::from_be_bytes([f0, f1]) & 0x3FFF == 0;
    let segment = packet.get(header_len..total_len).unwrap_or(&[]);
    let udp = segment.first_chunk::<UDP_HEADER_LEN>();
    let Some(&[p0, p1, q0, q1, u0, u1, c0, c1]) = udp.filter(|_| protocol == UDP) else {
        return Seen { sender, o_t: None };
    };
    let udp_len = u16::from_be_bytes([u0, u1]);
    let Some(datagram) = segment.get(..usize::from(udp_len)) else {
        return Seen { sender, o_t: None };
    };
    if u16::from_be_bytes([q0, q1]) != IO_PORT
        || !unfragmented
        || usize::from(udp_len) < UDP_HEADER_LEN
        || sender.is_none()
    {
        return Seen { sender, o_t: None };
    }
    let good = !verify.udp.rx() || [c0, c1] == [0, 0] || {
        let sum = Sum::default().add_pseudo_header(src, me, udp_len);
        sum.add(datagram).is_valid()
    };
    if !good {
        return Seen { sender, o_t: None };
    }
    // The payload's place in the frame: behind the Ethernet, IPv4 (with its options) and
    // UDP headers, as long as the UDP length says.
    let start = header_len.wrapping_add(ETHERNET_HEADER_LEN + UDP_HEADER_LEN);
    let end = header_len.wrapping_add(ETHERNET_HEADER_LEN + usize::from(udp_len));
    Seen {
        sender,
        o_t: Some((
            SocketAddrV4::new(src, u16::from_be_bytes([p0, p1])),
            start..end,
        )),
    }
}

/// The sender of an ARP message asking for or answering about `me`, sent from `from`: one
/// whose sender hardware address is not `from` names no sender (which of the two would the
/// T->O datagrams go to?).
fn arp_sender(packet: &[u8], from: EthernetAddress, me: Ipv4Addr) -> Option<(Ipv4Addr, [u8; 6])> {
    let arp = ArpPacket::new_checked(packet).ok()?;
    let Ok(ArpRepr::EthernetIpv4 {
        source_hardware_addr: mac,
        source_protocol_addr: ip,
        target_protocol_addr,
        ..
    }) = ArpRepr::parse(&arp)
    else {
        return None;
    };
    (target_protocol_addr == me && mac == from && is_host(ip) && is_unicast(mac))
        .then_some((ip, mac.0))
}

/// A MAC address of one station (not group, not zero).
fn is_unicast(mac: EthernetAddress) -> bool {
    mac.is_unicast() && mac.0 != [0; 6]
}

/// An IPv4 address of one host: not zero, broadcast or multicast.
fn is_host(ip: Ipv4Addr) -> bool {
    !(ip.is_unspecified() || ip.is_broadcast() || ip.is_multicast())
}

/// The Ethernet group address of IPv4 multicast group `group` (RFC 1112 section 6.4).
pub(crate) fn multicast_mac(group: Ipv4Addr) -> [u8; 6] {
    let [_, b, c, d] = group.octets();
    [0x01, 0x00, 0x5E, b & 0x7F, c, d]
}

/// Writes an ARP request from `from` (MAC, IPv4) for `target` into `frame` (at least
/// [`ARP_REQUEST_LEN`] bytes); `false` if it is too short.
pub(crate) fn write_arp_request(
    frame: &mut [u8],
    from: ([u8; 6], Ipv4Addr),
    target: Ipv4Addr,
) -> bool {
    let Some(frame) = frame.get_mut(..ARP_REQUEST_LEN) else {
        return false;
    };
    let mut eth = EthernetFrame::new_unchecked(&mut *frame);
    EthernetRepr {
        src_addr: EthernetAddress(from.0),
        dst_addr: EthernetAddress::BROADCAST,
        ethertype: EthernetProtocol::Arp,
    }
    .emit(&mut eth);
    let mut arp = ArpPacket::new_unchecked(eth.payload_mut());
    ArpRepr::EthernetIpv4 {
        operation: ArpOperation::Request,
        source_hardware_addr: EthernetAddress(from.0),
        source_protocol_addr: from.1,
        target_hardware_addr: EthernetAddress([0; 6]),
        target_protocol_addr: target,
    }
    .emit(&mut arp);
    true
}

/// Sends a copy of `frame` through `tx`. Never inlined: the cold senders (the network
/// stack's frames, LLDP, ACD, ARP requests) share one copy of the driver's transmit.
#[inline(never)]
pub(crate) fn send_copy<T: TxToken>(tx: T, frame: &[u8]) {
    tx.consume(frame.len(), |out| copy(out, frame));
}

/// Copies `from` into `to` as far as both go.
pub(crate) fn copy(to: &mut [u8], from: &[u8]) {
    let n = to.len().min(from.len());
    if let (Some(to), Some(from)) = (to.get_mut(..n), from.get(..n)) {
        to.copy_from_slice(from);
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use smoltcp::wire::{IpAddress, Ipv4Packet, UdpPacket};
    use std::vec::Vec;

    use crate::link::route::{Headers, Route};
    use crate::link::test_frames::{iface, ipv4_frame, ipv4_mut, ME, MY_MAC, PEER, PEER_MAC};
    use smoltcp::wire::IpProtocol;

    fn software() -> ChecksumCapabilities {
        ChecksumCapabilities::default()
    }

    /// A UDP datagram from the peer's `port` to `to`:2222 as the peer would send it.
    fn datagram(to: Ipv4Addr, port: u16, payload: &[u8]) -> Vec<u8> {
        let mut frame = std::vec![0u8; HEADERS_LEN + payload.len()];
        frame[HEADERS_LEN..].copy_from_slice(payload);
        let route = Route {
            from: (&PEER_MAC, PEER),
            to: (&MY_MAC, SocketAddrV4::new(to, IO_PORT)),
            ttl: 64,
            dscp: 0,
        };
        assert!(Headers::new(&route).write(&mut frame, payload.len(), &software()));
        // The peer's source port.
        frame[34..36].copy_from_slice(&port.to_be_bytes());
        let mut ip = Ipv4Packet::new_unchecked(&mut frame[14..]);
        let mut udp = UdpPacket::new_unchecked(ip.payload_mut());
        udp.fill_checksum(&IpAddress::Ipv4(PEER), &IpAddress::Ipv4(to));
        frame
    }

    #[test]
    fn an_o_t_datagram_for_this_adapter_is_found_with_its_sender() {
        let frame = datagram(ME, 2222, b"o->t data");
        let seen = inspect(&frame, ME, &software());
        assert_eq!(seen.sender, Some((PEER, PEER_MAC)));
        let (from, range) = seen.o_t.expect("an O->T datagram");
        assert_eq!(from, SocketAddrV4::new(PEER, 2222));
        assert_eq!(&frame[range], b"o->t data");
    }

    #[test]
    fn ethernet_padding_is_not_payload() {
        let mut frame = datagram(ME, 2222, b"x");
        frame.resize(60, 0);
        let (_, range) = inspect(&frame, ME, &software()).o_t.expect("O->T");
        assert_eq!(&frame[range], b"x");
    }

    #[test]
    fn everything_else_goes_to_the_stack() {
        let good = datagram(ME, 2222, b"data");
        // Not for this adapter: nothing learned either.
        assert_eq!(
            inspect(&good, Ipv4Addr::new(198, 18, 0, 3), &software()),
            Seen::default()
        );
        // Another UDP port: the sender is named (the link task learns it only if the frame is
        // taken in), the frame is the stack's.
        let other_port = {
            let mut f = good.clone();
            f[36..38].copy_from_slice(&44818u16.to_be_bytes());
            let mut ip = Ipv4Packet::new_unchecked(&mut f[14..]);
            let mut udp = UdpPacket::new_unchecked(ip.payload_mut());
            udp.fill_checksum(&IpAddress::Ipv4(PEER), &IpAddress::Ipv4(ME));
            f
        };
        let seen = inspect(&other_port, ME, &software());
        assert_eq!((seen.sender, seen.o_t), (Some((PEER, PEER_MAC)), None));
        // A bad UDP checksum, unless the driver checked it.
        let mut bad_udp = good.clone();
        *bad_udp.last_mut().unwrap() ^= 0xFF;
        assert_eq!(inspect(&bad_udp, ME, &software()).o_t, None);
        let mut offloaded = software();
        offloaded.udp = smoltcp::phy::Checksum::None;
        assert!(inspect(&bad_udp, ME, &offloaded).o_t.is_some());
        // A bad IPv4 header checksum: not even the sender is believed.
        let mut bad_ip = good.clone();
        bad_ip[14 + 10] ^= 0xFF;
        assert_eq!(inspect(&bad_ip, ME, &software()), Seen::default());
        // A fragment (more fragments set, header checksum refreshed).
        let mut fragment = good.clone();
        {
            let mut ip = Ipv4Packet::new_unchecked(&mut fragment[14..]);
            ip.set_more_frags(true);
            ip.fill_checksum();
        }
        assert_eq!(inspect(&fragment, ME, &software()).o_t, None);
        // An IPv4 ethertype on a header of another version (RFC 1122 3.2.1.1): nothing.
        let mut version_6 = good.clone();
        version_6[14] = 0x65;
        Ipv4Packet::new_unchecked(&mut version_6[14..]).fill_checksum();
        assert_eq!(inspect(&version_6, ME, &software()), Seen::default());
        // From a broadcast source MAC: no neighbour entry, and not Class 1 either.
        let mut group_mac = good.clone();
        group_mac[6] |= 1;
        assert_eq!(inspect(&group_mac, ME, &software()), Seen::default());
    }

    #[test]
    fn every_truncation_is_handled() {
        let frame = datagram(ME, 2222, b"0123456789");
        for len in 0..frame.len() {
            assert_eq!(
                inspect(&frame[..len], ME, &software()).o_t,
                None,
                "{len} bytes"
            );
        }
    }

    #[test]
    fn arp_about_this_adapter_names_its_sender() {
        let mut frame = [0u8; ARP_REQUEST_LEN];
        assert!(write_arp_request(&mut frame, (PEER_MAC, PEER), ME));
        let seen = inspect(&frame, ME, &software());
        assert_eq!(
            seen,
            Seen {
                sender: Some((PEER, PEER_MAC)),
                o_t: None
            }
        );
        // About another host: nothing.
        assert_eq!(
            inspect(&frame, Ipv4Addr::new(198, 18, 0, 9), &software()),
            Seen::default()
        );
        // From another MAC than the one it names (found by the `link_frame` fuzz target):
        // nothing either.
        let mut forged = frame;
        forged[6 + 4] ^= 0x20;
        assert_eq!(inspect(&forged, ME, &software()), Seen::default());
        assert!(!write_arp_request(
            &mut frame[..ARP_REQUEST_LEN - 1],
            (PEER_MAC, PEER),
            ME
        ));
    }

    #[test]
    fn tcp_fragments_to_us_and_echo_requests_to_others_are_kept_from_the_stack() {
        // The frames go from ME to PEER: PEER is "us" here.
        let tcp = ipv4_frame(IpProtocol::Tcp, 20, 0, &software());
        assert!(
            !kept_from_stack(&tcp, &iface(PEER)),
            "a whole segment passes on"
        );
        for (more, offset) in [(true, 0), (false, 8), (true, 16)] {
            let mut fragment = tcp.clone();
            let mut ip = ipv4_mut(&mut fragment);
            ip.set_more_frags(more);
            ip.set_frag_offset(offset);
            assert!(
                kept_from_stack(&fragment, &iface(PEER)),
                "fragment {more} {offset}"
            );
            assert!(
                !kept_from_stack(&fragment, &iface(ME)),
                "not to us: not ours to judge"
            );
        }
        let mut echo = ipv4_frame(IpProtocol::Icmp, 8, 0, &software());
        echo[HEADERS_LEN - UDP_HEADER_LEN] = ECHO_REQUEST;
        assert!(
            !kept_from_stack(&echo, &iface(PEER)),
            "an echo request to us is answered"
        );
        for to in [Ipv4Addr::BROADCAST, Ipv4Addr::new(198, 18, 0, 255)] {
            ipv4_mut(&mut echo).set_dst_addr(to);
            assert!(kept_from_stack(&echo, &iface(PEER)), "to {to}");
        }
        echo[HEADERS_LEN - UDP_HEADER_LEN] = 0;
        assert!(
            !kept_from_stack(&echo, &iface(PEER)),
            "an echo reply is the stack's to drop"
        );
        // A "land" segment, from us to us, one from a loopback address, and ones from the
        // subnet's broadcast and network addresses.
        let subnet_wide = [Ipv4Addr::new(198, 18, 0, 255), Ipv4Addr::new(198, 18, 0, 0)];
        for from in [PEER, Ipv4Addr::new(127, 0, 0, 1)]
            .into_iter()
            .chain(subnet_wide)
        {
            let mut land = tcp.clone();
            ipv4_mut(&mut land).set_src_addr(from);
            assert!(kept_from_stack(&land, &iface(PEER)), "from {from}");
        }
        let udp = ipv4_frame(IpProtocol::Udp, 8, 0, &software());
        assert!(!kept_from_stack(&udp, &iface(ME)) && !kept_from_stack(&udp, &iface(PEER)));
        assert!(!kept_from_stack(&udp[..20], &iface(PEER)), "short");
    }
}
