//! Explicit access to class 0x25 (Position Controller), class 0x24 (Position Controller
//! Supervisor) and class 0x0F (Parameter), with the manual's statuses.

use super::*;

#[test]
fn position_controller_statuses() {
    let mut b = Bench::new();
    let mut get = |a: u8| b.explicit(0x0E, 0x25, 1, Some(a), &[]);
    assert_eq!(get(1), (Ok(()), vec![17]));
    let (s, list) = get(2);
    s.unwrap();
    assert_eq!(
        list,
        [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 17, 22, 25, 58, 100, 101]
    );
    assert_eq!(get(3), (Ok(()), vec![0]));
    assert_eq!(get(4), (Ok(()), 65_536u32.to_le_bytes().to_vec()));
    assert_eq!(get(17), (Ok(()), vec![0]));
    assert_eq!(get(200).0, err(General::AttributeNotSupported));
    assert_eq!(get(101).0, err(General::AttributeNotGettable));
    let mut set = |a: u8, d: &[u8]| b.explicit(0x10, 0x25, 1, Some(a), d).0;
    assert_eq!(set(1, &[3]), err(General::AttributeNotSettable));
    assert_eq!(set(3, &[3]), err(General::InvalidAttributeValue));
    assert_eq!(
        set(4, &0i32.to_le_bytes()),
        err(General::InvalidAttributeValue)
    );
    assert_eq!(set(10, &[2]), err(General::InvalidAttributeValue));
    assert_eq!(set(3, &[1, 0]), err(General::TooMuchData));
    assert_eq!(set(6, &[1]), err(General::NotEnoughData));
    // HOME.MOVE needs the drive enabled (device state conflict otherwise).
    assert_eq!(set(101, &[1]), err(General::DeviceStateConflict));
    set(17, &[1]).unwrap();
    set(101, &[1]).unwrap();
    assert_eq!(b.explicit(0x0E, 0x25, 1, Some(17), &[]).1, [1]);
    b.run_ms(50);
    assert_ne!(b.response()[0] & status1::HOMED, 0);
    // Get_Attributes_All is not among the manual's services.
    assert_eq!(
        b.explicit(0x01, 0x25, 1, None, &[]).0,
        err(General::ServiceNotSupported)
    );
    // Instance 2 does not exist; class attributes answer.
    assert_eq!(
        b.explicit(0x0E, 0x25, 2, Some(3), &[]).0,
        err(General::ObjectDoesNotExist)
    );
    assert_eq!(
        b.explicit(0x0E, 0x25, 0, Some(1), &[]),
        (Ok(()), vec![1, 0])
    );
    // A class the drive does not have: 0x16, "Class Not Supported".
    assert_eq!(
        b.explicit(0x0E, 0x70, 1, Some(1), &[]).0,
        err(General::ObjectDoesNotExist)
    );
    // The stack's own objects still answer.
    assert!(b.explicit(0x0E, 0x01, 1, Some(7), &[]).0.is_ok());
}

