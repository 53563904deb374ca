//! Conversions between embassy-time instants and the stack's microsecond [`enip_stack::Instant`].

/// The current time as the stack counts it.
pub(crate) fn now() -> enip_stack::Instant {
    to_stack(embassy_time::Instant::now())
}

/// An embassy-time instant as a stack instant.
pub(crate) fn to_stack(at: embassy_time::Instant) -> enip_stack::Instant {
    enip_stack::Instant::from_micros(at.as_micros())
}

/// A stack instant as an embassy-time instant (saturating at [`embassy_time::Instant::MAX`]).
pub(crate) fn to_embassy(at: enip_stack::Instant) -> embassy_time::Instant {
    embassy_time::Instant::try_from_micros(at.as_micros()).unwrap_or(embassy_time::Instant::MAX)
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
}
