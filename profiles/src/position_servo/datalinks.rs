//! DataLinks (5.4, tables 10-13): variables 261-264 point input assembly 105 words 5-8 at
//! any variable, 265-268 point output assembly 108 words 2-5 at any variable.
//!
//! A control word holds the enable bit (31), the format bit (30: 0 U32, 1 F32), reserved
//! bits 29-16 (zero) and the variable ID (bits 15-0). A disabled input link reads 0; a
//! disabled output link ignores its word. Output links write the RAM copy only: DataLinks
//! never write to the EPM (6, STOP note).

use super::device::Servo;
use super::params::{self, id, Link, Value, Variables};

/// Number of input links and of output links.
pub const LINKS: usize = 4;

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
pub fn write(servo: &mut Servo, control: u16, word: [u8; 4]) {
    let link = Link::decode(servo.vars.raw(control));
    if !link.enabled {
        return;
    }
    let value = if link.real {
        Value::Real(f32::from_le_bytes(word))
    } else {
        Value::Integer(u32::from_le_bytes(word))
    };
    // Refused values leave the variable as it was, as for a refused O->T datagram.
    let _ = servo.write(link.id, value, None);
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
        let mut servo = Servo::power_up(|_| None);
        servo.write(id::V0, Value::Real(2.75), None).unwrap();
        // Default: link A is V0 as REAL.
        assert_eq!(read(&servo.vars, input(0)), 2.75f32.to_le_bytes());
        servo
            .write(input(0), Value::Integer(0x8000_0064), None)
            .unwrap();
        assert_eq!(read(&servo.vars, input(0)), 3u32.to_le_bytes());
        servo.write(input(0), Value::Integer(0x64), None).unwrap();
        assert_eq!(read(&servo.vars, input(0)), [0; 4]);
        servo
            .write(input(1), Value::Integer(0xC000_00BC), None)
            .unwrap();
        servo
            .write(id::DRIVE_MODE, Value::Integer(1), None)
            .unwrap();
        servo.write(id::ENABLE, Value::Integer(1), None).unwrap();
        servo.drive.poll(enip_stack::Instant(0), &mut servo.vars);
        let current = servo.vars.real(id::PHASE_CURRENT);
        assert!(current > 0.0);
        assert_eq!(read(&servo.vars, input(1)), current.to_le_bytes());
    }

    #[test]
    fn output_links_write_their_variable_in_their_format() {
        let mut servo = Servo::power_up(|_| None);
        // Default: link A writes V4 as REAL.
        write(&mut servo, output(0), 1.5f32.to_le_bytes());
        assert_eq!(servo.vars.real(id::V0 + 4), 1.5);
        servo
            .write(
                output(1),
                Value::Integer(0x8000_0000 | u32::from(id::V0)),
                None,
            )
            .unwrap();
        write(&mut servo, output(1), 9u32.to_le_bytes());
        assert_eq!(servo.vars.real(id::V0), 9.0);
        // Disabled: ignored.
        servo.write(output(2), Value::Integer(0x65), None).unwrap();
        write(&mut servo, output(2), 4.0f32.to_le_bytes());
        assert_eq!(servo.vars.real(id::V0 + 1), 0.0);
        // A read-only target refuses the value; nothing changes.
        servo
            .write(
                output(3),
                Value::Integer(0xC000_0000 | u32::from(id::STATUS)),
                None,
            )
            .unwrap();
        write(&mut servo, output(3), 4.0f32.to_le_bytes());
        assert_eq!(servo.vars.raw(id::STATUS) & 1, 0);
    }
}
