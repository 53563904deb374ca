//! The configuration class 0xC1 as stored words (§2.3-2.10): sizes, word layouts, the
//! power-up defaults, and the views the limit-switch engine reads.
//!
//! Every attribute is kept as the UINT words the manual tables number (word 1 = index 0),
//! so a Get returns exactly what a valid Set wrote.

// Word offsets only: group, setpoint and input indices below the tables' fixed sizes, and
// attribute IDs matched to their ranges before any subtraction.
#![allow(clippy::arithmetic_side_effects)]

/// PLS groups (§2.3).
pub const GROUPS: usize = 8;
/// Outputs: 1-16 high speed, 17-32 low speed.
pub const OUTPUTS: usize = 32;
/// High speed outputs (1-16).
pub const HIGH_SPEED: usize = 16;
/// Inputs: 1-8 hardware, 9-16 soft inputs from output word 7.
pub const INPUTS: usize = 16;

/// Words of attribute 1, the PLS object (8 groups x 6).
pub const PLS_WORDS: usize = 48;
/// Words of a high speed output attribute (2-17).
pub const HIGH_WORDS: usize = 26;
/// Words of a low speed output attribute (18-33).
pub const LOW_WORDS: usize = 20;
/// Words per input in attribute 34.
pub const INPUT_STRIDE: usize = 7;
/// Words of attribute 34, the input configuration (16 x 7).
pub const INPUT_WORDS: usize = INPUTS * INPUT_STRIDE;
/// Words of attribute 35, the add-on test.
pub const ADDON_WORDS: usize = 3;
/// Words of attribute 36, the offset object.
pub const OFFSET_WORDS: usize = 9;
/// Words of attribute 37, program control.
pub const CONTROL_WORDS: usize = 2;
/// Words of attribute 38, the encoder object.
pub const ENCODER_WORDS: usize = 2;

/// Attribute numbers of class 0xC1.
pub mod attr {
    /// PLS object.
    pub const PLS: u16 = 1;
    /// First high speed output (output 1).
    pub const FIRST_HIGH: u16 = 2;
    /// Last high speed output (output 16).
    pub const LAST_HIGH: u16 = 17;
    /// First low speed output (output 17).
    pub const FIRST_LOW: u16 = 18;
    /// Last low speed output (output 32).
    pub const LAST_LOW: u16 = 33;
    /// Input configuration.
    pub const INPUTS: u16 = 34;
    /// Add-on test.
    pub const ADDON: u16 = 35;
    /// Offset object (command).
    pub const OFFSET: u16 = 36;
    /// Program control (command).
    pub const CONTROL: u16 = 37;
    /// Encoder object.
    pub const ENCODER: u16 = 38;
}

/// The number of words attribute `a` of class 0xC1 holds.
pub const fn attribute_words(a: u16) -> usize {
    match a {
        attr::PLS => PLS_WORDS,
        attr::FIRST_HIGH..=attr::LAST_HIGH => HIGH_WORDS,
        attr::FIRST_LOW..=attr::LAST_LOW => LOW_WORDS,
        attr::INPUTS => INPUT_WORDS,
        attr::ADDON => ADDON_WORDS,
        attr::OFFSET => OFFSET_WORDS,
        attr::CONTROL => CONTROL_WORDS,
        _ => ENCODER_WORDS,
    }
}

/// Default scale factor of every group after power-up with an empty NVRAM (\[R\] 19).
pub const DEFAULT_SCALE: u16 = 360;

/// Setpoint types (§2.4, word 8 / §2.5, word 2).
pub mod setpoint {
    /// No setpoint programmed.
    pub const NONE: u16 = 0;
    /// Standard: on position, off position.
    pub const STANDARD: u16 = 1;
    /// Stitching: on, off, counts high, counts low.
    pub const STITCHING: u16 = 2;
    /// Time-based: on position, time in ms.
    pub const TIME_BASED: u16 = 3;
    /// Motion detect: RPM.
    pub const MOTION_DETECT: u16 = 4;
}

