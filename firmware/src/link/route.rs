//! Where a T->O datagram goes and the headers in front of it. The Ethernet, IPv4 and UDP
//! headers of one route are written once ([`Headers`]), with what stays of both checksums
//! summed; the link task keeps those of the route it used last ([`LastRoute`]), so the next
//! datagram to the same destination, with the same DSCP and time to live, from the same
//! interface and while the neighbour table has not changed, copies them and adds its
//! lengths and payload: no route, next-hop lookup or header built per datagram.

use core::net::{Ipv4Addr, SocketAddrV4};

use enip_stack::config::IO_PORT;
use enip_stack::NetworkConfig;
use smoltcp::phy::ChecksumCapabilities;
use smoltcp::wire::{ETHERNET_HEADER_LEN, IPV4_HEADER_LEN, UDP_HEADER_LEN};

use super::checksum::Sum;
use super::frame::{copy, multicast_mac, HEADERS_LEN, IPV4, UDP};
use super::neighbors::{next_hop, Neighbors};

/// Hop limit of point-to-point T->O datagrams (smoltcp's default for every other packet).
pub(crate) const UNICAST_TTL: u8 = 64;

/// The addresses of one T->O datagram (the MAC addresses borrowed: no byte copies to make
/// one).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Route<'a> {
    /// This adapter's MAC and IPv4 addresses.
    pub from: (&'a [u8; 6], Ipv4Addr),
    /// The next hop's MAC address and the datagram's destination.
    pub to: (&'a [u8; 6], SocketAddrV4),
    /// IPv4 time to live.
    pub ttl: u8,
    /// DSCP of the IPv4 header (the connection's, from the QoS object).
    pub dscp: u8,
}

/// The headers of one route's T->O datagrams: written with the lengths and checksums zero,
/// and the sums of the words that stay (IPv4: all but the total length; UDP: the
/// pseudo-header's addresses and protocol, and the ports). The IPv4 header is smoltcp's
/// (identification 0, don't fragment, no options).
#[derive(Debug, Clone)]
pub(crate) struct Headers {
    bytes: [u8; HEADERS_LEN],
    ip_sum: Sum,
    udp_sum: Sum,
}

impl Headers {
    /// The headers of datagrams on `route`.
    pub(crate) fn new(route: &Route<'_>) -> Headers {
        let (&[d0, d1, d2, d3, d4, d5], to) = route.to;
        let (&[s0, s1, s2, s3, s4, s5], src) = route.from;
        let dst = *to.ip();
        let [a0, a1, a2, a3] = src.octets();
        let [b0, b1, b2, b3] = dst.octets();
        let [p0, p1] = IO_PORT.to_be_bytes();
        let [q0, q1] = to.port().to_be_bytes();
        let [t0, t1] = IPV4;
        let (tos, ttl) = ((route.dscp & 0x3F) << 2, route.ttl);
        // The addresses count in both sums.
        let addresses = Sum::default().add_word(src.octets()).add_word(dst.octets());
        Headers {
            // Ethernet (14 bytes), IPv4 (20), UDP (8).
            bytes: [
                d0, d1, d2, d3, d4, d5, s0, s1, s2, s3, s4, s5, t0, t1, 0x45, tos, 0, 0, 0, 0,
                0x40, 0, ttl, UDP, 0, 0, a0, a1, a2, a3, b0, b1, b2, b3, p0, p1, q0, q1, 0, 0, 0,
                0,
            ],
            ip_sum: addresses
                .add_word([0x45, tos, 0, 0])
                .add_word([0, 0, 0x40, 0])
                .add_word([ttl, UDP, 0, 0]),
            udp_sum: addresses
                .add_word([0, UDP, 0, 0])
                .add_word([p0, p1, q0, q1]),
        }
    }

    /// Writes these headers in front of a T->O datagram of `payload_len` bytes into `frame`,
    /// whose payload (from [`HEADERS_LEN`]) is already written; `fill` says which checksums
    /// software computes. Returns `false`, writing nothing, if `frame` is too short. (Inline:
    /// its one caller writes the payload in front of it.)
    #[inline]
    pub(crate) fn write(
        &self,
        frame: &mut [u8],
        payload_len: usize,
        fill: &ChecksumCapabilities,
    ) -> bool {
        let udp_len = payload_len.saturating_add(UDP_HEADER_LEN);
        let ip_len = udp_len.saturating_add(IPV4_HEADER_LEN);
        let frame_len = ip_len.saturating_add(ETHERNET_HEADER_LEN);
        let (Ok(udp_len), Ok(ip_len)) = (u16::try_from(udp_len), u16::try_from(ip_len)) else {
            return false;
        };
        let Some((headers, payload)) = frame
            .get_mut(..frame_len)
            .and_then(|f| f.split_first_chunk_mut::<HEADERS_LEN>())
        else {
            return false;
        };
        copy_headers(headers, &self.bytes);
        let ip_len = ip_len.to_be_bytes();
        let [u0, u1] = udp_len.to_be_bytes();
        put(headers, 16, ip_len);
        put(headers, 38, [u0, u1]);
        if fill.ipv4.tx() {
            let [i0, i1] = ip_len;
            put(headers, 24, self.ip_sum.add_word([0, 0, i0, i1]).checksum());
        }
        if fill.udp.tx() {
            // The length counts twice: in the pseudo-header and in the UDP header.
            let sum = self.udp_sum.add_word([u0, u1, u0, u1]).add(payload);
            let sum = sum.checksum();
            // A computed zero is sent as all ones (RFC 768): zero means none was computed.
            let sum = if sum == [0, 0] { [0xFF, 0xFF] } else { sum };
            put(headers, 40, sum);
        }
        true
    }
}

/// Copies `from` into `to` eight bytes at a time, each two word moves: the frame's buffer
/// may start at any even address, and a copy of the whole (of more than eight bytes, or a
/// loop) becomes a call of the library's `memcpy`, twice the instructions.
#[inline(always)]
fn copy_headers(to: &mut [u8; HEADERS_LEN], from: &[u8; HEADERS_LEN]) {
    let rest = Some((to.as_mut_slice(), from.as_slice()));
    let rest = rest.and_then(copy_eight).and_then(copy_eight);
    let rest = rest.and_then(copy_eight).and_then(copy_eight);
    let rest = rest.and_then(copy_eight);
    if let Some((to, from)) = rest {
        copy(to, from);
    }
}

/// Copies the first eight bytes of `from` into `to`; the rest of both.
#[inline(always)]
fn copy_eight<'a, 'b>((to, from): (&'a mut [u8], &'b [u8])) -> Option<(&'a mut [u8], &'b [u8])> {
    let (t, to) = to.split_first_chunk_mut::<8>()?;
    let (f, from) = from.split_first_chunk::<8>()?;
    *t = *f;
    Some((to, from))
}

/// Writes `field` at `at` of `headers` (a constant place: the compiler checks it once).
#[inline(always)]
fn put(headers: &mut [u8; HEADERS_LEN], at: usize, field: [u8; 2]) {
    if let Some(to) = headers.get_mut(at..at.wrapping_add(2)) {
        to.copy_from_slice(&field);
    }
}

/// What the kept headers were written for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Key {
    to: SocketAddrV4,
    dscp: u8,
    ttl: u8,
    /// The interface's address, mask and gateway (they decide the next hop).
    me: (Ipv4Addr, Ipv4Addr, Ipv4Addr),
    /// [`Neighbors::changes`] when they were written.
    neighbors: u32,
}

