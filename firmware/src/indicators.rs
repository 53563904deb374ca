//! The ODVA Module Status (MS) and Network Status (NS) indicators (CIP Vol 2, 9-4.1/9-4.2),
//! driven from the adapter's state onto a board's LEDs.
//!
//! A board gives [`indicate`] something that implements [`Leds`]: [`BicolorLeds`] for two
//! bicolour (green/red) indicators on four `embedded-hal` output pins, or its own mapping
//! when it has fewer LEDs. At start the power-up test runs (MS green, MS red, NS green, NS
//! red, 250 ms each), then every 250 ms:
//!
//! | indicator | state | shows |
//! | --- | --- | --- |
//! | MS | operational | steady green |
//! | MS | recoverable fault (identity status bits 8-10) | flashing red |
//! | MS | unrecoverable major fault (bit 11) | steady red |
//! | NS | no IP address | off |
//! | NS | duplicate IP address (Address Conflict Detection gave it up) | steady red |
//! | NS | address, no connection | flashing green |
//! | NS | at least one CIP connection | steady green |
//! | NS | an exclusive owner timed out, none re-established | flashing red |
//!
//! Flashing is 1 Hz, half on.

use embassy_time::{Duration, Ticker, Timer};
use embedded_hal::digital::OutputPin;
use enip_stack::{Adapter, Device};

use crate::shared::{with_adapter_quiet, SharedAdapter};

/// Indicator update period; flashing toggles every second period.
const TICK: Duration = Duration::from_millis(250);
/// Identity status: minor recoverable, minor unrecoverable and major recoverable faults.
const RECOVERABLE_FAULTS: u16 = 0x0700;
/// Identity status: major unrecoverable fault.
const MAJOR_UNRECOVERABLE_FAULT: u16 = 0x0800;

/// What one bicolour indicator shows at an instant.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Color {
    /// Dark.
    Off,
    /// Green.
    Green,
    /// Red.
    Red,
}

/// The state of one indicator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Indicator {
    /// Steady off.
    Off,
    /// Steady green.
    Green,
    /// Steady red.
    Red,
    /// Green, 1 Hz.
    FlashingGreen,
    /// Red, 1 Hz.
    FlashingRed,
}

impl Indicator {
    /// The colour in the on (`lit` true) or off half of a flash period.
    pub fn color(self, lit: bool) -> Color {
        match self {
            Indicator::Off => Color::Off,
            Indicator::Green => Color::Green,
            Indicator::Red => Color::Red,
            Indicator::FlashingGreen if lit => Color::Green,
            Indicator::FlashingRed if lit => Color::Red,
            Indicator::FlashingGreen | Indicator::FlashingRed => Color::Off,
        }
    }
}

/// The LEDs of a board, showing the two indicators.
pub trait Leds {
    /// Shows `ms` on the Module Status indicator and `ns` on the Network Status one.
    fn show(&mut self, ms: Color, ns: Color);
}

/// Two bicolour indicators, each on a green and a red output pin (high = lit).
pub struct BicolorLeds<MsGreen, MsRed, NsGreen, NsRed> {
    /// Module Status green.
    pub ms_green: MsGreen,
    /// Module Status red.
    pub ms_red: MsRed,
    /// Network Status green.
    pub ns_green: NsGreen,
    /// Network Status red.
    pub ns_red: NsRed,
}

impl<A: OutputPin, B: OutputPin, C: OutputPin, E: OutputPin> Leds for BicolorLeds<A, B, C, E> {
    fn show(&mut self, ms: Color, ns: Color) {
        set(&mut self.ms_green, ms == Color::Green);
        set(&mut self.ms_red, ms == Color::Red);
        set(&mut self.ns_green, ns == Color::Green);
        set(&mut self.ns_red, ns == Color::Red);
    }
}

/// Drives `pin` high (lit) or low; a pin that fails keeps its state.
pub fn set(pin: &mut impl OutputPin, lit: bool) {
    let _ = if lit { pin.set_high() } else { pin.set_low() };
}

