//! SYN cookies (RFC 4987 3.6): the initial sequence number of every SYN-ACK (one sent
//! without keeping anything, and one whose connection is kept, which may lapse), from which
//! the ACK completing the handshake proves that it answers that SYN-ACK and recovers what
//! the connection needs of the SYN (the peer's segment size). As initial sequence numbers
//! they are hard to guess (RFC 6528's aim) and carry a clock in their top bits.
//!
//! A cookie is 32 bits: the low 5 bits of a clock ticking every 2^22 us (about 4.2 s), 25
//! bits of a keyed hash (SipHash-2-4, under a key of its own: [`Cookies`]) of the peer's
//! address and port, its initial sequence number, the whole tick count and the segment size
//! named, and 2 bits naming the peer's segment size from [`SEGMENT_SIZES`]. It is good in
//! the tick it was made and the next one: 4.2 to 8.4 s, far beyond a handshake's round trip
//! (a peer that misses it sends its SYN again), and never again later (the hash holds the
//! whole tick count, not its 5 bits). A forged ACK guesses 25 bits.

use core::net::SocketAddrV4;

use super::siphash::siphash24;
use super::{MIN_MSS, MSS};
use crate::{Duration, Instant};

/// The cookie clock's tick, in microseconds: 2^22.
const TICK_SHIFT: u32 = 22;
/// How long after the last cookie went an ACK may still prove one: two ticks.
pub(super) const LIFETIME: Duration = Duration::from_micros(2 << TICK_SHIFT);
/// The peer's segment sizes a cookie can name: the largest not over the peer's is used
/// (a peer that names none gets [`super::DEFAULT_MSS`]'s 536).
const SEGMENT_SIZES: [u16; 4] = [MIN_MSS, 536, 1440, MSS];
/// Bits of the hash in a cookie.
const HASH_BITS: u32 = 25;
/// The tick bits a cookie carries.
const TICK_MASK: u64 = 0x1F;

/// The key of the cookies' hash, drawn at start.
#[derive(Debug, Clone, Copy)]
pub(super) struct Cookies {
    key: (u64, u64),
}

impl Cookies {
    /// The key drawn from `seed`.
    pub(super) const fn new(seed: u64) -> Self {
        Cookies {
            key: (
                seed ^ 0x6B65_7920_666F_7220,
                seed.rotate_left(29) ^ 0x636F_6F6B_6965_7321,
            ),
        }
    }

    /// Mixes `a` and `b` (drawn from the runtime's seed) into the key.
    pub(super) fn mix(&mut self, a: u64, b: u64) {
        self.key = (self.key.0 ^ a, self.key.1 ^ b);
    }

    /// The cookie for a SYN from `peer` with initial sequence number `isn` and segment size
    /// `mss` (already clamped), at `now`.
    pub(super) fn make(&self, peer: SocketAddrV4, isn: u32, mss: u16, now: Instant) -> u32 {
        let index = SEGMENT_SIZES
            .iter()
            .rposition(|&size| size <= mss)
            .unwrap_or(0) as u32
            & 3;
        let tick = tick(now);
        let hash = self.hash(peer, isn, tick, index);
        (((tick & TICK_MASK) as u32) << (HASH_BITS + 2)) | (hash << 2) | index
    }

    /// The segment size named by `cookie` if it is the one made for `peer`'s SYN with initial
    /// sequence number `isn` in this tick or the last one (at `now`).
    pub(super) fn check(
        &self,
        peer: SocketAddrV4,
        isn: u32,
        cookie: u32,
        now: Instant,
    ) -> Option<u16> {
        let made = u64::from(cookie >> (HASH_BITS + 2));
        let this = tick(now);
        let tick = [this, this.wrapping_sub(1)]
            .into_iter()
            .find(|&t| t & TICK_MASK == made)?;
        let index = cookie & 3;
        let carried = (cookie >> 2) & ((1 << HASH_BITS) - 1);
        if carried != self.hash(peer, isn, tick, index) {
            return None;
        }
        SEGMENT_SIZES.get(index as usize).copied()
    }

