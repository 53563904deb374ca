//! TCP segments in Ethernet frames, for the link task: a received one to us located (its
//! port says whose it is) and read into the stack's [`Segment`] (its checksum checked where
//! the driver leaves it to software), an outgoing [`Outgoing`] written behind its Ethernet
//! and IPv4 headers.

use core::net::{Ipv4Addr, SocketAddrV4};
use core::ops::Range;

use enip_stack::tcp::{Flags, Outgoing, Segment};
use enip_stack::NetworkConfig;
use smoltcp::phy::ChecksumCapabilities;
use smoltcp::wire::{ETHERNET_HEADER_LEN, IPV4_HEADER_LEN};

use super::checksum::Sum;
use super::frame::{tcp_source, IPV4, TCP};
use super::route::UNICAST_TTL;

/// Bytes of a TCP header without options.
const TCP_HEADER_LEN: usize = 20;
/// Bytes of the maximum segment size option (kind 2, length 4).
const MSS_OPTION_LEN: usize = 4;
/// The flags' bits in the TCP header's 14th byte.
const FIN: u8 = 0x01;
const SYN: u8 = 0x02;
const RST: u8 = 0x04;
const PSH: u8 = 0x08;
const ACK: u8 = 0x10;
/// Don't fragment, in the IPv4 header's flags.
const DONT_FRAGMENT: u8 = 0x40;

/// Where a TCP segment to us came from and lies: its source, its place in the frame, and
/// the port it is for.
pub(crate) type Located = (Ipv4Addr, Range<usize>, u16);

/// The TCP segment in the IPv4 frame `frame` to the interface `me` (whose IPv4 header
/// [`super::frame::inspect`] found good), if it is whole. Not part of `inspect`, which every
/// Class 1 frame passes: a TCP frame pays for reading its IPv4 header twice.
pub(crate) fn locate(frame: &[u8], me: &NetworkConfig) -> Option<Located> {
    let packet = frame.get(ETHERNET_HEADER_LEN..)?;
    let header = packet.first_chunk::<IPV4_HEADER_LEN>()?;
    let &[ihl, _, l0, l1, _, _, f0, f1, _, protocol, _, _, s0, s1, s2, s3, d0, d1, d2, d3] = header;
    let header_len = usize::from(ihl & 0x0F).wrapping_mul(4);
    let total_len = usize::from(u16::from_be_bytes([l0, l1]));
    // More fragments (0x2000) or a fragment offset: not the whole segment.
    let unfragmented = u16::from_be_bytes([f0, f1]) & 0x3FFF == 0;
    if frame.get(12..ETHERNET_HEADER_LEN) != Some(&IPV4[..])
        || ihl >> 4 != 4
        || protocol != TCP
        || !unfragmented
        || Ipv4Addr::new(d0, d1, d2, d3) != me.ip
        || !tcp_source(Ipv4Addr::new(s0, s1, s2, s3), me)
        || header_len < IPV4_HEADER_LEN
        || total_len > packet.len()
    {
        return None;
    }
    let start = ETHERNET_HEADER_LEN.wrapping_add(header_len);
    let end = ETHERNET_HEADER_LEN.wrapping_add(total_len);
    let &[_, _, p0, p1, ..] = frame.get(start..end)? else {
        return None;
    };
    let port = u16::from_be_bytes([p0, p1]);
    Some((Ipv4Addr::new(s0, s1, s2, s3), start..end, port))
}

/// Reads the TCP segment `segment` (an IPv4 payload, whole) from `src` to `me`; `None` if
/// it is malformed or its checksum fails (checked if `verify`).
#[inline(always)] // Once on the request path, once to refuse a closed port.
pub(crate) fn parse(
    segment: &[u8],
    src: Ipv4Addr,
    me: Ipv4Addr,
    verify: bool,
) -> Option<Segment<'_>> {
    let header = segment.first_chunk::<TCP_HEADER_LEN>()?;
    let &[p0, p1, _, _, s0, s1, s2, s3, a0, a1, a2, a3, offset, bits, w0, w1, ..] = header;
    let header_len = usize::from(offset >> 4).wrapping_mul(4);
    let options = segment.get(TCP_HEADER_LEN..header_len)?;
    let payload = segment.get(header_len..)?;
    if verify {
        let len = u16::try_from(segment.len()).ok()?;
        let [l0, l1] = len.to_be_bytes();
        let pseudo = Sum::default()
            .add_word(src.octets())
            .add_word(me.octets())
            .add_word([0, TCP, l0, l1]);
        if !pseudo.add(segment).is_valid() {
            return None;
        }
    }
    let flags = Flags {
        syn: bits & SYN != 0,
        ack: bits & ACK != 0,
        fin: bits & FIN != 0,
        rst: bits & RST != 0,
        psh: bits & PSH != 0,
    };
    Some(Segment {
        peer: SocketAddrV4::new(src, u16::from_be_bytes([p0, p1])),
        seq: u32::from_be_bytes([s0, s1, s2, s3]),
        ack: u32::from_be_bytes([a0, a1, a2, a3]),
        flags,
        window: u16::from_be_bytes([w0, w1]),
        mss: if flags.syn { mss(options) } else { None },
        payload,
    })
}

