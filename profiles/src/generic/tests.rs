//! The generic profile through its Device hooks and the stack: the echo, sizes, the
//! configuration assembly, the scratch assembly.

use enip_stack::AssemblyRole;

use super::*;

fn read(dev: &mut Generic, instance: u16) -> CipResult<([u8; 64], usize)> {
    let mut buf = [0u8; 64];
    let size = dev
        .assemblies()
        .iter()
        .find(|a| a.instance == instance)
        .map_or(64, |a| usize::from(a.size));
    let n = dev.read_assembly(instance, &mut buf[..size])?;
    Ok((buf, n))
}

#[test]
fn declares_the_opener_sample_assemblies() {
    let dev = Generic::new();
    let list: [(u16, AssemblyRole, u16, bool); 6] = [
        (100, AssemblyRole::Input, 32, false),
        (150, AssemblyRole::Output, 32, true),
        (151, AssemblyRole::Config, 10, false),
        (152, AssemblyRole::InputOnlyHeartbeat, 0, false),
        (153, AssemblyRole::ListenOnlyHeartbeat, 0, false),
        (154, AssemblyRole::Explicit, 32, false),
    ];
    assert_eq!(dev.assemblies().len(), list.len());
    for (a, (instance, role, size, header)) in dev.assemblies().iter().zip(list) {
        assert_eq!(
            (a.instance, a.role, a.size, a.run_idle_header),
            (instance, role, size, header)
        );
    }
}

#[test]
fn output_is_echoed_into_input() {
    let mut dev = Generic::new();
    let data: [u8; 32] = core::array::from_fn(|i| i as u8 + 1);
    dev.write_assembly(OUTPUT, &data).unwrap();
    let (buf, n) = read(&mut dev, INPUT).unwrap();
    assert_eq!(&buf[..n], &data);
    let (buf, n) = read(&mut dev, OUTPUT).unwrap();
    assert_eq!(&buf[..n], &data);
}

#[test]
fn explicit_and_config_read_back_what_was_written() {
    let mut dev = Generic::new();
    dev.write_assembly(EXPLICIT, &[0xA5; 32]).unwrap();
    dev.write_assembly(CONFIG, &[7; 10]).unwrap();
    let (buf, n) = read(&mut dev, EXPLICIT).unwrap();
    assert_eq!(&buf[..n], &[0xA5; 32]);
    let (buf, n) = read(&mut dev, CONFIG).unwrap();
    assert_eq!(&buf[..n], &[7; 10]);
    // Neither touches the input data.
    let (buf, n) = read(&mut dev, INPUT).unwrap();
    assert_eq!(&buf[..n], &[0; 32]);
}

#[test]
fn heartbeats_are_empty() {
    let mut dev = Generic::new();
    for hb in [INPUT_ONLY_HEARTBEAT, LISTEN_ONLY_HEARTBEAT] {
        assert_eq!(read(&mut dev, hb).unwrap().1, 0);
        assert_eq!(dev.write_assembly(hb, &[]), Ok(()));
        assert_eq!(
            dev.write_assembly(hb, &[1]),
            Err(General::TooMuchData.into())
        );
    }
}

#[test]
fn wrong_sizes_and_instances_are_refused() {
    let mut dev = Generic::new();
    assert_eq!(
        dev.write_assembly(OUTPUT, &[1; 31]),
        Err(General::NotEnoughData.into())
    );
    assert_eq!(
        dev.write_assembly(OUTPUT, &[1; 33]),
        Err(General::TooMuchData.into())
    );
    assert_eq!(
        dev.write_assembly(INPUT, &[1; 32]),
        Err(General::AttributeNotSettable.into())
    );
    assert_eq!(dev.write_assembly(99, &[]), Err(unknown()));
    assert_eq!(read(&mut dev, 99).map(|r| r.1), Err(unknown()));
    // A refused write leaves the data alone.
    assert_eq!(read(&mut dev, INPUT).unwrap().0[..32], [0; 32]);
}

#[test]
fn identity_matches_the_constants() {
    let dev = Generic::new();
    let id = dev.identity();
    assert_eq!(
        (id.vendor_id, id.device_type, id.product_code),
        (1, 12, 65001)
    );
    assert_eq!(id.revision, (1, 1));
    assert_eq!(id.serial_number, 0x5255_5354);
    assert_eq!(id.product_name, "enip-rs generic");
}

#[test]
fn only_new_outputs_mark_the_input_changed() {
    let mut dev = Generic::new();
    let changed = |dev: &mut Generic| {
        let marks = dev.input_changes().unwrap();
        let any = !marks.is_empty();
        marks.clear();
        any
    };
    dev.write_assembly(OUTPUT, &[0; 32]).unwrap();
    assert!(!changed(&mut dev), "the same zeros");
    let mut data = [0u8; 32];
    data[31] = 1;
    dev.write_assembly(OUTPUT, &data).unwrap();
    assert!(changed(&mut dev), "the last byte differs");
    dev.write_assembly(OUTPUT, &data).unwrap();
    assert!(!changed(&mut dev), "the same again");
    // A short write changes nothing.
    assert!(dev.write_assembly(OUTPUT, &[9; 31]).is_err());
    assert!(!changed(&mut dev));
    assert_eq!(read(&mut dev, INPUT).unwrap().0[..32], data);
}

#[test]
fn copy_words_copies_and_says_whether_anything_changed() {
    let mut dst = [0u8; IO_SIZE];
    assert!(!copy_words(&mut dst, &[0; IO_SIZE]));
    for i in 0..IO_SIZE {
        let mut src = [0u8; IO_SIZE];
        src[i] = 0x80;
        assert!(copy_words(&mut dst, &src), "byte {i}");
        assert_eq!(dst, src);
        assert!(!copy_words(&mut dst, &src), "byte {i} again");
        dst = [0; IO_SIZE];
    }
}