/// The stored configuration: attributes 1-35 and 38 as words.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Config {
    /// Attribute 1.
    pub pls: [u16; PLS_WORDS],
    /// Attributes 2-17 (outputs 1-16).
    pub high: [[u16; HIGH_WORDS]; HIGH_SPEED],
    /// Attributes 18-33 (outputs 17-32).
    pub low: [[u16; LOW_WORDS]; OUTPUTS - HIGH_SPEED],
    /// Attribute 34.
    pub inputs: [u16; INPUT_WORDS],
    /// Attribute 35.
    pub addon: [u16; ADDON_WORDS],
    /// Attribute 38.
    pub encoder: [u16; ENCODER_WORDS],
}

/// Bytes of the stored configuration (the NVRAM image without the group offsets).
pub const CONFIG_BYTES: usize =
    2 * (PLS_WORDS + 16 * HIGH_WORDS + 16 * LOW_WORDS + INPUT_WORDS + ADDON_WORDS + ENCODER_WORDS);

impl Default for Config {
    fn default() -> Self {
        Self::new()
    }
}

/// One output's setpoint program, read from its attribute.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Program {
    /// Linear speed words 1-6 (high speed outputs; zeros for low speed).
    pub compensation: [u16; 6],
    /// Number of setpoints (words 7 / 1).
    pub count: u16,
    /// Setpoint 1 type.
    pub kind: u16,
    /// Setpoint 1 parameters 1-4.
    pub params: [u16; 4],
    /// Setpoints 2-8: (on, off).
    pub extra: [(u16, u16); 7],
}

impl Config {
    /// Power-up defaults: scale factor 360 in every group, everything else 0 (\[R\] 19).
    pub const fn new() -> Self {
        let mut pls = [0; PLS_WORDS];
        let mut g = 0;
        while g < GROUPS {
            // Const context, so no `get_mut`; `6 * g < 6 * GROUPS`, which the array length covers.
            #[allow(clippy::indexing_slicing)]
            {
                pls[6 * g] = DEFAULT_SCALE;
            }
            g += 1;
        }
        Config {
            pls,
            high: [[0; HIGH_WORDS]; HIGH_SPEED],
            low: [[0; LOW_WORDS]; OUTPUTS - HIGH_SPEED],
            inputs: [0; INPUT_WORDS],
            addon: [0; ADDON_WORDS],
            encoder: [0; ENCODER_WORDS],
        }
    }

    /// The words of stored attribute `a` (1-35, 38).
    pub fn words(&self, a: u16) -> Option<&[u16]> {
        Some(match a {
            attr::PLS => &self.pls,
            attr::FIRST_HIGH..=attr::LAST_HIGH => self.high.get(usize::from(a - 2))?,
            attr::FIRST_LOW..=attr::LAST_LOW => self.low.get(usize::from(a - 18))?,
            attr::INPUTS => &self.inputs,
            attr::ADDON => &self.addon,
            attr::ENCODER => &self.encoder,
            _ => return None,
        })
    }

    /// The words of stored attribute `a`, to write.
    pub fn words_mut(&mut self, a: u16) -> Option<&mut [u16]> {
        Some(match a {
            attr::PLS => &mut self.pls,
            attr::FIRST_HIGH..=attr::LAST_HIGH => self.high.get_mut(usize::from(a - 2))?,
            attr::FIRST_LOW..=attr::LAST_LOW => self.low.get_mut(usize::from(a - 18))?,
            attr::INPUTS => &mut self.inputs,
            attr::ADDON => &mut self.addon,
            attr::ENCODER => &mut self.encoder,
            _ => return None,
        })
    }

    /// Scale factor of group `g` (0-based).
    pub fn scale(&self, g: usize) -> u16 {
        self.pls.get(6 * g).copied().unwrap_or(DEFAULT_SCALE).max(2)
    }

