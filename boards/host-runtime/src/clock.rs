//! The clock: `CLOCK_MONOTONIC`, read through the vDSO without a lock or a system call.

/// Microseconds of the monotonic clock (since boot): the time of every `embassy_time::Instant`
/// on the host.
pub fn now_micros() -> u64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid timespec to write; CLOCK_MONOTONIC always exists on Linux, so
    // the call cannot fail.
    unsafe { libc::clock_gettime(libc::CLOCK_MONOTONIC, &mut ts) };
    // Both fields are non-negative for this clock, and microseconds since boot fit in 64
    // bits for 584 000 years: plain conversions, no checks on the hot path.
    (ts.tv_sec as u64)
        .wrapping_mul(1_000_000)
        .wrapping_add(ts.tv_nsec as u64 / 1_000)
}