/// The maximum segment size option among `options` (RFC 9293 3.2), if any.
fn mss(mut options: &[u8]) -> Option<u16> {
    // Each option takes at least a byte: bounded by their length.
    for _ in 0..options.len() {
        match *options {
            [] | [0, ..] => return None,
            [1, ref rest @ ..] => options = rest,
            [2, 4, hi, lo, ..] => return Some(u16::from_be_bytes([hi, lo])),
            [_, len, ..] if len >= 2 => options = options.get(usize::from(len)..)?,
            _ => return None,
        }
    }
    None
}

/// Bytes of the frame that carries `out` with `payload_len` bytes of data.
pub(crate) fn frame_len(out: &Outgoing, payload_len: usize) -> usize {
    const HEADERS: usize = ETHERNET_HEADER_LEN + IPV4_HEADER_LEN + TCP_HEADER_LEN;
    let mss = if out.mss.is_some() { MSS_OPTION_LEN } else { 0 };
    HEADERS.saturating_add(mss).saturating_add(payload_len)
}

/// Who a segment goes from and to on the link: our MAC and address, the next hop's MAC.
pub(crate) struct Hop {
    /// Our MAC address and IPv4 address.
    pub from: ([u8; 6], Ipv4Addr),
    /// The next hop's MAC address towards the peer.
    pub to: [u8; 6],
    /// The DSCP of explicit messaging (the QoS object's).
    pub dscp: u8,
    /// Our TCP port the segment goes from.
    pub port: u16,
}

/// Writes the frame of `out` with `payload` over `hop` into `frame` ([`frame_len`] bytes;
/// a shorter one is left alone), with the checksums `sums` says software fills.
pub(crate) fn write(
    frame: &mut [u8],
    hop: &Hop,
    out: &Outgoing,
    payload: &[u8],
    sums: &ChecksumCapabilities,
) {
    let len = frame_len(out, payload.len());
    let Some(frame) = frame.get_mut(..len) else {
        return;
    };
    let Some((eth, packet)) = frame.split_first_chunk_mut::<ETHERNET_HEADER_LEN>() else {
        return;
    };
    let (mac, me) = hop.from;
    let [t0, t1] = IPV4;
    let [h0, h1, h2, h3, h4, h5] = hop.to;
    let [m0, m1, m2, m3, m4, m5] = mac;
    *eth = [h0, h1, h2, h3, h4, h5, m0, m1, m2, m3, m4, m5, t0, t1];
    let Some((ip, segment)) = packet.split_first_chunk_mut::<IPV4_HEADER_LEN>() else {
        return;
    };
    let total = u16::try_from(IPV4_HEADER_LEN.saturating_add(segment.len())).unwrap_or(0);
    let [n0, n1] = total.to_be_bytes();
    let [s0, s1, s2, s3] = me.octets();
    let [d0, d1, d2, d3] = out.peer.ip().octets();
    let tos = hop.dscp << 2;
    // Identification 0, as the T->O datagrams' and the network stack's: a segment is never
    // fragmented (RFC 6864 4.1), and a counter would let a scanner use the board as an idle
    // scan's zombie.
    *ip = [
        0x45,
        tos,
        n0,
        n1,
        0,
        0,
        DONT_FRAGMENT,
        0,
        UNICAST_TTL,
        TCP,
        0,
        0,
        s0,
        s1,
        s2,
        s3,
        d0,
        d1,
        d2,
        d3,
    ];
    if sums.ipv4.tx() {
        let sum = Sum::default().add(ip).checksum();
        if let Some(field) = ip.get_mut(10..12) {
            field.copy_from_slice(&sum);
        }
    }
    write_tcp(segment, hop.port, out, payload);
    if sums.tcp.tx() {
        let len = u16::try_from(segment.len()).unwrap_or(0);
        let [l0, l1] = len.to_be_bytes();
        let sum = Sum::default()
            .add_word(me.octets())
            .add_word(out.peer.ip().octets())
            .add_word([0, TCP, l0, l1])
            .add(segment);
        if let Some(field) = segment.get_mut(16..18) {
            field.copy_from_slice(&sum.checksum());
        }
    }
}

