//! Seeds of the link-level targets: ARP frames for `acd`, an O->T datagram and an ARP
//! request in whole Ethernet frames for `link_frame`, and the records the device itself
//! stores for `nv_records`.

use std::net::Ipv4Addr;

use enip_stack::acd::AcdSettings;
use enip_stack::nv::{key, NvStore};
use enip_stack::objects::security::{CertInstance, SecurityState};
use enip_stack::objects::{LldpConfig, QosState, TcpIpState};

use crate::store;

/// The adapter's address in the targets.
const ME: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 2);
/// A scanner's address and MAC.
const PEER: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 1);
const PEER_MAC: [u8; 6] = [0x02, 0x00, 0x5E, 0x10, 0x00, 0x01];
/// The adapter's MAC in the targets.
const MY_MAC: [u8; 6] = [0x02, 0x00, 0x5E, 0x10, 0x00, 0x02];

/// A broadcast ARP frame (Ethernet header and the 28-byte PDU for IPv4).
fn arp(op: u16, mac: [u8; 6], ip: Ipv4Addr, target: Ipv4Addr) -> Vec<u8> {
    let mut f = vec![0xFF; 6];
    f.extend_from_slice(&mac);
    f.extend_from_slice(&[0x08, 0x06, 0x00, 0x01, 0x08, 0x00, 6, 4]);
    f.extend_from_slice(&op.to_be_bytes());
    f.extend_from_slice(&mac);
    f.extend_from_slice(&ip.octets());
    f.extend_from_slice(&[0; 6]);
    f.extend_from_slice(&target.octets());
    f
}

/// One step of the `acd` script: wait `wait` x 20 ms, then receive `frame`.
fn step(wait: u8, frame: &[u8]) -> Vec<u8> {
    let mut s = vec![wait, frame.len() as u8];
    s.extend_from_slice(frame);
    s
}

/// The one's-complement sum of `b` (RFC 1071), folded.
fn sum(b: &[u8], mut acc: u32) -> u16 {
    for c in b.chunks(2) {
        acc += u32::from(u16::from_be_bytes([c[0], *c.get(1).unwrap_or(&0)]));
    }
    while acc > 0xFFFF {
        acc = (acc & 0xFFFF) + (acc >> 16);
    }
    acc as u16
}

/// An Ethernet frame with an IPv4 UDP datagram from the scanner's port 2222 to the
/// adapter's, checksums right.
fn udp_frame(payload: &[u8]) -> Vec<u8> {
    let udp_len = 8 + payload.len() as u16;
    let mut ip = vec![0x45, 0];
    ip.extend_from_slice(&(20 + udp_len).to_be_bytes());
    ip.extend_from_slice(&[0, 1, 0x40, 0, 64, 17, 0, 0]);
    ip.extend_from_slice(&PEER.octets());
    ip.extend_from_slice(&ME.octets());
    let c = !sum(&ip, 0);
    ip[10..12].copy_from_slice(&c.to_be_bytes());
    let mut udp = Vec::new();
    udp.extend_from_slice(&2222u16.to_be_bytes());
    udp.extend_from_slice(&2222u16.to_be_bytes());
    udp.extend_from_slice(&udp_len.to_be_bytes());
    udp.extend_from_slice(&[0, 0]);
    udp.extend_from_slice(payload);
    let mut pseudo = PEER.octets().to_vec();
    pseudo.extend_from_slice(&ME.octets());
    pseudo.extend_from_slice(&[0, 17]);
    pseudo.extend_from_slice(&udp_len.to_be_bytes());
    let c = !sum(&udp, u32::from(sum(&pseudo, 0)));
    udp[6..8].copy_from_slice(&c.to_be_bytes());
    let mut f = MY_MAC.to_vec();
    f.extend_from_slice(&PEER_MAC);
    f.extend_from_slice(&[0x08, 0x00]);
    f.extend_from_slice(&ip);
    f.extend_from_slice(&udp);
    f
}

/// The record the device stores for `key` with `save`, behind the target's selector byte.
fn record(selector: u8, key: u16, save: impl FnOnce(&mut dyn NvStore)) -> Vec<u8> {
    let mut s = store::erased();
    save(&mut s);
    let mut buf = [0u8; 512];
    let n = s.read(key, &mut buf).expect("read").expect("saved");
    let mut seed = vec![selector];
    seed.extend_from_slice(&buf[..n]);
    seed
}

/// Every seed: (target, name, bytes). `o_t` is an O->T datagram's encapsulation.
pub fn seeds(o_t: &[u8]) -> Vec<(&'static str, &'static str, Vec<u8>)> {
    let other = [0x02, 0, 0, 0, 0, 0x99];
    let probe = arp(1, other, Ipv4Addr::UNSPECIFIED, ME);
    let claim = arp(1, other, ME, PEER);
    let asks = arp(1, PEER_MAC, PEER, ME);
    // Past probing and announcing (at most 1 + 3 x 2 + 2 + 2 s): 5.1 s steps.
    let settle = [step(255, &[]), step(255, &[]), step(255, &[])].concat();
    let mut pairs = Vec::new();
    for i in 0..40u8 {
        pairs.extend_from_slice(&[198, 18, i % 17, 1, 2, 0, 0, 0, i, 1]);
    }
    let datagram = udp_frame(o_t);
    // The link task takes them as meant: an O->T datagram, and a sender to learn.
    let (_, found) = enip_firmware::link::fuzzing::inspect(&datagram, ME);
    assert_eq!(found.map(|(from, _)| from.port()), Some(2222), "O->T seed");
    let (sender, _) = enip_firmware::link::fuzzing::inspect(&asks, ME);
    assert_eq!(sender, Some((PEER, PEER_MAC)), "ARP seed");
    vec![
        ("acd", "probe_conflict", [vec![7], step(1, &probe)].concat()),
        (
            "acd",
            "defend_then_lose",
            [vec![7], settle.clone(), step(1, &claim), step(1, &claim)].concat(),
        ),
        (
            "acd",
            "request_for_us",
            [vec![7], settle, step(1, &asks)].concat(),
        ),
        ("link_frame", "o_t_datagram", datagram),
        ("link_frame", "arp_request", asks),
        ("link_frame", "neighbours", pairs),
        (
            "nv_records",
            "tcp_ip",
            record(0, key::TCP_IP, |s| TcpIpState::new().save(s).expect("save")),
        ),
        (
            "nv_records",
            "lldp",
            record(1, key::LLDP, |s| LldpConfig::DEFAULT.save(s).expect("save")),
        ),
        (
            "nv_records",
            "qos",
            record(2, key::QOS, |s| QosState::new().save(s).expect("save")),
        ),
        (
            "nv_records",
            "acd",
            record(3, key::ACD, |s| AcdSettings::DEFAULT.save(s).expect("save")),
        ),
        (
            "nv_records",
            "security",
            record(4, key::SECURITY, |s| {
                let mut st = SecurityState::new();
                st.certs[1] = CertInstance::created(b"plant CA", 0).expect("a name");
                st.active.trusted_ca = Some(2);
                st.save(s).expect("save")
            }),
        ),
    ]
}
