//! The W5500-EVB-Pico's one user LED (green, GP25) as the ODVA indicators.
//!
//! One single-colour LED cannot show two bicolour indicators: it shows the Network Status
//! green (flashing 1 Hz: an address and no connection; steady: at least one CIP connection;
//! off: no address), and goes dark whenever either indicator is red (the cause is in the
//! defmt log).

use embassy_rp::gpio::Output;
use enip_firmware::indicators::{set, Color, Leds};

/// The user LED.
pub struct PicoLed {
    /// GP25, green, high = lit.
    pub led: Output<'static>,
}

impl Leds for PicoLed {
    fn show(&mut self, ms: Color, ns: Color) {
        set(&mut self.led, ns == Color::Green && ms != Color::Red);
    }
}
