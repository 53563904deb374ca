//! Sequence-number arithmetic modulo 2^32 (RFC 9293 3.4): comparisons that hold across the
//! wrap, for numbers less than 2^31 apart.

/// `a` comes before `b`.
pub(super) fn lt(a: u32, b: u32) -> bool {
    (a.wrapping_sub(b) as i32) < 0
}

/// `a` comes before `b` or is `b`.
pub(super) fn le(a: u32, b: u32) -> bool {
    !lt(b, a)
}

/// `x` lies in `[start, start + len)`.
pub(super) fn within(x: u32, start: u32, len: u32) -> bool {
    x.wrapping_sub(start) < len
}

/// The number of sequence numbers from `from` up to `to` (0 if `to` comes first).
pub(super) fn distance(from: u32, to: u32) -> u32 {
    if lt(to, from) {
        0
    } else {
        to.wrapping_sub(from)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comparisons_hold_across_the_wrap() {
        assert!(lt(u32::MAX, 0));
        assert!(lt(u32::MAX - 5, 3));
        assert!(!lt(3, u32::MAX - 5));
        assert!(le(7, 7));
        assert!(!lt(7, 7));
        assert!(within(1, u32::MAX, 3));
        assert!(!within(2, u32::MAX, 3));
        assert!(!within(5, 5, 0));
        assert_eq!(distance(u32::MAX, 2), 3);
        assert_eq!(distance(2, u32::MAX), 0);
    }
}
