//! Frames as smoltcp writes them, for the link module's tests: the addresses, the Ethernet
//! and IPv4 headers from its codecs, and the TCP segment the tests send. (Test code only:
//! `link` declares it `#[cfg(test)]`.)

extern crate std;

use smoltcp::phy::ChecksumCapabilities;
use smoltcp::wire::{
    EthernetAddress, EthernetFrame, EthernetProtocol, EthernetRepr, IpProtocol, Ipv4Address,
    Ipv4Packet, Ipv4Repr, TcpControl, TcpRepr, TcpSeqNumber, ETHERNET_HEADER_LEN, IPV4_HEADER_LEN,
};
use std::vec::Vec;

/// The adapter's address.
pub const ME: Ipv4Address = Ipv4Address::new(198, 18, 0, 2);
/// The adapter's MAC address.
pub const MY_MAC: [u8; 6] = [2, 0, 0, 0, 0, 2];
/// The peer's address.
pub const PEER: Ipv4Address = Ipv4Address::new(198, 18, 0, 1);
/// The peer's MAC address.
pub const PEER_MAC: [u8; 6] = [2, 0, 0, 0, 0, 1];

/// An interface at `ip` on the tests' /24.
pub const fn iface(ip: Ipv4Address) -> enip_stack::NetworkConfig {
    enip_stack::NetworkConfig::new_static(ip, Ipv4Address::new(255, 255, 255, 0), MY_MAC)
}

/// A TCP segment from `src_port` to port 50000 carrying `payload` (PSH, sequence 7,
/// acknowledging 9).
pub fn tcp_segment(src_port: u16, payload: &[u8]) -> TcpRepr<'_> {
    TcpRepr {
        src_port,
        dst_port: 50000,
        control: TcpControl::Psh,
        seq_number: TcpSeqNumber(7),
        ack_number: Some(TcpSeqNumber(9)),
        window_len: 4096,
        window_scale: None,
        max_seg_size: None,
        sack_permitted: false,
        sack_ranges: [None; 3],
        timestamp: None,
        payload,
    }
}

/// A frame from [`ME`] ([`MY_MAC`]) to [`PEER`] ([`PEER_MAC`]) with `len` bytes of
/// `protocol` behind its IPv4 header (zero, for the caller to write) and `pad` bytes of
/// Ethernet padding; the headers as smoltcp emits them with `sums`.
pub fn ipv4_frame(
    protocol: IpProtocol,
    len: usize,
    pad: usize,
    sums: &ChecksumCapabilities,
) -> Vec<u8> {
    let mut f = std::vec![0u8; ETHERNET_HEADER_LEN + IPV4_HEADER_LEN + len + pad];
    let mut eth = EthernetFrame::new_unchecked(&mut f[..]);
    EthernetRepr {
        src_addr: EthernetAddress(MY_MAC),
        dst_addr: EthernetAddress(PEER_MAC),
        ethertype: EthernetProtocol::Ipv4,
    }
    .emit(&mut eth);
    Ipv4Repr {
        src_addr: ME,
        dst_addr: PEER,
        next_header: protocol,
        payload_len: len,
        hop_limit: 64,
    }
    .emit(&mut Ipv4Packet::new_unchecked(eth.payload_mut()), sums);
    f
}

/// The IPv4 packet of a frame from [`ipv4_frame`], to write its payload or change a field.
pub fn ipv4_mut(frame: &mut [u8]) -> Ipv4Packet<&mut [u8]> {
    Ipv4Packet::new_unchecked(&mut frame[ETHERNET_HEADER_LEN..])
}
