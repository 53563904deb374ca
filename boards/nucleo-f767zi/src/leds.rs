//! The NUCLEO-F767ZI's three user LEDs as the two ODVA indicators.
//!
//! The board has no bicolour LEDs, so: LD1 (green, PB0) is Module Status green, LD2 (blue,
//! PB7) is Network Status green, and LD3 (red, PB14) is lit when either indicator is red.

use embassy_stm32::gpio::Output;
use enip_firmware::indicators::{set, Color, Leds};

/// LD1, LD2 and LD3.
pub struct NucleoLeds {
    /// LD1, green: Module Status green.
    pub ld1_green: Output<'static>,
    /// LD2, blue: Network Status green.
    pub ld2_blue: Output<'static>,
    /// LD3, red: either indicator red.
    pub ld3_red: Output<'static>,
}

impl Leds for NucleoLeds {
    fn show(&mut self, ms: Color, ns: Color) {
        set(&mut self.ld1_green, ms == Color::Green);
        set(&mut self.ld2_blue, ns == Color::Green);
        set(&mut self.ld3_red, ms == Color::Red || ns == Color::Red);
    }
}
