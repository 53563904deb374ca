//! The flood guard: what the link task keeps from the network stack during a flood. TCP
//! SYNs to the encapsulation port from a source that floods them (here), and ARP requests
//! from strangers past a budget ([`super::arp_guard`]).
//!
//! The encapsulation TCP (`enip_stack::tcp`) holds a few connections; every SYN that finds
//! one free holds it half-open until the handshake's ACK comes or `HALF_OPEN` passes, and
//! SYNs beyond them are answered with SYN cookies, which hold nothing. A source that sends
//! more than [`LIMIT`] SYNs to the port within [`WINDOW`] without a single segment that
//! acknowledges anything (a client completes each handshake with one; one that reconnects
//! thousands of times a second is no flooder) is a flooder: its SYNs are dropped until it
//! has sent none for [`BLOCK`], so once its half-open connections lapse the connections
//! serve everyone else, and the server spends no time on its SYNs. The guard follows
//! [`SOURCES`] sources at once (the least recently seen gives way): a flood from many forged
//! sources at a time is not told apart from clients; it holds the free connections
//! half-open while it lasts, and clients get in by the cookies. A flooder that also talks
//! TCP from the same address is never blocked (its forged SYN-ACKs draw its own host's
//! resets, which free the connections).

use core::net::Ipv4Addr;

use enip_stack::config::ENCAP_PORT;
use enip_stack::{Duration, Instant};

use super::arp_guard::ArpGuard;

/// Both guards, asked about every frame on its way to the stack.
#[derive(Debug, Default)]
pub(crate) struct FloodGuard {
    syn: SynGuard,
    arp: ArpGuard,
}

impl FloodGuard {
    /// False if `frame`, on its way to the network stack of the adapter at `me`, is to be
    /// dropped.
    pub(crate) fn admit(&mut self, frame: &[u8], me: Ipv4Addr, at: Instant) -> bool {
        self.syn.admit(frame, at) && self.arp.admit(frame, me, at)
    }
}

/// Sources followed at once.
pub(crate) const SOURCES: usize = 8;
/// The span over which a source's SYNs are counted.
pub(crate) const WINDOW: Duration = Duration::from_millis(100);
/// SYNs a source may send within [`WINDOW`]; more make it a flooder.
pub(crate) const LIMIT: u16 = 32;
/// A flooder's SYNs are dropped until it has sent none for this long.
pub(crate) const BLOCK: Duration = Duration::from_millis(500);

/// What the guard knows of one source.
#[derive(Debug, Clone, Copy)]
struct Source {
    ip: Ipv4Addr,
    /// Start of the current counting window and the SYNs seen in it.
    window: Instant,
    syns: u16,
    /// Its SYNs are dropped until then.
    blocked_until: Option<Instant>,
    /// Its last SYN.
    last: Instant,
}

/// The sources of recent SYNs to the encapsulation port.
#[derive(Debug, Default)]
pub(crate) struct SynGuard {
    sources: [Option<Source>; SOURCES],
}

impl SynGuard {
    /// False if `frame` is a SYN to the encapsulation port from a flooder (drop it); true
    /// for every other frame.
    pub(crate) fn admit(&mut self, frame: &[u8], at: Instant) -> bool {
        match segment_to_port(frame) {
            Some((ip, true)) => self.admit_syn(ip, at),
            Some((ip, false)) => {
                self.acknowledged(ip);
                true
            }
            None => true,
        }
    }

    /// `ip` acknowledged something: a TCP peer, not a flooder (its count starts again).
    fn acknowledged(&mut self, ip: Ipv4Addr) {
        let ours = self.sources.iter_mut().flatten().find(|s| s.ip == ip);
        if let Some(s) = ours {
            s.syns = 0;
            s.blocked_until = None;
        }
    }

    /// Counts a SYN from `ip` at `at`; false if `ip` is a flooder.
    fn admit_syn(&mut self, ip: Ipv4Addr, at: Instant) -> bool {
        let fresh = Source {
            ip,
            window: at,
            syns: 0,
            blocked_until: None,
            last: at,
        };
        let i = self.slot(ip);
        let Some(slot) = self.sources.get_mut(i) else {
            return true;
        };
        let s = slot.get_or_insert(fresh);
        if s.ip != ip {
            *s = fresh;
        }
        s.last = at;
        if let Some(until) = s.blocked_until {
            if at < until {
                s.blocked_until = Some(at.add(BLOCK));
                return false;
            }
            s.blocked_until = None;
            s.window = at;
            s.syns = 0;
        }
        if at.since(s.window) >= WINDOW {
            s.window = at;
            s.syns = 0;
        }
        s.syns = s.syns.saturating_add(1);
        if s.syns > LIMIT {
            s.blocked_until = Some(at.add(BLOCK));
            warn!("SYN flood from {}: its SYNs to port 44818 dropped", ip);
            return false;
        }
        true
    }

    /// The slot of `ip`, else an empty one, else the least recently seen.
    fn slot(&self, ip: Ipv4Addr) -> usize {
        let seen = |i: &usize| {
            self.sources
                .get(*i)
                .copied()
                .flatten()
                .map_or(Instant(0), |s| s.last)
        };
        let ours = self
            .sources
            .iter()
            .position(|s| s.is_some_and(|s| s.ip == ip));
        ours.or_else(|| self.sources.iter().position(Option::is_none))
            .or_else(|| (0..SOURCES).min_by_key(seen))
            .unwrap_or(0)
    }
}

