//! SipHash-2-4 (Aumasson and Bernstein) of one 8-byte word: the keyed hash of the initial
//! sequence numbers (RFC 6528) and of SYN cookies. core's `SipHasher` is deprecated.

/// SipHash-2-4 (Aumasson and Bernstein) of the 8-byte message `m` under `key`.
pub(super) fn siphash24((k0, k1): (u64, u64), m: u64) -> u64 {
    let mut v = [
        k0 ^ 0x736F_6D65_7073_6575,
        k1 ^ 0x646F_7261_6E64_6F6D,
        k0 ^ 0x6C79_6765_6E65_7261,
        k1 ^ 0x7465_6462_7974_6573,
    ];
    let round = |v: &mut [u64; 4]| {
        let [a, b, c, d] = v;
        *a = a.wrapping_add(*b);
        *b = b.rotate_left(13) ^ *a;
        *a = a.rotate_left(32);
        *c = c.wrapping_add(*d);
        *d = d.rotate_left(16) ^ *c;
        *a = a.wrapping_add(*d);
        *d = d.rotate_left(21) ^ *a;
        *c = c.wrapping_add(*b);
        *b = b.rotate_left(17) ^ *c;
        *c = c.rotate_left(32);
    };
    // The message word, then the last block: the length (8) in the top byte.
    for word in [m, 8 << 56] {
        v[3] ^= word;
        round(&mut v);
        round(&mut v);
        v[0] ^= word;
    }
    v[2] ^= 0xFF;
    for _ in 0..4 {
        round(&mut v);
    }
    v[0] ^ v[1] ^ v[2] ^ v[3]
}

#[cfg(test)]
mod tests {
    use super::siphash24;

    #[test]
    fn siphash_matches_the_reference_vector() {
        // The reference implementation's vector for the 8-byte message 00..07 under the key
        // 00..0f (vectors.h, entry 8).
        let key = (0x0706_0504_0302_0100, 0x0F0E_0D0C_0B0A_0908);
        assert_eq!(siphash24(key, 0x0706_0504_0302_0100), 0x93F5_F579_9A93_2462);
    }
}