    /// Group word `k` (0 = scale ... 5 = min speed mask) of group `g` (0-based).
    pub fn group_word(&self, g: usize, k: usize) -> u16 {
        self.pls.get(6 * g + k).copied().unwrap_or(0)
    }

    /// The group (0-based) output `o` (0-based) belongs to.
    pub fn group_of_output(&self, o: usize) -> Option<usize> {
        let (k, bit) = if o < HIGH_SPEED {
            (1, o)
        } else {
            (2, o - HIGH_SPEED)
        };
        (0..GROUPS).find(|&g| self.group_word(g, k) & (1 << (bit & 15)) != 0 && bit < 16)
    }

    /// The group (0-based) input `i` (0-based) belongs to.
    pub fn group_of_input(&self, i: usize) -> Option<usize> {
        (0..GROUPS).find(|&g| i < 16 && self.group_word(g, 3) & (1 << i) != 0)
    }

    /// The setpoint program of output `o` (0-based).
    pub fn program(&self, o: usize) -> Program {
        let (words, base): (&[u16], usize) = match o {
            0..=15 => (self.high.get(o).map_or(&[][..], |w| &w[..]), 6),
            _ => (self.low.get(o - HIGH_SPEED).map_or(&[][..], |w| &w[..]), 0),
        };
        let w = |i: usize| words.get(i).copied().unwrap_or(0);
        let mut compensation = [0; 6];
        if base == 6 {
            for (k, c) in compensation.iter_mut().enumerate() {
                *c = w(k);
            }
        }
        let mut extra = [(0, 0); 7];
        for (k, e) in extra.iter_mut().enumerate() {
            *e = (w(base + 6 + 2 * k), w(base + 7 + 2 * k));
        }
        Program {
            compensation,
            count: w(base),
            kind: w(base + 1),
            params: [w(base + 2), w(base + 3), w(base + 4), w(base + 5)],
            extra,
        }
    }

    /// Input `i`'s (0-based) seven words: bit register, high mask, low mask, type, P1-P3.
    pub fn input(&self, i: usize) -> [u16; INPUT_STRIDE] {
        let mut out = [0; INPUT_STRIDE];
        if let Some(w) = self.inputs.get(INPUT_STRIDE * i..INPUT_STRIDE * (i + 1)) {
            out.copy_from_slice(w);
        }
        out
    }

    /// Every stored word in attribute order (1-35, then 38), for the NVRAM image.
    pub fn all_words(&self) -> impl Iterator<Item = u16> + '_ {
        let high = self.high.iter().flat_map(|w| w.iter());
        let low = self.low.iter().flat_map(|w| w.iter());
        self.pls
            .iter()
            .chain(high)
            .chain(low)
            .chain(self.inputs.iter())
            .chain(self.addon.iter())
            .chain(self.encoder.iter())
            .copied()
    }

    /// Every stored word in the order of [`Config::all_words`], to write.
    pub fn all_words_mut(&mut self) -> impl Iterator<Item = &mut u16> + '_ {
        let high = self.high.iter_mut().flat_map(|w| w.iter_mut());
        let low = self.low.iter_mut().flat_map(|w| w.iter_mut());
        self.pls
            .iter_mut()
            .chain(high)
            .chain(low)
            .chain(self.inputs.iter_mut())
            .chain(self.addon.iter_mut())
            .chain(self.encoder.iter_mut())
    }
}

/// Little-endian UINT words of `bytes` into `out` (lengths already checked by the stack).
pub fn decode_words(bytes: &[u8], out: &mut [u16]) {
    let words = bytes
        .chunks_exact(2)
        .filter_map(|b| <[u8; 2]>::try_from(b).ok())
        .map(u16::from_le_bytes);
    for (w, v) in out.iter_mut().zip(words) {
        *w = v;
    }
}