/// The Module Status indicator for identity status bits `status`.
pub fn module_status(status: u16) -> Indicator {
    if status & MAJOR_UNRECOVERABLE_FAULT != 0 {
        Indicator::Red
    } else if status & RECOVERABLE_FAULTS != 0 {
        Indicator::FlashingRed
    } else {
        Indicator::Green
    }
}

/// Network Status, from the adapter.
#[derive(Debug, Default)]
pub struct NetworkStatus;

impl NetworkStatus {
    /// The Network Status indicator for `adapter` now: flashing red from an exclusive
    /// owner's timeout until an exclusive owner opens again (Vol 2 9-4.2; the table keeps it,
    /// as it does Identity's extended status 0010).
    pub fn update<D: Device, const S: usize, const C: usize, const F: usize, const L: usize>(
        &mut self,
        adapter: &Adapter<D, S, C, F, L>,
    ) -> Indicator {
        if adapter.acd().fault {
            Indicator::Red
        } else if adapter.network().ip.is_unspecified() {
            Indicator::Off
        } else if adapter.connections().owner_timed_out() {
            Indicator::FlashingRed
        } else if !adapter.connections().is_empty() {
            Indicator::Green
        } else {
            Indicator::FlashingGreen
        }
    }
}

/// Runs the power-up test, then shows the adapter's state on `leds` forever.
pub async fn indicate<D: Device, const S: usize, const C: usize, const F: usize, const L: usize>(
    adapter: &SharedAdapter<D, S, C, F, L>,
    mut leds: impl Leds,
) -> ! {
    use Color::{Green, Off, Red};
    for (ms, ns) in [(Green, Off), (Red, Off), (Green, Green), (Green, Red)] {
        leds.show(ms, ns);
        Timer::after(TICK).await;
    }
    let mut network = NetworkStatus;
    let mut ticker = Ticker::every(TICK);
    let mut tick = 0u32;
    loop {
        let (ms, ns) = with_adapter_quiet(adapter, |a| {
            let status = a.identity_status();
            (module_status(status), network.update(a))
        });
        let lit = tick % 4 < 2;
        leds.show(ms.color(lit), ns.color(lit));
        tick = tick.wrapping_add(1);
        ticker.next().await;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn module_status_from_identity_bits() {
        assert_eq!(module_status(0x0030), Indicator::Green);
        assert_eq!(module_status(0x0100), Indicator::FlashingRed);
        assert_eq!(module_status(0x0400), Indicator::FlashingRed);
        assert_eq!(module_status(0x0C00), Indicator::Red);
    }

    #[test]
    fn network_status_off_without_address_red_on_a_duplicate_else_flashing_green() {
        use core::net::Ipv4Addr;
        let config =
            |ip| enip_stack::NetworkConfig::new_static(ip, Ipv4Addr::new(255, 255, 255, 0), [2; 6]);
        let mut ns = NetworkStatus;
        let mut adapter = Adapter::new(
            enip_profiles::Generic::new(),
            config(Ipv4Addr::UNSPECIFIED),
            1,
        );
        assert_eq!(ns.update(&adapter), Indicator::Off);
        adapter.set_network(config(Ipv4Addr::new(198, 18, 0, 2)));
        assert_eq!(ns.update(&adapter), Indicator::FlashingGreen);
        // The address found in use by another host: steady red (duplicate IP).
        adapter.set_acd_status(true, true);
        assert_eq!(ns.update(&adapter), Indicator::Red);
    }

    #[test]
    fn flashing_alternates_and_steady_does_not() {
        assert_eq!(Indicator::FlashingGreen.color(true), Color::Green);
        assert_eq!(Indicator::FlashingGreen.color(false), Color::Off);
        assert_eq!(Indicator::FlashingRed.color(false), Color::Off);
        assert_eq!(Indicator::Red.color(false), Color::Red);
        assert_eq!(Indicator::Off.color(true), Color::Off);
    }
}
