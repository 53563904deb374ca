//! Conversions between embassy-time instants and the stack's microsecond [`stack::Instant`].

/// The current time as the stack counts it.
pub(crate) fn now() -> stack::Instant {
    to_stack(embassy_time::Instant::now())
}

/// An embassy-time instant as a stack instant.
pub(crate) fn to_stack(at: embassy_time::Instant) -> stack::Instant {
    stack::Instant::from_micros(at.as_micros())
}

/// A stack instant as an embassy-time instant (saturating at [`embassy_time::Instant::MAX`]).
pub(crate) fn to_embassy(at: stack::Instant) -> embassy_time::Instant {
    embassy_time::Instant::try_from_micros(at.as_micros()).unwrap_or(embassy_time::Instant::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_and_saturates() {
        let at = stack::Instant::from_micros(1_234_567);
        assert_eq!(to_stack(to_embassy(at)), at);
        assert_eq!(
            to_embassy(stack::Instant::from_micros(u64::MAX)),
            embassy_time::Instant::MAX
        );
    }
}
