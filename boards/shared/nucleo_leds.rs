//! The three user LEDs of a NUCLEO-144 board of the H7 and H5 generations (LD1 green, LD2
//! yellow, LD3 red) as the two ODVA indicators, `#[path]`-included by those boards.
//!
//! The board has no bicolour LEDs, so: LD1 (green) is Module Status green, LD2 (yellow) is
//! Network Status green, and LD3 (red) is lit when either indicator is red.

use embassy_stm32::gpio::Output;
use enip_firmware::indicators::{set, Color, Leds};

/// LD1, LD2 and LD3.
pub struct NucleoLeds {
    /// LD1, green: Module Status green.
    pub ld1_green: Output<'static>,
    /// LD2, yellow: Network Status green.
    pub ld2_yellow: Output<'static>,
    /// LD3, red: either indicator red.
    pub ld3_red: Output<'static>,
}

impl Leds for NucleoLeds {
    fn show(&mut self, ms: Color, ns: Color) {
        set(&mut self.ld1_green, ms == Color::Green);
        set(&mut self.ld2_yellow, ns == Color::Green);
        set(&mut self.ld3_red, ms == Color::Red || ns == Color::Red);
    }
}
