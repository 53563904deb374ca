//! The ARP guard: ARP requests for the adapter's address reach the network stack from the
//! hosts that talk IPv4 to it, and from anyone else at most [`STRANGERS`] per [`WINDOW`];
//! requests for other addresses (which smoltcp ignores) do not reach it.
//!
//! smoltcp learns the sender of every ARP request aimed at it into a neighbour cache of 8
//! entries and answers each. A storm of requests from changing senders (an ARP scan gone
//! wild, a forged flood) would have it answer thousands a second and push the hosts it is
//! talking to out of its cache: each then costs an ARP exchange, and smoltcp sends at most
//! one ARP request a second, so a session stalls for a second at a time. The link task
//! knows who talks IPv4 to the adapter (the last [`TALKERS`] sources of IPv4 frames for the
//! stack); their requests always pass. ARP replies always pass (they answer the stack's own
//! requests). A new host's request dropped during a storm is asked again by its sender.

use core::net::Ipv4Addr;

use enip_stack::{Duration, Instant};

/// IPv4 sources remembered.
pub(crate) const TALKERS: usize = 8;
/// ARP requests from other hosts passed per window.
pub(crate) const STRANGERS: u16 = 4;
/// The window [`STRANGERS`] is counted over.
pub(crate) const WINDOW: Duration = Duration::from_secs(1);

/// What a received frame is to the ARP guard.
enum Kind {
    /// An ARP request from this sender, for this address.
    Request(Ipv4Addr, Ipv4Addr),
    /// An IPv4 packet from this source.
    Ipv4(Ipv4Addr),
    Other,
}

/// The recent IPv4 talkers and the strangers' budget.
#[derive(Debug, Default)]
pub(crate) struct ArpGuard {
    /// Recent IPv4 sources, with the learn count when last seen.
    talkers: [Option<(Ipv4Addr, u32)>; TALKERS],
    clock: u32,
    /// The strangers' window: its start and the requests passed in it.
    window: Option<Instant>,
    strangers: u16,
}

impl ArpGuard {
    /// False if `frame` is an ARP request for another address than `me`, or for `me` from a
    /// stranger past the budget (drop it).
    pub(crate) fn admit(&mut self, frame: &[u8], me: Ipv4Addr, at: Instant) -> bool {
        match kind(frame) {
            Kind::Ipv4(ip) => {
                self.talked(ip);
                true
            }
            Kind::Request(_, target) if target != me => false,
            Kind::Request(ip, _) if self.talkers.iter().flatten().any(|t| t.0 == ip) => true,
            Kind::Request(..) => self.stranger(at),
            Kind::Other => true,
        }
    }

    /// Notes an IPv4 packet from `ip`.
    fn talked(&mut self, ip: Ipv4Addr) {
        self.clock = self.clock.wrapping_add(1);
        let now = self.clock;
        let age = |t: &Option<(Ipv4Addr, u32)>| t.map_or(u32::MAX, |t| now.wrapping_sub(t.1));
        let slot = self
            .talkers
            .iter()
            .position(|t| t.is_some_and(|t| t.0 == ip))
            .or_else(|| (0..TALKERS).max_by_key(|&i| self.talkers.get(i).map_or(0, age)));
        if let Some(t) = slot.and_then(|i| self.talkers.get_mut(i)) {
            *t = Some((ip, now));
        }
    }

    /// Counts a stranger's request at `at`; false past the budget.
    fn stranger(&mut self, at: Instant) -> bool {
        let fresh = self.window.is_none_or(|w| at.since(w) >= WINDOW || at < w);
        if fresh {
            self.window = Some(at);
            self.strangers = 0;
        }
        self.strangers = self.strangers.saturating_add(1);
        self.strangers <= STRANGERS
    }
}

/// An untagged ARP request's sender, or an IPv4 packet's source.
fn kind(frame: &[u8]) -> Kind {
    let ip = |at: usize| -> Option<Ipv4Addr> {
        let b: [u8; 4] = frame.get(at..at.checked_add(4)?)?.try_into().ok()?;
        Some(Ipv4Addr::from(b))
    };
    match frame.get(12..14) {
        Some([0x08, 0x00]) => ip(26).map_or(Kind::Other, Kind::Ipv4),
        // ARP: operation at 20-21, sender protocol address at 28, target's at 38.
        Some([0x08, 0x06]) if frame.get(20..22) == Some(&[0, 1]) => match (ip(28), ip(38)) {
            (Some(sender), Some(target)) => Kind::Request(sender, target),
            _ => Kind::Other,
        },
        _ => Kind::Other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn request(sender: [u8; 4]) -> [u8; 42] {
        let mut f = [0u8; 42];
        f[12..14].copy_from_slice(&[0x08, 0x06]);
        f[20..22].copy_from_slice(&[0, 1]);
        f[28..32].copy_from_slice(&sender);
        f[38..42].copy_from_slice(&[198, 18, 0, 2]);
        f
    }

    fn ipv4(src: [u8; 4]) -> [u8; 34] {
        let mut f = [0u8; 34];
        f[12..14].copy_from_slice(&[0x08, 0x00]);
        f[14] = 0x45;
        f[26..30].copy_from_slice(&src);
        f
    }

    const ME: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 2);

    #[test]
    fn a_storm_of_strangers_passes_its_budget_and_talkers_always() {
        let mut g = ArpGuard::default();
        let t = Instant(10_000_000);
        assert!(g.admit(&ipv4([198, 18, 0, 1]), ME, t));
        let passed = (0..=255u8)
            .filter(|i| g.admit(&request([198, 18, 1, *i]), ME, t))
            .count();
        assert_eq!(passed, usize::from(STRANGERS));
        assert!(g.admit(&request([198, 18, 0, 1]), ME, t), "a talker passes");
        let mut reply = request([198, 18, 1, 9]);
        reply[21] = 2;
        assert!(g.admit(&reply, ME, t), "replies pass");
        let mut other = request([198, 18, 0, 1]);
        other[41] = 9;
        assert!(
            !g.admit(&other, ME, t),
            "a request for another address goes nowhere"
        );
        // The next window has a new budget.
        assert!(g.admit(&request([198, 18, 1, 9]), ME, t.add(WINDOW)));
    }

    #[test]
    fn talkers_are_the_most_recent_ipv4_sources() {
        let mut g = ArpGuard::default();
        let t = Instant(0);
        for i in 0..=TALKERS as u8 {
            g.admit(&ipv4([10, 0, 0, i]), ME, t);
        }
        g.strangers = STRANGERS;
        g.window = Some(t);
        assert!(
            !g.admit(&request([10, 0, 0, 0]), ME, t),
            "the oldest was forgotten"
        );
        assert!(g.admit(&request([10, 0, 0, TALKERS as u8]), ME, t));
    }
}
