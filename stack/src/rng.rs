//! A tiny deterministic pseudo-random generator (xorshift64*) for reply delays and handles.

/// xorshift64* state; seeded by the runtime from a hardware RNG or the clock.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator from `seed` (zero is replaced by a fixed non-zero constant).
    pub const fn new(seed: u64) -> Self {
        Rng(if seed == 0 {
            0x9E37_79B9_7F4A_7C15
        } else {
            seed
        })
    }
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    /// A value in `0..=max`. Never inlined: its 64-bit remainder is wanted only by the
    /// cold callers (ACD's random delays, List_Identity's reply delay).
    #[inline(never)]
    pub fn below_or_equal(&mut self, max: u64) -> u64 {
        match max.checked_add(1) {
            Some(m) => self.next_u64().checked_rem(m).unwrap_or(0),
            None => self.next_u64(),
        }
    }
}
