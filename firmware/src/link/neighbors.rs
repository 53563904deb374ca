//! Where T->O data goes next: the MAC address each IPv4 host's frames last came from, as
//! the link task saw them (an originator always talks to the adapter before its first T->O
//! datagram: the Forward_Open, then O->T data or heartbeats), and when to ask by ARP for
//! a host it has not heard from.

use core::net::Ipv4Addr;

use enip_stack::config::{MAX_CONNECTIONS, MAX_SESSIONS};
use enip_stack::Instant;

/// Hosts remembered: one per session and per connection.
pub(crate) const NEIGHBORS: usize = MAX_SESSIONS + MAX_CONNECTIONS;
/// Shortest time between two ARP requests of the link task, microseconds.
const ARP_INTERVAL_US: u64 = 100_000;

/// IPv4 host -> MAC address, learned from received frames; the least recently learned entry
/// that no T->O datagram went to makes room for a new host (the least recently learned of
/// all only when every entry has carried T->O): a storm of frames from changing senders
/// (ARP requests, forged IPv4) cycles through the other entries and leaves the
/// originators' alone.
#[derive(Debug, Default)]
pub(crate) struct Neighbors {
    entries: [Option<Entry>; NEIGHBORS],
    /// Learn count, to find the least recently learned entry.
    clock: u32,
    /// The entry learned or found last (most frames come from the same few hosts).
    last: usize,
    /// The last ARP request sent: when.
    asked: Option<Instant>,
    /// Count of the entries that took another host or another MAC address: a next hop's
    /// MAC address looked up before may no longer be the one a lookup finds.
    changes: u32,
}

#[derive(Debug, Clone, Copy)]
struct Entry {
    ip: Ipv4Addr,
    mac: [u8; 6],
    learned: u32,
    /// A T->O datagram or a connection's TCP segment went to it ([`Neighbors::get`]).
    used: bool,
}

impl Neighbors {
    /// Notes that `ip`'s frames come from `mac`. Inline: the commonest case, the host
    /// learned last from the same MAC (a stream of O->T data), which stays the newest and
    /// changes nothing, is one comparison where it is called.
    #[inline]
    pub fn learn(&mut self, ip: Ipv4Addr, mac: [u8; 6]) {
        let newest = |e: &Option<Entry>| {
            e.is_some_and(|e| e.ip == ip && e.mac == mac && e.learned == self.clock)
        };
        if !self.entries.get(self.last).is_some_and(newest) {
            self.learn_anew(ip, mac);
        }
    }

    /// [`Self::learn`] for a host other than the one learned last, or from another MAC.
    #[inline(never)]
    fn learn_anew(&mut self, ip: Ipv4Addr, mac: [u8; 6]) {
        self.clock = self.clock.wrapping_add(1);
        let learned = self.clock;
        // A host heard from before (nearly every frame): newer, and its MAC if it moved.
        if let Some(i) = self.find(ip) {
            if let Some(Some(e)) = self.entries.get_mut(i) {
                e.learned = learned;
                if e.mac != mac {
                    e.mac = mac;
                    self.changes = self.changes.wrapping_add(1);
                }
                self.last = i;
                return;
            }
        }
        let slot = self.oldest();
        if let Some(e) = self.entries.get_mut(slot) {
            *e = Some(Entry {
                ip,
                mac,
                learned,
                used: false,
            });
            self.last = slot;
            self.changes = self.changes.wrapping_add(1);
        }
    }

    /// The MAC address of `ip`'s frames, if any came; the entry is one T->O goes to now.
    pub fn get(&mut self, ip: Ipv4Addr) -> Option<[u8; 6]> {
        let mac = self.peek(ip)?;
        if let Some(Some(e)) = self.entries.get_mut(self.last) {
            e.used = true;
        }
        Some(mac)
    }

    /// The MAC address of `ip`'s frames, if any came, without making its entry one that T->O
    /// goes to: for the answers to SYNs and the RSTs, which a storm of forged segments would
    /// otherwise turn into entries kept before the originators'.
    pub fn peek(&mut self, ip: Ipv4Addr) -> Option<[u8; 6]> {
        let i = self.find(ip)?;
        self.last = i;
        Some(self.entries.get(i)?.as_ref()?.mac)
    }