/// The headers of the route the link task used last.
#[derive(Debug)]
pub(crate) struct LastRoute {
    key: Option<Key>,
    headers: Headers,
}

impl Default for LastRoute {
    fn default() -> Self {
        LastRoute {
            key: None,
            headers: Headers {
                bytes: [0; HEADERS_LEN],
                ip_sum: Sum::default(),
                udp_sum: Sum::default(),
            },
        }
    }
}

impl LastRoute {
    /// The headers of a datagram to `to` with `dscp` and `ttl` from the interface `me`
    /// (MAC `mac`): the kept ones if they were written for the same, else new ones, the next
    /// hop's MAC address from `neighbors` (or the multicast group's). `None` if no frame
    /// came from the next hop yet.
    pub(crate) fn headers(
        &mut self,
        (mac, me): (&[u8; 6], &NetworkConfig),
        (to, dscp, ttl): (SocketAddrV4, u8, u8),
        neighbors: &mut Neighbors,
    ) -> Option<&Headers> {
        let key = Key {
            to,
            dscp,
            ttl,
            me: (me.ip, me.netmask, me.gateway),
            neighbors: neighbors.changes(),
        };
        if self.key != Some(key) {
            self.key = None;
            let ip = *to.ip();
            let next = if ip.is_multicast() {
                multicast_mac(ip)
            } else {
                let hop = next_hop(ip, me.ip, me.netmask, me.gateway);
                neighbors.get(ip).or_else(|| neighbors.get(hop))?
            };
            let route = Route {
                from: (mac, me.ip),
                to: (&next, to),
                ttl,
                dscp,
            };
            self.headers = Headers::new(&route);
            self.key = Some(key);
        }
        Some(&self.headers)
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::link::test_frames::{ipv4_frame, ipv4_mut, ME, MY_MAC, PEER, PEER_MAC};
    use smoltcp::wire::{EthernetFrame, IpAddress, IpProtocol, Ipv4Packet, UdpPacket, UdpRepr};

    fn software() -> ChecksumCapabilities {
        ChecksumCapabilities::default()
    }

    #[test]
    fn t_o_headers_are_the_ones_smoltcp_writes() {
        let to = SocketAddrV4::new(PEER, 40_000);
        let route = Route {
            from: (&MY_MAC, ME),
            to: (&PEER_MAC, to),
            ttl: 64,
            dscp: 43,
        };
        let headers = Headers::new(&route);
        // Every length, odd ones among them, from one set of headers.
        for payload in [&b""[..], b"0", b"0123456789a", &[0xFF; 64], &[0x5A; 507]] {
            let mut ours = std::vec![0u8; HEADERS_LEN + payload.len()];
            ours[HEADERS_LEN..].copy_from_slice(payload);
            assert!(headers.write(&mut ours, payload.len(), &software()));
            let mut theirs = ipv4_frame(IpProtocol::Udp, 8 + payload.len(), 0, &software());
            theirs[HEADERS_LEN..].copy_from_slice(payload);
            let mut ip = ipv4_mut(&mut theirs);
            ip.set_dscp(43);
            ip.fill_checksum();
            let (src, dst) = (IpAddress::Ipv4(ME), IpAddress::Ipv4(PEER));
            UdpRepr {
                src_port: IO_PORT,
                dst_port: 40_000,
            }
            .emit(
                &mut UdpPacket::new_unchecked(ip.payload_mut()),
                &src,
                &dst,
                payload.len(),
                |_| {},
                &software(),
            );
            assert_eq!(ours, theirs, "{} bytes", payload.len());
        }
    }

    #[test]
    fn t_o_headers_parse_back_with_good_checksums() {
        let group = Ipv4Addr::new(239, 192, 1, 0);
        let payload = b"t->o payload";
        let mut frame = std::vec![0u8; HEADERS_LEN + payload.len() + 4];
        frame[HEADERS_LEN..HEADERS_LEN + payload.len()].copy_from_slice(payload);
        let route = Route {
            from: (&MY_MAC, ME),
            to: (&multicast_mac(group), SocketAddrV4::new(group, 2222)),
            ttl: 7,
            dscp: 47,
        };
        let headers = Headers::new(&route);
        assert!(headers.write(&mut frame, payload.len(), &software()));
        let eth = EthernetFrame::new_checked(&frame[..]).unwrap();
        assert_eq!(eth.dst_addr().0, [0x01, 0x00, 0x5E, 0x40, 1, 0]);
        assert_eq!(eth.src_addr().0, MY_MAC);
        let ip = Ipv4Packet::new_checked(eth.payload()).unwrap();
        assert!(ip.verify_checksum());
        assert_eq!(
            (ip.src_addr(), ip.dst_addr(), ip.hop_limit(), ip.dscp()),
            (ME, group, 7, 47)
        );
        let udp = UdpPacket::new_checked(ip.payload()).unwrap();
        assert!(udp.verify_checksum(&IpAddress::Ipv4(ME), &IpAddress::Ipv4(group)));
        assert_eq!((udp.src_port(), udp.dst_port()), (2222, 2222));
        assert_eq!(udp.payload(), payload);
        // Too short a frame is refused.
        assert!(!headers.write(&mut frame[..HEADERS_LEN], 1, &software()));
        // Checksums the driver fills are left zero.
        let mut offloaded = software();
        offloaded.ipv4 = smoltcp::phy::Checksum::None;
        offloaded.udp = smoltcp::phy::Checksum::None;
        assert!(headers.write(&mut frame, payload.len(), &offloaded));
        assert_eq!(frame[24..26], [0, 0]);
        assert_eq!(frame[40..42], [0, 0]);
    }

    fn me() -> NetworkConfig {
        NetworkConfig::new_static(ME, Ipv4Addr::new(255, 255, 255, 0), MY_MAC)
    }

    #[test]
    fn the_last_route_is_kept_until_something_it_depends_on_changes() {
        let mut neighbors = Neighbors::default();
        let mut last = LastRoute::default();
        let to = SocketAddrV4::new(PEER, 2222);
        let me = me();
        // Nobody heard from yet.
        assert!(last
            .headers((&MY_MAC, &me), (to, 0, 64), &mut neighbors)
            .is_none());
        neighbors.learn(PEER, PEER_MAC);
        let first = last
            .headers((&MY_MAC, &me), (to, 0, 64), &mut neighbors)
            .unwrap()
            .bytes;
        assert_eq!(first[..6], PEER_MAC);
        // Learning the same MAC again changes nothing; a new MAC is taken at once.
        let changes = neighbors.changes();
        neighbors.learn(PEER, PEER_MAC);
        assert_eq!(neighbors.changes(), changes);
        let moved = [2, 0, 0, 0, 0, 9];
        neighbors.learn(PEER, moved);
        let h = last.headers((&MY_MAC, &me), (to, 0, 64), &mut neighbors);
        assert_eq!(h.unwrap().bytes[..6], moved);
        // Another DSCP, time to live or port: other headers.
        let h = last.headers((&MY_MAC, &me), (to, 46, 64), &mut neighbors);
        assert_eq!(h.unwrap().bytes[15], 46 << 2);
        let h = last.headers((&MY_MAC, &me), (to, 46, 9), &mut neighbors);
        assert_eq!(h.unwrap().bytes[22], 9);
        let other = SocketAddrV4::new(PEER, 40_000);
        let h = last.headers((&MY_MAC, &me), (other, 46, 9), &mut neighbors);
        assert_eq!(h.unwrap().bytes[36..38], 40_000u16.to_be_bytes());
        // A new interface address: the source follows it.
        let mut renumbered = me;
        renumbered.ip = Ipv4Addr::new(198, 18, 0, 7);
        let h = last.headers((&MY_MAC, &renumbered), (other, 46, 9), &mut neighbors);
        assert_eq!(h.unwrap().bytes[26..30], [198, 18, 0, 7]);
        // Off the link, through the gateway's MAC.
        let far = SocketAddrV4::new(Ipv4Addr::new(198, 19, 5, 5), 2222);
        let gateway = Ipv4Addr::new(198, 18, 0, 254);
        let mut routed = me;
        routed.gateway = gateway;
        let gw_mac = [2, 0, 0, 0, 0, 0xFE];
        assert!(last
            .headers((&MY_MAC, &routed), (far, 0, 64), &mut neighbors)
            .is_none());
        neighbors.learn(gateway, gw_mac);
        let h = last.headers((&MY_MAC, &routed), (far, 0, 64), &mut neighbors);
        assert_eq!(h.unwrap().bytes[..6], gw_mac);
        // Multicast: the group's MAC, no neighbour needed.
        let group = SocketAddrV4::new(Ipv4Addr::new(239, 192, 1, 0), 2222);
        let h = last.headers((&MY_MAC, &me), (group, 0, 1), &mut neighbors);
        assert_eq!(h.unwrap().bytes[..6], [0x01, 0x00, 0x5E, 0x40, 1, 0]);
    }
}