#[test]
fn parameter_object() {
    let mut b = Bench::new();
    let mut get = |i: u16, a: u8| b.explicit(0x0E, 0x0F, i, Some(a), &[]);
    // AIN.CUTOFF: 4-byte float x1000, U32 type code.
    assert_eq!(get(1, 6), (Ok(()), vec![4]));
    assert_eq!(get(1, 5), (Ok(()), vec![0xC8]));
    assert_eq!(get(1, 1), (Ok(()), 5_000_000u32.to_le_bytes().to_vec()));
    // AIN.OFFSET: 2-byte signed; AIN.PSCALE 8 bytes, its lower 32 bits at 6.
    assert_eq!(get(4, 5), (Ok(()), vec![0xC3]));
    assert_eq!(get(5, 6), (Ok(()), vec![8]));
    assert_eq!(get(6, 6), (Ok(()), vec![4]));
    assert_eq!(get(205, 6), (Ok(()), vec![1]));
    assert_eq!(get(205, 1), (Ok(()), vec![0]));
    assert_eq!(get(12, 1).0, err(General::ObjectDoesNotExist));
    assert_eq!(get(1, 2).0, err(General::AttributeNotSupported));
    let mut set = |i: u16, d: &[u8]| b.explicit(0x10, 0x0F, i, Some(1), d).0;
    set(5, &(-7i64).to_le_bytes()).unwrap();
    set(4, &(-3i16).to_le_bytes()).unwrap();
    assert_eq!(set(1, &[1, 2]), err(General::NotEnoughData));
    assert_eq!(set(1, &[1, 2, 3, 4, 5]), err(General::TooMuchData));
    assert_eq!(set(7, &[0; 4]), err(General::AttributeNotSettable));
    assert_eq!(
        set(id::EIP_POSUNIT, &0u32.to_le_bytes()),
        err(General::InvalidAttributeValue)
    );
    // A 32-bit write to a 64-bit parameter.
    set(5, &(-9i32).to_le_bytes()).unwrap();
    assert_eq!(
        b.explicit(0x0E, 0x0F, 5, Some(1), &[]).1,
        (-9i64).to_le_bytes()
    );
    assert_eq!(
        b.explicit(0x0E, 0x0F, 6, Some(1), &[]).1,
        (-9i32).to_le_bytes()
    );
    assert_eq!(
        b.explicit(0x0E, 0x0F, 4, Some(1), &[]).1,
        (-3i16).to_le_bytes()
    );
    // EIP.PROFUNIT is attribute 5.
    b.explicit(
        0x10,
        0x0F,
        id::EIP_PROFUNIT,
        Some(1),
        &1000u32.to_le_bytes(),
    )
    .0
    .unwrap();
    assert_eq!(
        b.explicit(0x0E, 0x25, 1, Some(5), &[]).1,
        1000u32.to_le_bytes()
    );
    // HOME.MOVE (205): "class 0x0F, instance 205, attribute 1, length 1, value 1".
    b.send(cmd(EN, 0x21, 0x20, 0));
    b.explicit(0x10, 0x0F, 205, Some(1), &[1]).0.unwrap();
    assert_ne!(b.run_ms(100)[0] & status1::HOMED, 0);
    assert_eq!(
        b.explicit(0x0E, 0x0F, id::DRV_MOTIONSTAT, Some(1), &[]).1,
        6u32.to_le_bytes()
    );
}

#[test]
fn position_controller_supervisor_answers() {
    let mut b = Bench::new();
    let get = |b: &mut Bench, a: u8| b.explicit(0x0E, 0x24, 1, Some(a), &[]);
    assert_eq!(get(&mut b, 1), (Ok(()), vec![6]));
    assert_eq!(get(&mut b, 2), (Ok(()), vec![1, 2, 3, 5, 6, 7]));
    assert_eq!(get(&mut b, 3), (Ok(()), vec![1]));
    assert_eq!(get(&mut b, 5), (Ok(()), vec![0]));
    // The last command assembly's command and response types.
    b.send(cmd(EN, 0x26, 0x25, 0));
    assert_eq!(get(&mut b, 6), (Ok(()), vec![0x06]));
    assert_eq!(get(&mut b, 7), (Ok(()), vec![0x05]));
    // A move before homing faults: General Fault follows Status Word 1 bit 3.
    b.send(motion(EN | LOAD, 0x26, 100, 1000, 10_000, 10_000));
    assert_eq!(get(&mut b, 5), (Ok(()), vec![1]));
    assert_eq!(get(&mut b, 4).0, err(General::AttributeNotSupported));
    assert_eq!(
        b.explicit(0x10, 0x24, 1, Some(6), &[1]).0,
        err(General::AttributeNotSettable)
    );
    assert_eq!(
        b.explicit(0x0E, 0x24, 2, Some(1), &[]).0,
        err(General::ObjectDoesNotExist)
    );
}

#[test]
fn jog_velocity_attribute_22_drives_velocity_mode_starts() {
    let mut b = Bench::new();
    assert_eq!(
        b.explicit(0x0E, 0x25, 1, Some(22), &[]),
        (Ok(()), 65_536i32.to_le_bytes().to_vec())
    );
    b.explicit(0x10, 0x25, 1, Some(3), &[1]).0.unwrap();
    b.explicit(0x10, 0x25, 1, Some(22), &(-2000i32).to_le_bytes())
        .0
        .unwrap();
    // Attribute 7 stays what it was; a start through attribute 11 jogs at attribute 22.
    b.send(cmd(EN, 0x21, 0x23, 0));
    b.explicit(0x10, 0x25, 1, Some(11), &[1]).0.unwrap();
    let r = b.run_ms(100);
    assert_eq!(dint(&r, 12), -2000);
    // Beyond the velocity limit: 0x09.
    assert_eq!(
        b.explicit(0x10, 0x25, 1, Some(22), &i32::MAX.to_le_bytes())
            .0,
        err(General::InvalidAttributeValue)
    );
}

#[test]
fn identity_names_kollmorgen_vendor_452() {
    let mut b = Bench::new();
    assert_eq!(
        b.explicit(0x0E, 0x01, 1, Some(1), &[]),
        (Ok(()), 452u16.to_le_bytes().to_vec())
    );
}