    /// Changes to the entries since the start: the same count means every lookup finds what
    /// it found before.
    pub fn changes(&self) -> u32 {
        self.changes
    }

    /// The entry of `ip`: the last one used, else the first that matches.
    fn find(&self, ip: Ipv4Addr) -> Option<usize> {
        let is = |e: &Option<Entry>| e.is_some_and(|e| e.ip == ip);
        if self.entries.get(self.last).is_some_and(is) {
            return Some(self.last);
        }
        self.entries.iter().position(is)
    }

    /// Whether an ARP request may go out at `now` (none in the last 100 ms); notes it did.
    pub fn may_ask(&mut self, now: Instant) -> bool {
        let quiet = self
            .asked
            .is_none_or(|at| now.as_micros().saturating_sub(at.as_micros()) >= ARP_INTERVAL_US);
        if quiet {
            self.asked = Some(now);
        }
        quiet
    }

    /// The free entry, else the least recently learned one no T->O went to, else the least
    /// recently learned one.
    fn oldest(&self) -> usize {
        // Free first, then unused before used, then by age.
        let rank = |e: &Option<Entry>| {
            e.map_or((true, true, u32::MAX), |e| {
                (false, !e.used, self.clock.wrapping_sub(e.learned))
            })
        };
        (0..NEIGHBORS)
            .max_by_key(|&i| self.entries.get(i).map_or((false, false, 0), rank))
            .unwrap_or(0)
    }
}

