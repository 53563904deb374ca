//! The add-on test (§2.7): outputs 1-16 of its mask follow a simulated resolver at the
//! test's speed, from the group positions where it started, while the enable bit holds it
//! or for the test's time.

use enip_stack::{Duration, Instant};

use super::super::params::{Config, GROUPS, HIGH_SPEED};
use super::geometry::advance;

/// The add-on test's state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Addon {
    /// Running.
    active: bool,
    /// When it ends (timed test), or `None` while the enable bit holds it.
    until: Option<Instant>,
    /// The simulated angle travelled since the start (fraction of a revolution, and the
    /// remainder of the division).
    angle: u64,
    rem: u128,
    /// Group positions at the start.
    start: [u16; GROUPS],
    /// Simulated RPM.
    rpm: u16,
    /// Output mask (outputs 1-16).
    mask: u16,
}

impl Addon {
    /// Not running.
    pub const IDLE: Addon = Addon {
        active: false,
        until: None,
        angle: 0,
        rem: 0,
        start: [0; GROUPS],
        rpm: 0,
        mask: 0,
    };

    /// The test of attribute 35 started at `now` with the groups at `positions`.
    pub fn start(cfg: &Config, now: Instant, positions: [u16; GROUPS]) -> Addon {
        let [rpm, ms, mask] = cfg.addon;
        Addon {
            active: true,
            until: (ms != 0).then(|| now.add(Duration::from_millis(ms.into()))),
            angle: 0,
            rem: 0,
            start: positions,
            rpm,
            mask,
        }
    }

    /// The enable bit went low: a test without a time ends; a timed one runs on (\[R\]).
    pub fn release(&mut self) {
        if self.until.is_none() {
            self.active = false;
        }
    }

    /// Advances the simulated resolver by `dt` microseconds, ending a timed test at `now`.
    pub fn advance(&mut self, dt: u64, now: Instant) {
        if self.active {
            let (s, r) = advance(self.rpm, dt, self.rem);
            self.angle = self.angle.wrapping_add(s);
            self.rem = r;
            if self.until.is_some_and(|u| now.as_micros() >= u.as_micros()) {
                self.active = false;
            }
        }
    }

    /// True while the test runs.
    pub fn active(&self) -> bool {
        self.active
    }

    /// The simulated RPM.
    pub fn rpm(&self) -> u16 {
        self.rpm
    }

    /// The simulated position of group `g` (scale factor `sf`) for output `o`, if the test
    /// drives that output.
    pub fn position(&self, o: usize, g: usize, sf: u16) -> Option<u16> {
        if !(self.active && o < HIGH_SPEED && self.mask & (1 << o) != 0) {
            return None;
        }
        let sim = (u64::from(self.angle as u32) * u64::from(sf)) >> 32;
        let start = self.start.get(g).copied().unwrap_or(0);
        Some(((u64::from(start) + sim) % u64::from(sf)) as u16)
    }
}