/// For an untagged IPv4 TCP segment to the encapsulation port (first fragment), its source
/// and whether it is a SYN (without ACK); `None` for a SYN-less segment that acknowledges
/// nothing (an RST) and for every other frame.
fn segment_to_port(frame: &[u8]) -> Option<(Ipv4Addr, bool)> {
    const ETH: usize = 14;
    if frame.get(12..14)? != [0x08, 0x00] {
        return None;
    }
    let ip = frame.get(ETH..)?;
    let ihl = usize::from(ip.first()? & 0x0F).saturating_mul(4);
    let first_fragment = u16::from_be_bytes([*ip.get(6)?, *ip.get(7)?]) & 0x1FFF == 0;
    if ihl < 20 || *ip.get(9)? != 6 || !first_fragment {
        return None;
    }
    let src: [u8; 4] = ip.get(12..16)?.try_into().ok()?;
    let tcp = ip.get(ihl..)?;
    let port = u16::from_be_bytes([*tcp.get(2)?, *tcp.get(3)?]);
    let flags = *tcp.get(13)?;
    let (syn, ack, rst) = (flags & 0x02 != 0, flags & 0x10 != 0, flags & 0x04 != 0);
    if port != ENCAP_PORT || rst {
        return None;
    }
    match (syn, ack) {
        (true, false) => Some((Ipv4Addr::from(src), true)),
        (false, true) => Some((Ipv4Addr::from(src), false)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An Ethernet + IPv4 + TCP frame from `src` to port `port` with TCP `flags`.
    fn segment(src: [u8; 4], port: u16, flags: u8) -> [u8; 54] {
        let mut f = [0u8; 54];
        f[12..14].copy_from_slice(&[0x08, 0x00]);
        f[14] = 0x45;
        f[23] = 6;
        f[26..30].copy_from_slice(&src);
        f[30..34].copy_from_slice(&[198, 18, 0, 2]);
        f[36..38].copy_from_slice(&port.to_be_bytes());
        f[47] = flags;
        f
    }

    const SYN: u8 = 0x02;

    #[test]
    fn only_syns_to_the_encapsulation_port_count() {
        let a = [198, 18, 0, 77];
        let from = Ipv4Addr::from(a);
        assert_eq!(segment_to_port(&segment(a, 44818, SYN)), Some((from, true)));
        assert_eq!(segment_to_port(&segment(a, 44818, 0x12)), None, "SYN-ACK");
        assert_eq!(
            segment_to_port(&segment(a, 44818, 0x10)),
            Some((from, false))
        );
        assert_eq!(segment_to_port(&segment(a, 44818, 0x14)), None, "RST-ACK");
        assert_eq!(segment_to_port(&segment(a, 80, SYN)), None, "other port");
        let mut udp = segment(a, 44818, SYN);
        udp[23] = 17;
        assert_eq!(segment_to_port(&udp), None);
        let mut fragment = segment(a, 44818, SYN);
        fragment[21] = 8;
        assert_eq!(segment_to_port(&fragment), None);
        assert_eq!(
            segment_to_port(&segment(a, 44818, SYN)[..40]),
            None,
            "cut short"
        );
    }

    #[test]
    fn a_flooder_is_dropped_until_it_stops_and_others_pass() {
        let mut g = SynGuard::default();
        let flood = segment([198, 18, 0, 77], 44818, SYN);
        let client = segment([198, 18, 0, 1], 44818, SYN);
        let t0 = Instant(1_000_000);
        let admitted = (0..1000u64)
            .filter(|i| g.admit(&flood, t0.add(Duration::from_micros(i * 50))))
            .count();
        assert_eq!(admitted, usize::from(LIMIT));
        let during = t0.add(Duration::from_millis(40));
        assert!(g.admit(&client, during), "another source passes");
        assert!(
            g.admit(&segment([198, 18, 0, 77], 80, SYN), during),
            "other ports pass"
        );
        // 100 ms after its last SYN: still blocked (and that SYN keeps it so).
        let last = t0.add(Duration::from_micros(999 * 50));
        assert!(!g.admit(&flood, last.add(Duration::from_millis(100))));
        // BLOCK after its last SYN, it passes again.
        let later = last.add(Duration::from_millis(100)).add(BLOCK);
        assert!(g.admit(&flood, later));
    }

    #[test]
    fn a_client_retrying_every_10_ms_is_not_a_flooder() {
        let mut g = SynGuard::default();
        let client = segment([198, 18, 0, 1], 44818, SYN);
        assert!((0..500u64).all(|i| g.admit(&client, Instant(i * 10_000))));
    }

    #[test]
    fn a_client_reconnecting_thousands_of_times_a_second_is_no_flooder() {
        let mut g = SynGuard::default();
        let syn = segment([198, 18, 0, 1], 44818, SYN);
        let ack = segment([198, 18, 0, 1], 44818, 0x10);
        // A handshake every 250 us, each completed.
        assert!((0..4000u64).all(|i| {
            let at = Instant(i * 250);
            let ok = g.admit(&syn, at);
            g.admit(&ack, at);
            ok
        }));
    }

    #[test]
    fn many_sources_take_turns_in_the_table() {
        let mut g = SynGuard::default();
        for i in 0..100u8 {
            assert!(g.admit(&segment([10, 0, 0, i], 44818, SYN), Instant(u64::from(i))));
        }
        assert!(g.sources.iter().all(Option::is_some));
    }
}
