//! DataLinks (5.4, tables 10-13): variables 261-264 point input assembly 105 words 5-8 at
//! any variable, 265-268 point output assembly 108 words 2-5 at any variable.
//!
//! A control word holds the enable bit (31), the format bit (30: 0 U32, 1 F32), reserved
//! bits 29-16 (zero) and the variable ID (bits 15-0). A disabled input link reads 0; a
//! disabled output link ignores its word. Output links write the RAM copy only: DataLinks
//! never write to the EPM (6, STOP note).

use super::params::{self, id, Value, Variables};
use super::PositionServo;

/// Number of input links and of output links.
pub const LINKS: usize = 4;

/// A decoded DataLink control word.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Link {
    /// Bit 31: the link transfers data.
    pub enabled: bool,
    /// Bit 30: REAL (F32) rather than integer (U32).
    pub real: bool,
    /// Bits 15-0: the linked variable.
    pub id: u16,
}

impl Link {
    /// Bits 29-16, which must be zero.
    pub const RESERVED: u32 = 0x3FFF_0000;
    const ENABLE: u32 = 1 << 31;
    const REAL: u32 = 1 << 30;

    /// Decodes a control word (the reserved bits are ignored).
    pub const fn decode(control: u32) -> Self {
        Link {
            enabled: control & Self::ENABLE != 0,
            real: control & Self::REAL != 0,
            id: control as u16,
        }
    }

    /// The control word for this link.
    pub const fn encode(self) -> u32 {
        (if self.enabled { Self::ENABLE } else { 0 })
            | (if self.real { Self::REAL } else { 0 })
            | self.id as u32
    }
}

/// The control variable of input link `n` (0 = A).
pub const fn input(n: usize) -> u16 {
    id::LINK_A_IN.saturating_add(n as u16)
}

/// The control variable of output link `n` (0 = A).
pub const fn output(n: usize) -> u16 {
    id::LINK_A_OUT.saturating_add(n as u16)
}

/// The 4 bytes a link with control variable `control` carries: the linked variable in the
/// link's format, or zero when disabled or unknown.
pub fn read(vars: &Variables, control: u16) -> [u8; 4] {
    let link = Link::decode(vars.raw(control));
    match params::find(link.id) {
        Some((_, v)) if link.enabled => {
            let raw = vars.raw(link.id);
            if link.real {
                v.real(raw).to_le_bytes()
            } else {
                v.int_bits(raw).to_le_bytes()
            }
        }
        _ => [0; 4],
    }
}

/// Writes `word` through the output link with control variable `control`. A disabled link,
/// or a value the variable refuses, changes nothing (like any refused O->T data).
pub fn write(servo: &mut PositionServo, control: u16, word: [u8; 4]) {
    let link = Link::decode(servo.variables().raw(control));
    if !link.enabled {
        return;
    }
    let value = if link.real {
        Value::Real(f32::from_le_bytes(word))
    } else {
        Value::Integer(u32::from_le_bytes(word))
    };
    // Refused values leave the variable as it was, as for a refused O->T datagram.
    let _ = servo.write(link.id, value, false);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_13_example_control_word() {
        let link = Link::decode(0xC000_00BC);
        assert_eq!(
            link,
            Link {
                enabled: true,
                real: true,
                id: 188
            }
        );
        assert_eq!(link.encode(), 0xC000_00BC);
        assert!(!Link::decode(0x8000_0041).real);
        assert!(!Link::decode(0x4000_0041).enabled);
    }

    #[test]
    fn input_links_carry_the_linked_variable_in_their_format() {
        let mut servo = PositionServo::new();
        servo.write(id::V0, Value::Real(2.75), false).unwrap();
        // Default: link A is V0 as REAL.
        assert_eq!(read(servo.variables(), input(0)), 2.75f32.to_le_bytes());
        servo
            .write(input(0), Value::Integer(0x8000_0064), false)
            .unwrap();
        assert_eq!(read(servo.variables(), input(0)), 3u32.to_le_bytes());
        servo.write(input(0), Value::Integer(0x64), false).unwrap();
        assert_eq!(read(servo.variables(), input(0)), [0; 4]);
        servo
            .write(input(1), Value::Integer(0xC000_00BC), false)
            .unwrap();
        servo
            .write(id::DRIVE_MODE, Value::Integer(1), false)
            .unwrap();
        servo.write(id::ENABLE, Value::Integer(1), false).unwrap();
        enip_stack::Device::poll(&mut servo, enip_stack::Instant(0));
        let current = servo.variables().real(id::PHASE_CURRENT);
        assert!(current > 0.0);
        assert_eq!(read(servo.variables(), input(1)), current.to_le_bytes());
    }

    #[test]
    fn output_links_write_their_variable_in_their_format() {
        let mut servo = PositionServo::new();
        // Default: link A writes V4 as REAL.
        write(&mut servo, output(0), 1.5f32.to_le_bytes());
        assert_eq!(servo.variables().real(id::V0 + 4), 1.5);
        servo
            .write(
                output(1),
                Value::Integer(0x8000_0000 | u32::from(id::V0)),
                false,
            )
            .unwrap();
        write(&mut servo, output(1), 9u32.to_le_bytes());
        assert_eq!(servo.variables().real(id::V0), 9.0);
        // Disabled: ignored.
        servo.write(output(2), Value::Integer(0x65), false).unwrap();
        write(&mut servo, output(2), 4.0f32.to_le_bytes());
        assert_eq!(servo.variables().real(id::V0 + 1), 0.0);
        // A read-only target refuses the value; nothing changes.
        servo
            .write(
                output(3),
                Value::Integer(0xC000_0000 | u32::from(id::STATUS)),
                false,
            )
            .unwrap();
        write(&mut servo, output(3), 4.0f32.to_le_bytes());
        assert_eq!(servo.variables().raw(id::STATUS) & 1, 0);
    }
}
