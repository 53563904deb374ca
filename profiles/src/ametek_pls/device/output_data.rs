//! The output data (O->T, §2.1 "Output Data Transfer"), words 1-7: the bits of word 1 and
//! the force masks of the outputs and the groups.

/// Output data (O->T, §2.1 "Output Data Transfer"), words 1-7.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct OutputData {
    /// Word 1: bit 0 Run Enable, bit 1 Add-On Test Enable, bit 2 Acknowledge.
    pub bits: u16,
    /// Words 2-5: force masks of outputs 1-8, 9-16, 17-24, 25-32 (2 bits each).
    pub force: [u16; 4],
    /// Word 6: force mask of groups 1-8.
    pub group_force: u16,
    /// Word 7: soft inputs 9-16 (bit 0 = input 9).
    pub soft: u16,
}

/// Word 1 bit 0: Run Enable (level).
pub const RUN_ENABLE: u16 = 1 << 0;
/// Word 1 bit 1: Add-On Test Enable (0->1 starts the test).
pub const ADDON_ENABLE: u16 = 1 << 1;
/// Word 1 bit 2: Acknowledge (0->1 clears the error words).
pub const ACKNOWLEDGE: u16 = 1 << 2;

impl OutputData {
    /// Decodes the 14 bytes of the output assembly.
    pub fn decode(data: &[u8]) -> Self {
        let w = |i: usize| {
            data.get(2 * i..2 * i + 2)
                .and_then(|b| <[u8; 2]>::try_from(b).ok())
                .map_or(0, u16::from_le_bytes)
        };
        OutputData {
            bits: w(0),
            force: [w(1), w(2), w(3), w(4)],
            group_force: w(5),
            soft: w(6),
        }
    }

    /// The force code (0 unforce, 1 on, 2 off; 3 reserved = unforce) of output `o`.
    pub fn force_of(&self, o: usize) -> u16 {
        let word = self.force.get(o / 8).copied().unwrap_or(0);
        code((word >> (2 * (o % 8))) & 3)
    }

    /// The force code of group `g`.
    pub fn group_force_of(&self, g: usize) -> u16 {
        code((self.group_force >> (2 * (g % 8))) & 3)
    }
}

/// A 2-bit force code, reserved (3) read as unforce (\[R\]).
fn code(c: u16) -> u16 {
    if c == 3 {
        0
    } else {
        c
    }
}
