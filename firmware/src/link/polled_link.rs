//! [`PolledLink`]: a driver whose link state is read from its PHY at most once a period.
//!
//! The link task asks its driver for the link state at every wake-up. embassy-stm32's
//! `Ethernet` answers by reading the PHY's status register over MDIO, busy-waiting for the
//! whole management frame (64 MDC clocks: about 30 µs at the NUCLEO-F767ZI's 216 MHz HCLK,
//! divided by 102), and arms a timer for its next poll. At ten 1 ms connections the link task
//! wakes about ten times a millisecond: the reads alone would take a third of the core.
//! Wrapped, the driver's link state is read at the first wake-up a period after the last
//! read, and every wake-up in between answers with the state last read and asks embassy-time
//! for a wake-up at the next read, so a link change is seen within a period even on an
//! otherwise idle link. Frames go to and from the driver untouched.
//!
//! For drivers that poll their PHY; one whose link state is cheap or comes by interrupt (the
//! LAN9118's, the TAP's) needs no wrapper.

use core::task::Context;

use embassy_net_driver::{Capabilities, Driver, HardwareAddress, LinkState};
use embassy_time::Duration;

use crate::clock::instant_now;

/// The period the NUCLEO boards read their PHY's link state at: a link change is seen
/// within it (autonegotiation itself takes a second or more).
pub const PHY_READ_PERIOD: Duration = Duration::from_millis(100);

/// A driver whose link state is read at most once a period.
pub struct PolledLink<D> {
    inner: D,
    reads: Reads,
}

impl<D: Driver> PolledLink<D> {
    /// `inner`, its link state read at most once every `period`.
    pub fn new(inner: D, period: Duration) -> Self {
        PolledLink {
            inner,
            reads: Reads {
                period_ticks: period.as_ticks(),
                next: None,
                state: LinkState::Down,
            },
        }
    }
}

/// When the link state is read next, and what it was.
struct Reads {
    period_ticks: u64,
    /// The tick of the next read (`None`: read at the next call).
    next: Option<u64>,
    /// The state last read.
    state: LinkState,
}

impl Reads {
    /// At tick `now`: whether the state is to be read now, and the tick of the read after
    /// (a read counts the period from `now`).
    fn due(&mut self, now: u64) -> (bool, u64) {
        match self.next {
            Some(next) if now < next => (false, next),
            _ => {
                let next = now.saturating_add(self.period_ticks);
                self.next = Some(next);
                (true, next)
            }
        }
    }
}

impl<D: Driver> Driver for PolledLink<D> {
    type RxToken<'a>
        = D::RxToken<'a>
    where
        Self: 'a;
    type TxToken<'a>
        = D::TxToken<'a>
    where
        Self: 'a;

    fn receive(&mut self, cx: &mut Context<'_>) -> Option<(Self::RxToken<'_>, Self::TxToken<'_>)> {
        self.inner.receive(cx)
    }

    fn transmit(&mut self, cx: &mut Context<'_>) -> Option<Self::TxToken<'_>> {
        self.inner.transmit(cx)
    }

    fn link_state(&mut self, cx: &mut Context<'_>) -> LinkState {
        let (read, next) = self.reads.due(instant_now().as_ticks());
        if read {
            self.reads.state = self.inner.link_state(cx);
        }
        embassy_time_driver::schedule_wake(next, cx.waker());
        self.reads.state
    }

    fn capabilities(&self) -> Capabilities {
        self.inner.capabilities()
    }

    fn hardware_address(&self) -> HardwareAddress {
        self.inner.hardware_address()
    }
}

#[cfg(test)]
mod tests {
    use super::Reads;
    use embassy_net_driver::LinkState;

    fn reads() -> Reads {
        Reads {
            period_ticks: 100,
            next: None,
            state: LinkState::Down,
        }
    }

    #[test]
    fn reads_once_a_period() {
        let mut reads = reads();
        // The first call reads; the calls within the period wait for the next read.
        assert_eq!(reads.due(1_000), (true, 1_100));
        assert_eq!(reads.due(1_000), (false, 1_100));
        assert_eq!(reads.due(1_099), (false, 1_100));
        // A period on, it reads again, the next period counted from that call.
        assert_eq!(reads.due(1_100), (true, 1_200));
        assert_eq!(reads.due(1_150), (false, 1_200));
        // Woken late, the next period counts from the late read.
        assert_eq!(reads.due(5_000), (true, 5_100));
        assert_eq!(reads.due(5_001), (false, 5_100));
    }

    #[test]
    fn the_end_of_time_does_not_wrap() {
        let mut reads = reads();
        assert_eq!(reads.due(u64::MAX - 10), (true, u64::MAX));
        assert_eq!(reads.due(u64::MAX - 1), (false, u64::MAX));
    }
}
