//! SYN cookies (RFC 4987 3.6): the initial sequence number of a SYN-ACK sent without keeping
//! anything, from which the ACK completing the handshake proves that it answers that
//! SYN-ACK and recovers what the connection needs of the SYN (the peer's segment size).
//!
//! A cookie is 32 bits: 5 bits of a clock ticking every 2^22 us (about 4.2 s), 25 bits of a
//! keyed hash (SipHash-2-4) of the peer's address and port, its initial sequence number and
//! the tick, and 2 bits naming the segment size from [`SEGMENT_SIZES`]. It is good in the
//! tick it was made and the next one: 4.2 to 8.4 s, far beyond a handshake's round trip
//! (a peer that misses it sends its SYN again). A forged ACK guesses 25 bits.

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

/// The cookie for a SYN from `peer` with initial sequence number `isn` and segment size
/// `mss` (already clamped), at `now`, under `key`.
pub(super) fn make(key: (u64, u64), peer: SocketAddrV4, isn: u32, mss: u16, now: Instant) -> u32 {
    let index = SEGMENT_SIZES
        .iter()
        .rposition(|&size| size <= mss)
        .unwrap_or(0);
    let tick = tick(now);
    (tick << (HASH_BITS + 2)) | (hash(key, peer, isn, tick) << 2) | (index as u32 & 3)
}

/// The segment size named by `cookie` if it is the one made for `peer`'s SYN with initial
/// sequence number `isn` in this tick or the last one (at `now`, under `key`).
pub(super) fn check(
    key: (u64, u64),
    peer: SocketAddrV4,
    isn: u32,
    cookie: u32,
    now: Instant,
) -> Option<u16> {
    let made = cookie >> (HASH_BITS + 2);
    let this = tick(now);
    let tick = [this, this.wrapping_sub(1) & 0x1F]
        .into_iter()
        .find(|&t| t == made)?;
    let carried = (cookie >> 2) & ((1 << HASH_BITS) - 1);
    if carried != hash(key, peer, isn, tick) {
        return None;
    }
    SEGMENT_SIZES.get((cookie & 3) as usize).copied()
}

/// The cookie clock at `now`, in its 5 bits.
fn tick(now: Instant) -> u32 {
    (now.as_micros() >> TICK_SHIFT) as u32 & 0x1F
}

/// SipHash-2-4 of the peer's address and port under `key`, then of the initial sequence
/// number and the tick under a key derived from the first: its top [`HASH_BITS`] bits.
fn hash(key: (u64, u64), peer: SocketAddrV4, isn: u32, tick: u32) -> u32 {
    let tuple = (u64::from(u32::from(*peer.ip())) << 16) | u64::from(peer.port());
    let first = siphash24(key, tuple);
    let second = siphash24(
        (key.0 ^ first, key.1),
        (u64::from(isn) << 32) | u64::from(tick),
    );
    (second >> (64 - HASH_BITS)) as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::net::Ipv4Addr;

    const KEY: (u64, u64) = (0x0123_4567_89AB_CDEF, 0xFEDC_BA98_7654_3210);

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
        assert_eq!(check((1, 2), peer(5000), 77, cookie, made), None);
        // Nor any other cookie of that tick and size (one bit off anywhere in the hash).
        for bit in 2..27 {
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
    fn the_clock_wraps_within_its_five_bits() {
        let made = Instant(31 << TICK_SHIFT);
        let cookie = make(KEY, peer(5000), 1, 536, made);
        let after_wrap = Instant(32 << TICK_SHIFT);
        assert_eq!(check(KEY, peer(5000), 1, cookie, after_wrap), Some(536));
    }
}
