//! Conversions between embassy-time instants and the stack's microsecond
//! [`enip_stack::Instant`], and the earlier of two deadlines.

/// The current time as the stack counts it.
pub(crate) fn now() -> enip_stack::Instant {
    to_stack(instant_now())
}

/// The current embassy-time instant. Never inlined: one copy of the time driver's read for
/// its dozen callers.
#[inline(never)]
pub(crate) fn instant_now() -> embassy_time::Instant {
    embassy_time::Instant::now()
}

/// An embassy-time instant as a stack instant.
pub(crate) fn to_stack(at: embassy_time::Instant) -> enip_stack::Instant {
    enip_stack::Instant::from_micros(at.as_micros())
}

/// A stack instant as an embassy-time instant (saturating at [`embassy_time::Instant::MAX`]).
pub(crate) fn to_embassy(at: enip_stack::Instant) -> embassy_time::Instant {
    embassy_time::Instant::try_from_micros(at.as_micros()).unwrap_or(embassy_time::Instant::MAX)
}

/// The earlier of two deadlines (`None` is never).
pub(crate) fn earliest(
    a: Option<enip_stack::Instant>,
    b: Option<enip_stack::Instant>,
) -> Option<enip_stack::Instant> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_and_saturates() {
        let at = enip_stack::Instant::from_micros(1_234_567);
        assert_eq!(to_stack(to_embassy(at)), at);
        assert_eq!(
            to_embassy(enip_stack::Instant::from_micros(u64::MAX)),
            embassy_time::Instant::MAX
        );
    }

    #[test]
    fn earliest_treats_none_as_never() {
        let (one, two) = (enip_stack::Instant(1), enip_stack::Instant(2));
        assert_eq!(earliest(Some(two), Some(one)), Some(one));
        assert_eq!(earliest(None, Some(two)), Some(two));
        assert_eq!(earliest(Some(one), None), Some(one));
        assert_eq!(earliest(None, None), None);
    }
}