/// The next hop towards `to` from an interface at `ip`/`netmask` with `gateway`
/// (unspecified: none): `to` itself on the link, else the gateway.
pub(crate) fn next_hop(
    to: Ipv4Addr,
    ip: Ipv4Addr,
    netmask: Ipv4Addr,
    gateway: Ipv4Addr,
) -> Ipv4Addr {
    let mask = u32::from(netmask);
    let on_link = u32::from(to) & mask == u32::from(ip) & mask;
    if on_link || gateway.is_unspecified() {
        to
    } else {
        gateway
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const A: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 1);

    #[test]
    fn learns_updates_and_forgets_the_oldest() {
        let mut n = Neighbors::default();
        assert_eq!(n.get(A), None);
        n.learn(A, [2, 0, 0, 0, 0, 1]);
        n.learn(A, [2, 0, 0, 0, 0, 2]);
        // Looked at without `get`, which would make A one T->O goes to.
        let mac = |n: &Neighbors, ip| n.find(ip).and_then(|i| n.entries[i]).map(|e| e.mac);
        assert_eq!(mac(&n, A), Some([2, 0, 0, 0, 0, 2]));
        for i in 0..NEIGHBORS as u8 {
            n.learn(Ipv4Addr::new(198, 18, 1, i), [2, 0, 0, 0, 1, i]);
        }
        // A was the oldest of NEIGHBORS + 1 hosts.
        assert_eq!(n.get(A), None);
        assert_eq!(
            n.get(Ipv4Addr::new(198, 18, 1, 0)),
            Some([2, 0, 0, 0, 1, 0])
        );
        // Learning an existing host again moves it to the newest.
        n.learn(Ipv4Addr::new(198, 18, 1, 0), [2, 0, 0, 0, 1, 0]);
        n.learn(A, [2, 0, 0, 0, 0, 3]);
        assert_eq!(
            n.get(Ipv4Addr::new(198, 18, 1, 0)),
            Some([2, 0, 0, 0, 1, 0])
        );
        assert_eq!(n.get(Ipv4Addr::new(198, 18, 1, 1)), None);
    }

    #[test]
    fn a_storm_of_senders_leaves_the_originators_alone() {
        let mut n = Neighbors::default();
        n.learn(A, [2, 0, 0, 0, 0, 1]);
        assert!(n.get(A).is_some(), "T->O goes to A");
        for i in 0..=255u8 {
            n.learn(Ipv4Addr::new(198, 18, 1, i), [2, 0, 0, 0, 1, i]);
        }
        assert_eq!(n.get(A), Some([2, 0, 0, 0, 0, 1]));
        // Learned again, A stays one T->O goes to.
        n.learn(A, [2, 0, 0, 0, 0, 2]);
        for i in 0..=255u8 {
            n.learn(Ipv4Addr::new(198, 18, 2, i), [2, 0, 0, 0, 2, i]);
        }
        assert_eq!(n.get(A), Some([2, 0, 0, 0, 0, 2]));
    }

    #[test]
    fn senders_only_answered_by_peek_do_not_crowd_out_the_originators() {
        let mut n = Neighbors::default();
        n.learn(A, [2, 0, 0, 0, 0, 1]);
        assert!(n.get(A).is_some(), "T->O goes to A");
        // Forged SYNs from changing senders, each answered (its MAC looked up by peek).
        for i in 0..=255u8 {
            let ip = Ipv4Addr::new(198, 18, 1, i);
            n.learn(ip, [2, 0, 0, 0, 1, i]);
            assert_eq!(n.peek(ip), Some([2, 0, 0, 0, 1, i]));
        }
        assert_eq!(n.get(A), Some([2, 0, 0, 0, 0, 1]));
    }

    #[test]
    fn changes_count_what_a_lookup_could_find_differently() {
        let mut n = Neighbors::default();
        let b = Ipv4Addr::new(198, 18, 0, 9);
        n.learn(A, [2, 0, 0, 0, 0, 1]);
        let first = n.changes();
        // The same host from the same MAC again, in a stream or after another host: none.
        n.learn(A, [2, 0, 0, 0, 0, 1]);
        n.learn(A, [2, 0, 0, 0, 0, 1]);
        assert_eq!(n.changes(), first);
        n.learn(b, [2, 0, 0, 0, 0, 9]);
        let second = n.changes();
        assert_ne!(second, first, "a new host");
        n.learn(A, [2, 0, 0, 0, 0, 1]);
        assert_eq!(n.changes(), second);
        n.learn(A, [2, 0, 0, 0, 0, 2]);
        assert_ne!(n.changes(), second, "a MAC that moved");
        assert_eq!(n.get(A), Some([2, 0, 0, 0, 0, 2]));
    }

    #[test]
    fn learning_the_last_looked_up_host_again_makes_it_the_newest() {
        let mut n = Neighbors::default();
        let b = Ipv4Addr::new(198, 18, 0, 9);
        n.learn(b, [2, 0, 0, 0, 0, 9]);
        n.learn(A, [2, 0, 0, 0, 0, 1]);
        // Both carry T->O; B was looked up last, so it is the entry a lookup starts from,
        // but it was learned before A: learning it again must still make it the newer.
        assert!(n.get(A).is_some());
        assert!(n.get(b).is_some());
        n.learn(b, [2, 0, 0, 0, 0, 9]);
        n.learn(b, [2, 0, 0, 0, 0, 9]);
        // Every other entry taken by a host that carries T->O too, then one more host: the
        // least recently learned of them all makes room.
        for i in 0..(NEIGHBORS - 2) as u8 {
            let ip = Ipv4Addr::new(198, 18, 1, i);
            n.learn(ip, [2, 0, 0, 0, 1, i]);
            assert!(n.get(ip).is_some());
        }
        n.learn(Ipv4Addr::new(198, 18, 2, 0), [2, 0, 0, 0, 2, 0]);
        assert_eq!(n.get(A), None, "A, learned before B's return, made room");
        assert_eq!(n.get(b), Some([2, 0, 0, 0, 0, 9]));
    }

    #[test]
    fn asks_at_most_every_100_ms() {
        let mut n = Neighbors::default();
        assert!(n.may_ask(Instant::from_micros(1_000)));
        assert!(!n.may_ask(Instant::from_micros(100_999)));
        assert!(n.may_ask(Instant::from_micros(101_000)));
    }

    #[test]
    fn next_hop_is_the_gateway_off_the_link() {
        let ip = Ipv4Addr::new(198, 18, 0, 2);
        let mask = Ipv4Addr::new(255, 255, 255, 0);
        let gw = Ipv4Addr::new(198, 18, 0, 254);
        assert_eq!(next_hop(A, ip, mask, gw), A);
        let far = Ipv4Addr::new(198, 19, 0, 9);
        assert_eq!(next_hop(far, ip, mask, gw), gw);
        assert_eq!(next_hop(far, ip, mask, Ipv4Addr::UNSPECIFIED), far);
    }
}
