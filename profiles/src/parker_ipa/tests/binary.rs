//! Class 0x65 service 0x34: the ACR binary commands of Table 7, in the formats of the
//! *ACR Programmer's Guide* ("Binary Host Interface"), run on the simulated parameters.

extern crate std;

use std::vec::Vec;

use super::super::classes::binary::execute;
use super::super::params::Value;
use super::super::ParkerIpa;

/// Runs binary packet `data`; the CIP general status (0 = done).
fn send(ipa: &mut ParkerIpa, data: &[u8]) -> u8 {
    match execute(&mut ipa.memory, data) {
        Ok(()) => 0,
        Err(e) => e.general as u8,
    }
}

fn cat(parts: &[&[u8]]) -> Vec<u8> {
    parts.concat()
}

#[test]
fn set_long_set_ieee_parameter_mask_set_and_clr() {
    let mut ipa = ParkerIpa::new();
    // Set Long P38912 = -5 (00 89, index 0x9800).
    assert_eq!(
        send(
            &mut ipa,
            &cat(&[&[0x00, 0x89, 0x00, 0x98], &(-5i32).to_le_bytes()])
        ),
        0
    );
    assert_eq!(ipa.get(38912), Some(Value::Long(-5)));
    // Set IEEE P12348 (axis 0 JOG VEL, 0x303C) = 15.0.
    assert_eq!(
        send(
            &mut ipa,
            &cat(&[&[0x00, 0x8B, 0x3C, 0x30], &15.0f32.to_le_bytes()])
        ),
        0
    );
    assert_eq!(ipa.get(12348), Some(Value::Float(15.0)));
    // Set Long on a float parameter converts, as 0x52 does.
    assert_eq!(
        send(
            &mut ipa,
            &cat(&[&[0x00, 0x89, 0x3D, 0x30], &7i32.to_le_bytes()])
        ),
        0
    );
    assert_eq!(ipa.get(12349), Some(Value::Float(7.0)));
    // The Guide's Parameter Mask example: P4097 cleared, then bit 0 set.
    ipa.set(4097, Value::Long(0x7F00));
    let mask = [
        0x00, 0x95, 0x01, 0x10, 0xFF, 0xFF, 0xFF, 0xFF, 0x01, 0x00, 0x00, 0x00,
    ];
    assert_eq!(send(&mut ipa, &mask), 0);
    assert_eq!(ipa.get(4097), Some(Value::Long(1)));
    // The Guide's SET/CLR examples: set bit 520 (P4112 bit 8), clear bit 32 (P4097 bit 0),
    // two commands in one packet.
    assert_eq!(send(&mut ipa, &[0x1C, 0x08, 0x02, 0x1D, 0x20, 0x00]), 0);
    assert_eq!(ipa.get(4112), Some(Value::Long(0x100)));
    assert_eq!(ipa.get(4097), Some(Value::Long(0)));
    // SET of bit 8464 (P4360 bit 16): axis 0 jogs forward.
    assert_eq!(send(&mut ipa, &[0x1C, 0x10, 0x21]), 0);
    assert_eq!(ipa.get(4360), Some(Value::Long(1630535712 | 1 << 16)));
}

#[test]
fn unsupported_truncated_and_invalid_commands_change_nothing() {
    let mut ipa = ParkerIpa::new();
    let set = cat(&[&[0x00, 0x89, 0x00, 0x98], &9i32.to_le_bytes()]);
    // Table 7 "No": Get Long, Get IEEE, Peek, Poke, Address, Parameter Address, Mask and
    // data packets; "Yes" but not simulated: Move, FOV, ROV; unknown headers: all 0x08,
    // even after a good command.
    for bad in [
        &[0x00, 0x88, 0x00, 0x98][..],
        &[0x00, 0x8A, 0x00, 0x98],
        &[0x00, 0x90, 0, 0, 0, 0, 0, 0],
        &[0x00, 0x91, 0, 0, 0, 0, 0, 0],
        &[0x00, 0x92, 0x00, 0x02],
        &[0x00, 0x93, 0x00, 0x30],
        &[0x00, 0x94, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
        &[0x00, 0x18, 0x00, 0xFF],
        &[0x04, 0, 0, 0, 0, 0, 0, 0, 0],
        &[0x07, 0x01, 0, 0, 0, 0, 0x80, 0x3F],
        &[0x08, 0x01, 0, 0, 0, 0, 0x80, 0x3F],
        &[0x42],
    ] {
        assert_eq!(send(&mut ipa, bad), 0x08, "{bad:02X?}");
        assert_eq!(send(&mut ipa, &cat(&[&set, bad])), 0x08, "{bad:02X?}");
    }
    // A packet ending inside a command, or empty: 0x13.
    assert_eq!(send(&mut ipa, &set[..7]), 0x13);
    assert_eq!(send(&mut ipa, &cat(&[&set, &[0x1C, 0x08]])), 0x13);
    assert_eq!(send(&mut ipa, &[]), 0x13);
    // A parameter that does not exist (P10 is not dimensioned, P20000), a mask on a float,
    // a bit past the flags (16384): 0x20.
    assert_eq!(
        send(&mut ipa, &cat(&[&[0x00, 0x89, 0x0A, 0x00], &[0; 4]])),
        0x20
    );
    assert_eq!(
        send(&mut ipa, &cat(&[&set, &[0x00, 0x8B, 0x20, 0x4E], &[0; 4]])),
        0x20
    );
    assert_eq!(
        send(&mut ipa, &cat(&[&[0x00, 0x95, 0x3C, 0x30], &[0; 8]])),
        0x20
    );
    assert_eq!(send(&mut ipa, &[0x1C, 0x00, 0x40]), 0x20);
    // None of it ran.
    assert_eq!(ipa.get(38912), Some(Value::Long(0)));
    assert_eq!(ipa, ParkerIpa::new());
}
