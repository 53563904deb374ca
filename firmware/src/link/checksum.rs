//! The Internet checksum (RFC 1071) of the Class 1 frames, sixteen bytes per step: 32-bit
//! words are summed in memory order into a wide accumulator and folded once, which gives the
//! same 16-bit result in memory order as the big-endian sum (RFC 1071 section 2 (B)).

use core::net::Ipv4Addr;

/// A running one's-complement sum.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct Sum(u64);

impl Sum {
    /// Adds `data`, which starts at an even offset of the checksummed bytes; an odd
    /// trailing byte counts as if followed by a zero.
    pub fn add(self, data: &[u8]) -> Sum {
        // Whole 32-bit words into a 64-bit sum (a load and two adds a word on a Cortex-M;
        // 2^16 and 2^32 are both 1 modulo 0xFFFF, so folding gives the 16-bit sum), four
        // words a step.
        let (words, rest) = data.as_chunks::<4>();
        let (quads, words) = words.as_chunks::<4>();
        let mut sum = self.0;
        for [a, b, c, d] in quads {
            sum = sum
                .wrapping_add(u64::from(u32::from_ne_bytes(*a)))
                .wrapping_add(u64::from(u32::from_ne_bytes(*b)))
                .wrapping_add(u64::from(u32::from_ne_bytes(*c)))
                .wrapping_add(u64::from(u32::from_ne_bytes(*d)));
        }
        for word in words {
            sum = sum.wrapping_add(u64::from(u32::from_ne_bytes(*word)));
        }
        if rest.is_empty() {
            return Sum(sum);
        }
        let mut last = [0u8; 4];
        for (to, from) in last.iter_mut().zip(rest) {
            *to = *from;
        }
        Sum(sum.wrapping_add(u64::from(u32::from_ne_bytes(last))))
    }

    /// Adds four bytes at an even offset of the checksummed bytes.
    pub fn add_word(self, word: [u8; 4]) -> Sum {
        Sum(self.0.wrapping_add(u64::from(u32::from_ne_bytes(word))))
    }

    /// Adds the IPv4 pseudo-header of a UDP datagram of `udp_len` bytes.
    pub fn add_pseudo_header(self, src: Ipv4Addr, dst: Ipv4Addr, udp_len: u16) -> Sum {
        let [l0, l1] = udp_len.to_be_bytes();
        self.add_word(src.octets())
            .add_word(dst.octets())
            .add_word([0, 17, l0, l1])
    }

    /// The sum folded to 16 bits, as its two bytes in memory order.
    pub fn folded(self) -> [u8; 2] {
        // 64 to 32 bits with the end-around carry (an add and an add-with-carry on a
        // Cortex-M), then 32 to 16 bits twice: at most 0x1_FFFE after the first, 0xFFFF after
        // the second.
        let (low, carry) = (self.0 as u32).overflowing_add((self.0 >> 32) as u32);
        let s = low.wrapping_add(u32::from(carry));
        let s = (s & 0xFFFF).wrapping_add(s >> 16);
        let s = (s & 0xFFFF).wrapping_add(s >> 16);
        (s as u16).to_ne_bytes()
    }

    /// True if the data summed held a correct checksum (it sums to all ones).
    pub fn is_valid(self) -> bool {
        self.folded() == [0xFF, 0xFF]
    }

    /// The checksum to write for the data summed (with its checksum field zero).
    pub fn checksum(self) -> [u8; 2] {
        let [a, b] = self.folded();
        [!a, !b]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// RFC 1071's big-endian, two bytes at a time definition.
    fn reference(data: &[u8]) -> u16 {
        let mut acc: u32 = 0;
        for pair in data.chunks(2) {
            let hi = u32::from(pair[0]) << 8;
            let lo = pair.get(1).map_or(0, |b| u32::from(*b));
            acc += hi | lo;
        }
        while acc > 0xFFFF {
            acc = (acc & 0xFFFF) + (acc >> 16);
        }
        acc as u16
    }

    #[test]
    fn matches_the_two_byte_definition_at_every_length() {
        let data: [u8; 67] =
            core::array::from_fn(|i| (i as u8).wrapping_mul(37).wrapping_add(0xF1));
        for len in 0..data.len() {
            let folded = Sum::default().add(&data[..len]).folded();
            assert_eq!(
                u16::from_be_bytes(folded),
                reference(&data[..len]),
                "{len} bytes"
            );
        }
    }

    #[test]
    fn wide_sums_fold_like_the_reference() {
        // Many all-ones words: the 64-bit accumulator carries far past 32 bits.
        let data = [0xFFu8; 4096];
        for len in [2, 4, 6, 1024, 4094, 4096] {
            let folded = Sum::default().add(&data[..len]).folded();
            assert_eq!(u16::from_be_bytes(folded), reference(&data[..len]), "{len}");
        }
        let data: [u8; 4096] = core::array::from_fn(|i| (i as u8).wrapping_mul(151) | 0x80);
        let folded = Sum::default().add(&data).folded();
        assert_eq!(u16::from_be_bytes(folded), reference(&data));
    }

    #[test]
    fn a_written_checksum_verifies() {
        // An IPv4 header with its checksum field (bytes 10-11) zero.
        let mut header = [
            0x45, 0, 0, 0x54, 0, 0, 0x40, 0, 0x40, 0x11, 0, 0, 198, 18, 0, 2, 198, 18, 0, 1,
        ];
        let c = Sum::default().add(&header).checksum();
        header[10..12].copy_from_slice(&c);
        assert!(Sum::default().add(&header).is_valid());
        header[3] ^= 1;
        assert!(!Sum::default().add(&header).is_valid());
    }
}
