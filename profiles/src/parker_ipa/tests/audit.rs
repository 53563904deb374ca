//! Findings of the audit against the manual (88-032525-01 A), one test each.

use super::*;

/// A request to `class`/`instance` with a 32-bit instance segment (`25` is 16-bit, `26`
/// 32-bit) and attribute 1.
fn req32(service: u8, class: u8, instance: u32, data: &[u8]) -> Vec<u8> {
    let i = instance.to_le_bytes();
    let mut v = vec![
        service, 5, 0x20, class, 0x26, 0x00, i[0], i[1], i[2], i[3], 0x30, 0x01,
    ];
    v.extend_from_slice(data);
    v
}

/// Table 8 (p.30): an instance that "is not known" is 0x05, Path destination unknown, the
/// only code the manual gives for it; the instance of class 0x64 is a P number, and one
/// above 65535 does not exist (no P number has more than 16 bits). Was 0x16 from the
/// stack, which is not in Table 8. Class 0x65 alike: its instance decodes to a group code
/// outside 0x80-0xBF, a valid code (p.28), whose first element does not exist.
#[test]
fn an_instance_above_65535_is_an_unknown_parameter() {
    let mut ipa = ParkerIpa::new();
    let count = 1i32.to_le_bytes();
    for (service, class) in [(0x53, 0x64), (0x51, 0x64), (0x53, 0x65)] {
        let (g, n, _) = run(&mut ipa, &req32(service, class, 70_000, &count));
        assert_eq!((g, n), (0x05, 0), "{service:#04x} on {class:#04x}");
    }
    let (g, _, _) = run(&mut ipa, &req32(0x52, 0x64, 0x1_0000 + 4100, &longs(&[9])));
    assert_eq!(g, 0x05);
    assert_eq!(read_longs(&mut ipa, 4100, 1), [0]);
    // The 32-bit segment itself is fine: P4360 through it reads as through a 16-bit one.
    let (g, _, d) = run(&mut ipa, &req32(0x53, 0x64, 4360, &count));
    assert_eq!((g, d), (0, longs(&[1630535712])));
}