    /// The top [`HASH_BITS`] bits of SipHash-2-4 chained over two words (the peer's address
    /// and port; then, added to the first hash, the initial sequence number, the tick count
    /// and the segment size's index), under the cookies' key.
    fn hash(&self, peer: SocketAddrV4, isn: u32, tick: u64, index: u32) -> u32 {
        let tuple = (u64::from(u32::from(*peer.ip())) << 16) | u64::from(peer.port());
        let rest = (u64::from(isn) << 32) | ((tick << 2) & 0xFFFF_FFFF) | u64::from(index);
        let hash = siphash24(self.key, siphash24(self.key, tuple) ^ rest);
        (hash >> (64 - HASH_BITS)) as u32
    }
}

/// The cookie clock at `now`: its whole tick count.
fn tick(now: Instant) -> u64 {
    now.as_micros() >> TICK_SHIFT
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::net::Ipv4Addr;

    const KEY: Cookies = Cookies::new(0x0123_4567_89AB_CDEF);

    fn make(key: Cookies, peer: SocketAddrV4, isn: u32, mss: u16, now: Instant) -> u32 {
        key.make(peer, isn, mss, now)
    }

    fn check(key: Cookies, peer: SocketAddrV4, isn: u32, cookie: u32, now: Instant) -> Option<u16> {
        key.check(peer, isn, cookie, now)
    }

    fn peer(port: u16) -> SocketAddrV4 {
        SocketAddrV4::new(Ipv4Addr::new(198, 18, 0, 1), port)
    }

    #[test]
    fn a_cookie_is_good_for_its_syn_in_its_tick_and_the_next_only() {
        let made = Instant(5 << TICK_SHIFT);
        let cookie = make(KEY, peer(5000), 77, 1460, made);
        assert_eq!(check(KEY, peer(5000), 77, cookie, made), Some(1460));
        let next_tick = Instant((7 << TICK_SHIFT) - 1);
        assert_eq!(check(KEY, peer(5000), 77, cookie, next_tick), Some(1460));
        assert_eq!(
            check(KEY, peer(5000), 77, cookie, Instant(7 << TICK_SHIFT)),
            None
        );
        // Another SYN, peer, port or key: not its cookie.
        assert_eq!(check(KEY, peer(5000), 78, cookie, made), None);
        assert_eq!(check(KEY, peer(5001), 77, cookie, made), None);
        assert_eq!(check(Cookies::new(1), peer(5000), 77, cookie, made), None);
        // Nor any other cookie of that tick (one bit off anywhere in the hash), nor the same
        // hash naming another segment size.
        for bit in 0..27 {
            assert_eq!(check(KEY, peer(5000), 77, cookie ^ (1 << bit), made), None);
        }
    }

    #[test]
    fn the_segment_size_named_is_the_largest_not_over_the_peers() {
        let now = Instant(1 << 40);
        let named = |mss| check(KEY, peer(1), 9, make(KEY, peer(1), 9, mss, now), now);
        assert_eq!(named(1460), Some(1460));
        assert_eq!(named(1450), Some(1440));
        assert_eq!(named(1439), Some(536));
        assert_eq!(named(536), Some(536));
        assert_eq!(named(535), Some(MIN_MSS));
        assert_eq!(named(MIN_MSS), Some(MIN_MSS));
    }

    #[test]
    fn the_ticks_five_bits_wrap_and_a_cookie_never_comes_back() {
        let made = Instant(31 << TICK_SHIFT);
        let cookie = make(KEY, peer(5000), 1, 536, made);
        let after_wrap = Instant(32 << TICK_SHIFT);
        assert_eq!(check(KEY, peer(5000), 1, cookie, after_wrap), Some(536));
        // 32 ticks on, its 5 bits read as this tick's again: the hash of the whole count
        // refuses it.
        for later in [63u64, 64, 95, 96] {
            let at = Instant(later << TICK_SHIFT);
            assert_eq!(check(KEY, peer(5000), 1, cookie, at), None, "tick {later}");
        }
    }
}