/// The TCP header of `out` from our `port` (checksum zero) and `payload` into `segment`.
fn write_tcp(segment: &mut [u8], port: u16, out: &Outgoing, payload: &[u8]) {
    let Some((header, rest)) = segment.split_first_chunk_mut::<TCP_HEADER_LEN>() else {
        return;
    };
    let [p0, p1] = port.to_be_bytes();
    let [d0, d1] = out.peer.port().to_be_bytes();
    let [s0, s1, s2, s3] = out.seq.to_be_bytes();
    let [a0, a1, a2, a3] = if out.flags.ack { out.ack } else { 0 }.to_be_bytes();
    let [w0, w1] = out.window.to_be_bytes();
    let words = if out.mss.is_some() { 6u8 } else { 5 };
    let f = out.flags;
    let bit = |on: bool, b: u8| if on { b } else { 0 };
    let bits =
        bit(f.fin, FIN) | bit(f.syn, SYN) | bit(f.rst, RST) | bit(f.psh, PSH) | bit(f.ack, ACK);
    *header = [
        p0,
        p1,
        d0,
        d1,
        s0,
        s1,
        s2,
        s3,
        a0,
        a1,
        a2,
        a3,
        words << 4,
        bits,
        w0,
        w1,
        0,
        0,
        0,
        0,
    ];
    let data = match out.mss {
        Some(mss) => {
            let [m0, m1] = mss.to_be_bytes();
            let Some((option, data)) = rest.split_first_chunk_mut::<MSS_OPTION_LEN>() else {
                return;
            };
            *option = [2, 4, m0, m1];
            data
        }
        None => rest,
    };
    if let Some(data) = data.get_mut(..payload.len()) {
        data.copy_from_slice(payload);
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use enip_stack::config::ENCAP_PORT;
    use smoltcp::wire::{
        EthernetFrame, IpAddress, IpProtocol, Ipv4Packet, TcpControl, TcpPacket, TcpRepr,
        TcpSeqNumber,
    };
    use std::vec;

    use crate::link::test_frames::{iface, ipv4_mut};

    const ME: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 2);
    const PEER: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 1);

    fn software() -> ChecksumCapabilities {
        ChecksumCapabilities::default()
    }

    fn written(out: &Outgoing, payload: &[u8]) -> std::vec::Vec<u8> {
        written_from(ENCAP_PORT, out, payload)
    }

    fn written_from(port: u16, out: &Outgoing, payload: &[u8]) -> std::vec::Vec<u8> {
        let mut frame = vec![0u8; frame_len(out, payload.len())];
        let hop = Hop {
            from: ([2, 0, 0, 0, 0, 2], ME),
            to: [2, 0, 0, 0, 0, 1],
            dscp: 27,
            port,
        };
        write(&mut frame, &hop, out, payload, &software());
        frame
    }

    #[test]
    fn a_written_segment_is_what_smoltcp_reads_with_good_checksums() {
        let out = Outgoing {
            peer: SocketAddrV4::new(PEER, 50_000),
            seq: 1000,
            ack: 77,
            flags: Flags {
                syn: true,
                ack: true,
                ..Flags::default()
            },
            window: 1048,
            mss: Some(1460),
        };
        let frame = written(&out, &[]);
        let eth = EthernetFrame::new_checked(&frame[..]).unwrap();
        let ip = Ipv4Packet::new_checked(eth.payload()).unwrap();
        assert!(ip.verify_checksum());
        assert_eq!((ip.dscp(), ip.hop_limit(), ip.dont_frag()), (27, 64, true));
        assert_eq!(ip.ident(), 0, "no counter for an idle scan to read");
        let tcp = TcpPacket::new_checked(ip.payload()).unwrap();
        let repr = TcpRepr::parse(
            &tcp,
            &IpAddress::Ipv4(ME),
            &IpAddress::Ipv4(PEER),
            &software(),
        )
        .expect("smoltcp takes it, checksum and all");
        assert_eq!(repr.control, TcpControl::Syn);
        assert_eq!(repr.seq_number, TcpSeqNumber(1000));
        assert_eq!(repr.ack_number, Some(TcpSeqNumber(77)));
        assert_eq!((repr.window_len, repr.max_seg_size), (1048, Some(1460)));
        assert_eq!((repr.src_port, repr.dst_port), (ENCAP_PORT, 50_000));
        assert_eq!(ip.next_header(), IpProtocol::Tcp);
    }

    #[test]
    fn a_segment_reads_back_and_a_bad_checksum_is_refused() {
        let out = Outgoing {
            peer: SocketAddrV4::new(PEER, 50_000),
            seq: u32::MAX,
            ack: 9,
            flags: Flags {
                ack: true,
                psh: true,
                fin: true,
                ..Flags::default()
            },
            window: 512,
            mss: None,
        };
        let mut frame = written(&out, b"hello");
        // Read back as if the peer had sent it to us: swap the addresses and ports.
        let at = ETHERNET_HEADER_LEN + IPV4_HEADER_LEN;
        let segment = &mut frame[at..];
        let (src, dst) = (segment[0..2].to_vec(), segment[2..4].to_vec());
        segment[0..2].copy_from_slice(&dst);
        segment[2..4].copy_from_slice(&src);
        let seg = parse(segment, PEER, ME, true).expect("swapping words keeps the checksum");
        assert_eq!(
            (seg.peer.port(), seg.seq, seg.ack, seg.window),
            (50_000, u32::MAX, 9, 512)
        );
        assert!(seg.flags.ack && seg.flags.psh && seg.flags.fin && !seg.flags.syn);
        assert_eq!(seg.payload, b"hello");
        segment[24] ^= 1;
        assert!(parse(segment, PEER, ME, true).is_none());
        assert!(
            parse(segment, PEER, ME, false).is_some(),
            "unchecked when offloaded"
        );
    }

    #[test]
    fn a_segment_is_located_with_the_port_it_is_for_and_goes_from_ours() {
        let rst = Outgoing {
            peer: SocketAddrV4::new(PEER, 50_000),
            seq: 0,
            ack: 11,
            flags: Flags {
                rst: true,
                ack: true,
                ..Flags::default()
            },
            window: 0,
            mss: None,
        };
        let frame = written_from(80, &rst, &[]);
        let at = ETHERNET_HEADER_LEN + IPV4_HEADER_LEN;
        // As the peer would find it: from us, for its port 50 000, from our port 80.
        assert_eq!(
            locate(&frame, &iface(PEER)),
            Some((ME, at..frame.len(), 50_000))
        );
        assert_eq!(frame[at..at + 2], 80u16.to_be_bytes());
        assert_eq!(locate(&frame, &iface(ME)), None, "not to us");
        let mut fragment = frame.clone();
        fragment[ETHERNET_HEADER_LEN + 6] |= 0x20;
        assert_eq!(locate(&fragment, &iface(PEER)), None, "not whole");
        // Sources (the segments go to PEER): a land segment from PEER itself, the subnet's
        // broadcast and network addresses (RFC 1122 4.2.3.10), none of which a /31 link
        // (RFC 3021) has; a routed client judged by its own subnet's mask, not ours; and
        // addresses that are no host's anywhere.
        let mut point_to_point = iface(PEER);
        point_to_point.netmask = Ipv4Addr::new(255, 255, 255, 254);
        for (from, on_24, on_31) in [
            (PEER, false, false),
            (Ipv4Addr::new(198, 18, 0, 255), false, true),
            (Ipv4Addr::new(198, 18, 0, 0), false, true),
            (Ipv4Addr::new(10, 1, 4, 255), true, true),
            (Ipv4Addr::new(10, 1, 5, 0), true, true),
            (Ipv4Addr::new(224, 0, 0, 1), false, false),
            (Ipv4Addr::UNSPECIFIED, false, false),
        ] {
            let mut sent = frame.clone();
            ipv4_mut(&mut sent).set_src_addr(from);
            assert_eq!(locate(&sent, &iface(PEER)).is_some(), on_24, "/24 {from}");
            assert_eq!(
                locate(&sent, &point_to_point).is_some(),
                on_31,
                "/31 {from}"
            );
        }
    }

    #[test]
    fn options_are_walked_to_the_segment_size() {
        assert_eq!(mss(&[1, 1, 2, 4, 0x05, 0xB4]), Some(1460));
        assert_eq!(mss(&[3, 3, 7, 2, 4, 0x02, 0x18]), Some(536));
        assert_eq!(mss(&[0, 2, 4, 1, 1]), None);
        assert_eq!(
            mss(&[8, 1, 2, 4, 1, 1]),
            None,
            "a length below 2 ends the walk"
        );
        assert_eq!(mss(&[8, 40]), None);
        assert_eq!(mss(&[]), None);
    }
}
