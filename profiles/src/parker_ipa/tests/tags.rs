//! The tag services through the stack: the manual's figures 1 and 2, conversion and masks,
//! and every error case of a symbolic path.

use super::*;

#[test]
fn figure_1_data_table_read_and_figure_2_write() {
    let mut ipa = ParkerIpa::new();
    run(&mut ipa, &req(0x52, 0x64, 4112, &longs(&[7, -8, 9])));
    let bytes = [
        0x4C, 0x04, 0x91, 0x05, 0x50, 0x34, 0x31, 0x31, 0x32, 0x00, 0x03, 0x00,
    ];
    let mut expected = vec![0xCC, 0, 0, 0, 0xC4, 0];
    expected.extend(longs(&[7, -8, 9]));
    assert_eq!(raw(&mut ipa, &bytes), expected);
    assert_eq!(read_longs(&mut ipa, 4112, 3), [7, -8, 9]);
    let mut write = vec![
        0x4D, 0x04, 0x91, 0x05, 0x50, 0x34, 0x31, 0x30, 0x30, 0x00, 0xC4, 0, 1, 0,
    ];
    write.extend(longs(&[0x0BAD_CAFE]));
    assert_eq!(raw(&mut ipa, &write), [0xCD, 0, 0, 0]);
    assert_eq!(read_longs(&mut ipa, 4100, 1), [0x0BAD_CAFE]);
}

#[test]
fn tag_services_convert_and_mask() {
    let mut ipa = ParkerIpa::new();
    // 0x4D REAL 77.0 to a long, DINT -3 to a float.
    let mut w = vec![0xCA, 0, 1, 0];
    w.extend(floats(&[77.0]));
    assert_eq!(run(&mut ipa, &tag(0x4D, "P39001", &w)).0, 0);
    assert_eq!(read_longs(&mut ipa, 39001, 1), [77]);
    let mut w = vec![0xC4, 0, 1, 0];
    w.extend(longs(&[-3]));
    assert_eq!(run(&mut ipa, &tag(0x4D, "P39201", &w)).0, 0);
    assert_eq!(read_floats(&mut ipa, 39201, 1), [-3.0]);
    // 0x4C of a float holding 99.75: type C4, 99.
    run(&mut ipa, &req(0x50, 0x64, 39202, &floats(&[99.75])));
    assert_eq!(
        run(&mut ipa, &tag(0x4C, "P39202", &[1, 0])).2,
        [0xC4, 0, 99, 0, 0, 0]
    );
    // 0x48 of four floats.
    run(
        &mut ipa,
        &req(0x50, 0x64, 39200, &floats(&[1.5, -2.5, 3.25, 4.0])),
    );
    let mut expected = vec![0xCA, 0];
    expected.extend(floats(&[1.5, -2.5, 3.25, 4.0]));
    assert_eq!(run(&mut ipa, &tag(0x48, "P39200", &[4, 0])).2, expected);
    // 0x4E on 0x1234ABCD: AND 0xFFFF00FF, OR 0x55.
    run(&mut ipa, &req(0x52, 0x64, 4101, &longs(&[0x1234ABCD])));
    let masks = longs(&[0xFFFF00FFu32 as i32, 0x55]);
    assert_eq!(run(&mut ipa, &tag(0x4E, "P4101", &masks)).0, 0);
    assert_eq!(read_longs(&mut ipa, 4101, 1), [0x123400DD]);
    assert_eq!(run(&mut ipa, &tag(0x4E, "P4101", &masks[..4])).0, 0x13);
    // Lower-case p, and the 0x4C read equals the 0x53 read.
    let (g, _, d) = run(&mut ipa, &tag(0x4C, "p4360", &[3, 0]));
    assert_eq!(g, 0);
    assert_eq!(d[2..], longs(&read_longs(&mut ipa, 4360, 3))[..]);
    // A tag write of 16 values reads back through class 0x64.
    let mut w = vec![0xC4, 0, 16, 0];
    w.extend(longs(&[42; 16]));
    assert_eq!(run(&mut ipa, &tag(0x4D, "P38920", &w)).0, 0);
    assert_eq!(read_longs(&mut ipa, 38920, 16), [42; 16]);
}

#[test]
fn tag_errors() {
    let mut ipa = ParkerIpa::new();
    let g = |ipa: &mut ParkerIpa, b: Vec<u8>| run(ipa, &b).0;
    // Cases 3 and 4, with the target unchanged.
    assert_eq!(g(&mut ipa, tag(0x4C, "P4096", &[17, 0])), 0x20);
    assert_eq!(g(&mut ipa, tag(0x48, "P39200", &[17, 0])), 0x20);
    assert_eq!(g(&mut ipa, tag(0x4C, "P4096", &[0, 0])), 0x20);
    let mut w = vec![0xC4, 0, 17, 0];
    w.extend(longs(&[9; 17]));
    assert_eq!(g(&mut ipa, tag(0x4D, "P38912", &w)), 0x15);
    assert_eq!(read_longs(&mut ipa, 38912, 1), [0]);
    // Type, length and count errors.
    assert_eq!(
        g(&mut ipa, tag(0x4D, "P38912", &[0xC3, 0, 1, 0, 1, 0, 0, 0])),
        0x20
    );
    assert_eq!(
        g(&mut ipa, tag(0x4D, "P38912", &[0xC4, 0, 2, 0, 1, 0, 0, 0])),
        0x13
    );
    assert_eq!(
        g(
            &mut ipa,
            tag(0x4D, "P38912", &[0xC4, 0, 1, 0, 1, 0, 0, 0, 0])
        ),
        0x15
    );
    assert_eq!(g(&mut ipa, tag(0x4D, "P38912", &[0xC4, 0])), 0x13);
    assert_eq!(g(&mut ipa, tag(0x4C, "P38912", &[])), 0x13);
    // Names: malformed 0x04, unknown parameter 0x05.
    for name in ["X4012", "P", "P123456", "P65536", "P40a2", "Pump"] {
        assert_eq!(g(&mut ipa, tag(0x4C, name, &[1, 0])), 0x04, "{name}");
    }
    assert_eq!(g(&mut ipa, tag(0x4C, "P10", &[1, 0])), 0x05);
    assert_eq!(g(&mut ipa, tag(0x4C, "P65535", &[1, 0])), 0x05);
    assert_eq!(g(&mut ipa, tag(0x4C, "P39423", &[2, 0])), 0x05);
    // A member segment after the name.
    let mut b = tag(0x4C, "P4096", &[]);
    b[1] += 1;
    b.extend_from_slice(&[0x28, 0x01, 1, 0]);
    assert_eq!(g(&mut ipa, b), 0x04);
    // Other services on a tag.
    assert_eq!(g(&mut ipa, tag(0x0E, "P4096", &[])), 0x08);
    assert_eq!(g(&mut ipa, tag(0x52, "P4096", &[1, 0, 0, 0])), 0x08);
}
