//! The profile as a scanner sees it through the stack (`Adapter::execute`): every
//! attribute's size, the manual's examples of §2.3-2.10 and every validation rule of the
//! digest with its CIP status and input words 15-17, the assemblies, and program control.

mod class1;
mod device;
mod inputs;

extern crate std;

use core::net::Ipv4Addr;
use std::vec;
use std::vec::Vec;

use enip_stack::{Adapter, Device, Instant, NetworkConfig};

use enip_stack::nv::{CutFlash, SharedStore};

use super::storage::Nvram;
use super::{identity, AmetekPls};
use crate::storage::testing;

/// Message Router request bytes: 8-bit class and instance, optional attribute, data.
pub fn request(
    service: u8,
    class: u8,
    instance: u8,
    attribute: Option<u8>,
    data: &[u8],
) -> Vec<u8> {
    let mut path = vec![0x20, class, 0x24, instance];
    if let Some(a) = attribute {
        path.extend_from_slice(&[0x30, a]);
    }
    let mut out = vec![service, (path.len() / 2) as u8];
    out.extend(path);
    out.extend_from_slice(data);
    out
}

/// Runs request `bytes` against `pls` through the stack; the general status and data.
pub fn execute(pls: &mut AmetekPls, bytes: &[u8]) -> (u8, Vec<u8>) {
    let net = NetworkConfig::new_static(
        Ipv4Addr::new(198, 18, 0, 2),
        Ipv4Addr::new(255, 255, 255, 0),
        [2, 0, 0, 0, 0, 1],
    );
    let mut adapter = Adapter::new(core::mem::take(pls), net, 1);
    let mut buf = [0u8; 600];
    let n = adapter.execute(bytes, Instant(0), &mut buf);
    *pls = adapter.into_device();
    let reply = &buf[..n];
    let additional = 2 * usize::from(reply[3]);
    (reply[2], reply[4 + additional..].to_vec())
}

/// Little-endian bytes of `words`.
pub fn le(words: &[u16]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

/// Words of little-endian `bytes`.
pub fn words(bytes: &[u8]) -> Vec<u16> {
    bytes
        .chunks_exact(2)
        .map(|b| u16::from_le_bytes([b[0], b[1]]))
        .collect()
}

fn get(pls: &mut AmetekPls, class: u8, attribute: u8) -> Vec<u8> {
    let (s, d) = execute(pls, &request(0x0E, class, 1, Some(attribute), &[]));
    assert_eq!(s, 0, "Get 0x{class:02X}/{attribute}");
    d
}

/// Set_Attribute_Single of class 0xC1 attribute `a` with `w`; the general status.
pub fn set(pls: &mut AmetekPls, a: u8, w: &[u16]) -> u8 {
    execute(pls, &request(0x10, 0xC1, 1, Some(a), &le(w))).0
}

/// The input assembly's words (Get of 100 attribute 3).
pub fn input(pls: &mut AmetekPls) -> Vec<u16> {
    let (s, d) = execute(pls, &request(0x0E, 0x04, 100, Some(3), &[]));
    assert_eq!(s, 0);
    words(&d)
}

/// Writes the output assembly (Set of 150 attribute 3); the general status.
pub fn output(pls: &mut AmetekPls, w: [u16; 7]) -> u8 {
    execute(pls, &request(0x10, 0x04, 150, Some(3), &le(&w))).0
}

/// Input words 15-17.
fn error(pls: &mut AmetekPls) -> [u16; 3] {
    let w = input(pls);
    [w[14], w[15], w[16]]
}

/// An Acknowledge pulse (0 -> 1 -> 0) through the output assembly.
fn acknowledge(pls: &mut AmetekPls) {
    assert_eq!(output(pls, [0; 7]), 0);
    assert_eq!(output(pls, [4, 0, 0, 0, 0, 0, 0]), 0);
    assert_eq!(output(pls, [0; 7]), 0);
}

/// §4.1's valid PLS object: group 1 SF 360, outputs 1 and 17, input 9; groups 2-8 SF 360.
pub fn pls_object() -> [u16; 48] {
    let mut w = [0u16; 48];
    for g in 0..8 {
        w[6 * g] = 360;
    }
    w[1] = 0x0001;
    w[2] = 0x0001;
    w[3] = 0x0100;
    w
}

/// §4.2's output 1: no compensation, 2 standard setpoints 100-200 and 300-330.
pub fn output_1() -> [u16; 26] {
    let mut w = [0u16; 26];
    w[6] = 2;
    w[7] = 1;
    w[8] = 100;
    w[9] = 200;
    w[12] = 300;
    w[13] = 330;
    w
}

/// §4.3's output 17: 1 standard setpoint 50-60.
pub fn output_17() -> [u16; 20] {
    let mut w = [0u16; 20];
    w[0] = 1;
    w[1] = 1;
    w[2] = 50;
    w[3] = 60;
    w
}

/// A module with the PLS object, output 1 and output 17 programmed.
pub fn programmed() -> AmetekPls {
    let mut pls = AmetekPls::new();
    assert_eq!(set(&mut pls, 1, &pls_object()), 0);
    assert_eq!(set(&mut pls, 2, &output_1()), 0);
    assert_eq!(set(&mut pls, 18, &output_17()), 0);
    pls
}

/// A violation: the Set answers `status` and input words 15-17 read `expected`; the
/// attribute is unchanged; an Acknowledge clears the words.
fn refused(pls: &mut AmetekPls, a: u8, w: &[u16], status: u8, expected: [u16; 3]) {
    let before = get(pls, 0xC1, a);
    assert_eq!(set(pls, a, w), status, "attribute {a}: {expected:?}");
    assert_eq!(error(pls), expected, "attribute {a}");
    assert_eq!(get(pls, 0xC1, a), before, "a refused Set changes nothing");
    acknowledge(pls);
    assert_eq!(error(pls), [0; 3]);
}

/// A violation case: (1-based word, value) edits, and the expected words 15-17.
type Case = (&'static [(usize, u16)], [u16; 3]);

#[test]
fn every_attribute_has_the_manuals_size() {
    let mut pls = AmetekPls::new();
    for (a, size) in [(1, 4), (2, 96), (3, 48)] {
        assert_eq!(get(&mut pls, 0xC0, a).len(), size, "0xC0/{a}");
    }
    for a in 1..=38u8 {
        let size = match a {
            1 => 96,
            2..=17 => 52,
            18..=33 => 40,
            34 => 224,
            35 => 6,
            36 => 18,
            _ => 4,
        };
        assert_eq!(get(&mut pls, 0xC1, a).len(), size, "0xC1/{a}");
    }
}

#[test]
fn identity_revision_is_the_software_version() {
    let mut pls = AmetekPls::new();
    let (major, minor) = identity::SOFTWARE_VERSION;
    assert_eq!(words(&get(&mut pls, 0xC0, 1)), [major.into(), minor.into()]);
    assert_eq!(pls.identity().revision, (major, minor));
    assert!(pls.identity().product_name.contains("7500"));
    let (s, d) = execute(&mut pls, &request(0x0E, 0x01, 1, Some(7), &[]));
    assert_eq!(s, 0);
    assert_eq!(&d[1..], b"7500 PLS");
}

#[test]
fn power_up_defaults() {
    let mut pls = AmetekPls::new();
    let w = words(&get(&mut pls, 0xC1, 1));
    for g in 0..8 {
        assert_eq!(w[6 * g..6 * g + 6], [360, 0, 0, 0, 0, 0]);
    }
    assert_eq!(input(&mut pls), [0; 17]);
    assert_eq!(get(&mut pls, 0xC1, 36), [0; 18]);
}

#[test]
fn pls_object_example_reads_back() {
    let mut pls = AmetekPls::new();
    assert_eq!(set(&mut pls, 1, &pls_object()), 0);
    assert_eq!(get(&mut pls, 0xC1, 1), le(&pls_object()));
    assert_eq!(error(&mut pls), [0; 3]);
}

#[test]
fn pls_object_violations() {
    let mut pls = programmed();
    let with = |edits: &[(usize, u16)]| {
        let mut w = pls_object();
        for &(i, v) in edits {
            w[i - 1] = v;
        }
        w
    };
    let cases: [Case; 8] = [
        (&[(1, 1)], [1, 1, 1]),
        (&[(7, 0)], [1, 1, 7]),
        (&[(8, 0x0001)], [2, 1, 8]),
        (&[(9, 0x0001)], [2, 1, 9]),
        (&[(10, 0x0100)], [2, 1, 10]),
        (&[(5, 2049)], [1, 1, 5]),
        (&[(6, 0x0002)], [1, 1, 6]),
        // A range error wins over an earlier conflict (code 1 before code 2).
        (&[(8, 0x0001), (47, 2049)], [1, 1, 47]),
    ];
    for (edits, expected) in cases {
        refused(&mut pls, 1, &with(edits), 0x09, expected);
    }
    // Min speed 2048 is the largest valid value; the mask may name the group's outputs.
    assert_eq!(set(&mut pls, 1, &with(&[(5, 2048), (6, 0x0001)])), 0);
}

#[test]
fn high_speed_output_example_and_violations() {
    let mut pls = programmed();
    assert_eq!(get(&mut pls, 0xC1, 2), le(&output_1()));
    let with = |edits: &[(usize, u16)]| {
        let mut w = output_1();
        for &(i, v) in edits {
            w[i - 1] = v;
        }
        w
    };
    let cases: [Case; 10] = [
        (&[(4, 2049)], [1, 2, 4]),
        (&[(1, 2049), (4, 2049)], [1, 2, 1]),
        (&[(1, 200), (4, 100)], [2, 2, 1]),
        (&[(1, 0), (4, 100), (2, 10), (5, 5)], [2, 2, 2]),
        (&[(1, 0), (4, 100), (3, 10), (6, 5)], [2, 2, 3]),
        (&[(7, 9)], [1, 2, 7]),
        (&[(9, 360)], [1, 2, 9]),
        (&[(10, 400)], [1, 2, 10]),
        (&[(7, 3), (15, 360)], [1, 2, 15]),
        (&[(8, 5)], [1, 2, 8]),
    ];
    for (edits, expected) in cases {
        refused(&mut pls, 2, &with(edits), 0x09, expected);
    }
    // A time-based setpoint cannot have others.
    refused(&mut pls, 2, &with(&[(8, 3)]), 0x09, [2, 2, 7]);
    // RPM start = end with the block in use is a conflict; all zero is no compensation.
    refused(&mut pls, 2, &with(&[(1, 100), (4, 100)]), 0x09, [2, 2, 1]);
    // Setpoints past N are ignored, not validated.
    let ignored = with(&[(7, 1), (15, 999)]);
    assert_eq!(set(&mut pls, 2, &ignored), 0);
    assert_eq!(error(&mut pls), [0; 3]);
    assert_eq!(get(&mut pls, 0xC1, 2), le(&ignored));
    // Equal start/end counts are allowed ("greater than").
    assert_eq!(
        set(&mut pls, 2, &with(&[(1, 10), (4, 100), (2, 5), (5, 5)])),
        0
    );
}

#[test]
fn low_speed_output_example_and_violations() {
    let mut pls = programmed();
    assert_eq!(get(&mut pls, 0xC1, 18), le(&output_17()));
    let mut nine = output_17();
    nine[0] = 9;
    refused(&mut pls, 18, &nine, 0x09, [1, 18, 1]);
    let mut off = output_17();
    off[0] = 2;
    off[7] = 360;
    refused(&mut pls, 18, &off, 0x09, [1, 18, 8]);
    let mut motion = output_17();
    motion[0] = 2;
    motion[1] = 4;
    motion[2] = 10;
    refused(&mut pls, 18, &motion, 0x09, [2, 18, 1]);
    // Output 18 is in no group: positions are checked against 65535 only.
    let mut free = output_17();
    free[2] = 65534;
    assert_eq!(set(&mut pls, 19, &free), 0);
}

#[test]
fn input_configuration_violations() {
    let mut pls = programmed();
    let mut w = [0u16; 112];
    // Input 9 (words 57-63): type 120, preset 77, active high, capture at leading edge.
    w[56] = 0b011;
    w[59] = 120;
    w[60] = 77;
    assert_eq!(set(&mut pls, 34, &w), 0);
    assert_eq!(get(&mut pls, 0xC1, 34), le(&w));
    let mut bad = w;
    bad[56] = 0b111;
    refused(&mut pls, 34, &bad, 0x09, [1, 34, 57]);
    let mut bad = w;
    bad[59] = 5;
    refused(&mut pls, 34, &bad, 0x09, [1, 34, 60]);
    let mut bad = w;
    bad[60] = 360;
    refused(&mut pls, 34, &bad, 0x09, [1, 34, 61]);
    let mut bad = w;
    bad[59] = 22;
    bad[60] = 33;
    refused(&mut pls, 34, &bad, 0x09, [1, 34, 61]);
    let mut bad = w;
    bad[59] = 140;
    bad[60] = 1;
    bad[61] = 3;
    refused(&mut pls, 34, &bad, 0x09, [1, 34, 62]);
    // Type 20 with output 2 (in no group) in its mask: conflict at the mask word.
    let mut bad = w;
    bad[59] = 20;
    bad[57] = 0x0003;
    refused(&mut pls, 34, &bad, 0x09, [2, 34, 58]);
    let mut bad = w;
    bad[59] = 30;
    bad[58] = 0x0002;
    refused(&mut pls, 34, &bad, 0x09, [2, 34, 59]);
    // Input 1 is in no group: any mask conflicts; group types ignore the masks.
    let mut bad = w;
    bad[3] = 40;
    bad[1] = 0x0001;
    refused(&mut pls, 34, &bad, 0x09, [2, 34, 2]);
    let mut ok = w;
    ok[59] = 130;
    ok[57] = 0xFFFF;
    assert_eq!(set(&mut pls, 34, &ok), 0);
}

#[test]
fn add_on_test_encoder_and_program_control_violations() {
    let mut pls = programmed();
    refused(&mut pls, 35, &[2049, 0, 1], 0x09, [1, 35, 1]);
    assert_eq!(set(&mut pls, 35, &[2048, 65535, 0xFFFF]), 0);
    // The encoder object on the resolver version: 0x0C and (2, 38, 1).
    refused(&mut pls, 38, &[1000, 1], 0x0C, [2, 38, 1]);
    refused(&mut pls, 37, &[9, 0], 0x09, [1, 37, 1]);
    refused(&mut pls, 37, &[0, 0], 0x09, [1, 37, 1]);
    // Restore with nothing saved: memory error, 0x19.
    refused(&mut pls, 37, &[3, 0], 0x19, [4, 37, 1]);
    refused(
        &mut pls,
        36,
        &[0b01, 360, 0, 0, 0, 0, 0, 0, 0],
        0x09,
        [1, 36, 2],
    );
    refused(
        &mut pls,
        36,
        &[0b0100, 0, (-1i16) as u16, 0, 0, 0, 0, 0, 0],
        0x09,
        [1, 36, 3],
    );
}

#[test]
fn resolver_fault_refuses_offsets_with_code_3() {
    let mut pls = programmed();
    pls.set_resolver(0, true);
    assert_eq!(input(&mut pls)[9], 1);
    refused(
        &mut pls,
        36,
        &[0b01, 150, 0, 0, 0, 0, 0, 0, 0],
        0x10,
        [3, 36, 1],
    );
    assert_ne!(pls.status_bits() & 0x0400, 0);
}

#[test]
fn errors_latch_until_an_acknowledge_rising_edge() {
    let mut pls = programmed();
    let mut bad = pls_object();
    bad[0] = 1;
    assert_eq!(set(&mut pls, 1, &bad), 0x09);
    // A later valid write leaves the words.
    assert_eq!(set(&mut pls, 1, &pls_object()), 0);
    assert_eq!(error(&mut pls), [1, 1, 1]);
    // A later error overwrites them.
    assert_eq!(set(&mut pls, 35, &[3000, 0, 0]), 0x09);
    assert_eq!(error(&mut pls), [1, 35, 1]);
    // Acknowledge held at 1 is a level: an error raised meanwhile stays.
    assert_eq!(output(&mut pls, [4, 0, 0, 0, 0, 0, 0]), 0);
    assert_eq!(error(&mut pls), [0; 3]);
    assert_eq!(set(&mut pls, 1, &bad), 0x09);
    assert_eq!(output(&mut pls, [4, 0, 0, 0, 0, 0, 0]), 0);
    assert_eq!(error(&mut pls), [1, 1, 1]);
    // Falling edge: nothing; next rising edge: cleared.
    assert_eq!(output(&mut pls, [0; 7]), 0);
    assert_eq!(error(&mut pls), [1, 1, 1]);
    assert_eq!(output(&mut pls, [4, 0, 0, 0, 0, 0, 0]), 0);
    assert_eq!(error(&mut pls), [0; 3]);
}

#[test]
fn cip_statuses_of_the_stack_leave_the_error_words_alone() {
    let mut pls = programmed();
    let mut call = |service, class, instance, attr, data: &[u8]| {
        execute(&mut pls, &request(service, class, instance, attr, data)).0
    };
    assert_eq!(call(0x0E, 0xC1, 1, Some(39), &[]), 0x14);
    assert_eq!(call(0x0E, 0xC1, 2, Some(1), &[]), 0x16);
    assert_eq!(call(0x10, 0xC0, 1, Some(1), &[0; 4]), 0x0E);
    assert_eq!(call(0x01, 0xC1, 1, None, &[]), 0x08);
    assert_eq!(call(0x10, 0xC1, 1, Some(1), &[0; 95]), 0x13);
    assert_eq!(call(0x10, 0xC1, 1, Some(1), &[0; 97]), 0x15);
    assert_eq!(error(&mut pls), [0; 3]);
}

/// Get_Attribute_List and Set_Attribute_List (0x03/0x04) are served on both classes, with
/// the same checks as the single services.
#[test]
fn attribute_lists_are_served() {
    let mut pls = programmed();
    // Get_Attribute_List of 0xC1 attributes 35 and 37: count 2, then (id, status, value).
    let (s, d) = execute(&mut pls, &request(0x03, 0xC1, 1, None, &le(&[2, 35, 37])));
    assert_eq!(s, 0);
    assert_eq!(words(&d), [2, 35, 0, 0, 0, 0, 37, 0, 0, 0]);
    // Set_Attribute_List of 0xC1/35: applied like a Set_Attribute_Single.
    let (s, d) = execute(
        &mut pls,
        &request(0x04, 0xC1, 1, None, &le(&[1, 35, 60, 1500, 1])),
    );
    assert_eq!((s, words(&d)), (0, vec![1, 35, 0]));
    assert_eq!(words(&get(&mut pls, 0xC1, 35)), [60, 1500, 1]);
    // A broken rule in a list: that attribute's status is 0x09, the error words latch.
    let (s, d) = execute(
        &mut pls,
        &request(0x04, 0xC1, 1, None, &le(&[1, 35, 2049, 0, 1])),
    );
    assert_eq!((s, words(&d)), (0x0A, vec![1, 35, 0x09]));
    assert_eq!(error(&mut pls), [1, 35, 1]);
    // On 0xC0 (Get only): Get_Attribute_List serves, Set_Attribute_List refuses (0x0E).
    let (s, d) = execute(&mut pls, &request(0x03, 0xC0, 1, None, &le(&[1, 1])));
    assert_eq!((s, d.len()), (0, 10));
    let (s, d) = execute(&mut pls, &request(0x04, 0xC0, 1, None, &le(&[1, 1, 0, 0])));
    assert_eq!((s, words(&d)), (0x0A, vec![1, 1, 0x0E]));
}

#[test]
fn assemblies_100_150_1() {
    let mut pls = AmetekPls::new();
    let attr = |pls: &mut AmetekPls, instance, a| {
        let (s, d) = execute(pls, &request(0x0E, 0x04, instance, Some(a), &[]));
        assert_eq!(s, 0);
        d
    };
    assert_eq!(attr(&mut pls, 100, 3).len(), 34);
    assert_eq!(attr(&mut pls, 150, 3).len(), 14);
    assert_eq!(attr(&mut pls, 100, 4), 34u16.to_le_bytes());
    assert_eq!(attr(&mut pls, 150, 4), 14u16.to_le_bytes());
    assert_eq!(attr(&mut pls, 1, 4), 0u16.to_le_bytes());
    // The output assembly reads back what was written; the input one is not settable.
    assert_eq!(output(&mut pls, [1, 2, 3, 4, 5, 6, 7]), 0);
    assert_eq!(words(&attr(&mut pls, 150, 3)), [1, 2, 3, 4, 5, 6, 7]);
    let (s, _) = execute(&mut pls, &request(0x10, 0x04, 100, Some(3), &[0; 34]));
    assert_eq!(s, 0x0E);
}

#[test]
fn offsets_home_absolute_relative() {
    let mut pls = programmed();
    // Home: group 1 position becomes 150.
    assert_eq!(set(&mut pls, 36, &[0b01, 150, 0, 0, 0, 0, 0, 0, 0]), 0);
    assert_eq!(input(&mut pls)[0], 150);
    assert_eq!(
        get(&mut pls, 0xC1, 36),
        le(&[0b01, 150, 0, 0, 0, 0, 0, 0, 0])
    );
    // Relative -10: 140.
    assert_eq!(
        set(&mut pls, 36, &[0b11, (-10i16) as u16, 0, 0, 0, 0, 0, 0, 0]),
        0
    );
    assert_eq!(input(&mut pls)[0], 140);
    // Absolute 80 on group 1, nothing on group 2: group 1 = group 2 + 80.
    assert_eq!(set(&mut pls, 36, &[0b10, 80, 0, 0, 0, 0, 0, 0, 0]), 0);
    let w = input(&mut pls);
    assert_eq!(w[0], (w[1] + 80) % 360);
    let info = words(&get(&mut pls, 0xC0, 3));
    assert_eq!(info[0], 80);
    assert_eq!(info[1], 0);
    // Relative wraps modulo the scale factor.
    assert_eq!(
        set(&mut pls, 36, &[0b11, (-100i16) as u16, 0, 0, 0, 0, 0, 0, 0]),
        0
    );
    assert_eq!(input(&mut pls)[0], 340);
    // Program control 1: no offset.
    assert_eq!(set(&mut pls, 37, &[1, 0]), 0);
    assert_eq!(input(&mut pls)[0], 0);
    assert_eq!(get(&mut pls, 0xC1, 37), le(&[1, 0]));
}

#[test]
fn program_control_save_change_restore() {
    let mut pls = programmed();
    assert_eq!(set(&mut pls, 36, &[0b01, 150, 0, 0, 0, 0, 0, 0, 0]), 0);
    assert_eq!(set(&mut pls, 37, &[2, 0]), 0);
    let saved = get(&mut pls, 0xC1, 2);
    let mut changed = output_1();
    changed[8] = 10;
    assert_eq!(set(&mut pls, 2, &changed), 0);
    assert_eq!(set(&mut pls, 36, &[0b01, 10, 0, 0, 0, 0, 0, 0, 0]), 0);
    assert_eq!(set(&mut pls, 37, &[3, 0]), 0);
    assert_eq!(get(&mut pls, 0xC1, 2), saved);
    assert_eq!(input(&mut pls)[0], 150);
    // A power cycle (Identity Reset type 0) loads the saved program; type 1 forgets it.
    assert_eq!(set(&mut pls, 2, &changed), 0);
    pls.reset(0).unwrap();
    assert_eq!(get(&mut pls, 0xC1, 2), saved);
    assert_eq!(get(&mut pls, 0xC1, 1), le(&pls_object()));
    pls.reset(1).unwrap();
    assert_eq!(get(&mut pls, 0xC1, 2), [0; 52]);
}

/// A module programmed like [`programmed`], its NVRAM in `store`.
fn programmed_in(store: SharedStore) -> AmetekPls {
    let mut pls = AmetekPls::with_storage(Nvram::in_store(store));
    assert_eq!(set(&mut pls, 1, &pls_object()), 0);
    assert_eq!(set(&mut pls, 2, &output_1()), 0);
    assert_eq!(set(&mut pls, 18, &output_17()), 0);
    pls
}

#[test]
fn a_saved_program_survives_a_restart_in_the_store() {
    let store = testing::store();
    let mut pls = programmed_in(store);
    assert_eq!(set(&mut pls, 37, &[2, 0]), 0);
    let mut fresh = AmetekPls::with_storage(Nvram::in_store(store));
    assert_eq!(get(&mut fresh, 0xC1, 2), le(&output_1()));
    assert_eq!(get(&mut fresh, 0xC1, 18), le(&output_17()));
    assert_ne!(fresh.status_bits() & 0x4, 0);
    // Factory defaults remove the record.
    fresh.reset(1).unwrap();
    let mut after = AmetekPls::with_storage(Nvram::in_store(store));
    assert_eq!(after.storage().load(), None);
    assert_eq!(get(&mut after, 0xC1, 2), [0; 52]);
    // A failing medium: code 4.
    let mut dead = CutFlash::new();
    dead.cut_after(0);
    let mut failing = AmetekPls::with_storage(Nvram::in_store(testing::store_on(dead).0));
    assert_eq!(set(&mut failing, 1, &pls_object()), 0);
    refused(&mut failing, 37, &[2, 0], 0x19, [4, 37, 1]);
}

#[test]
fn every_power_cut_during_a_save_keeps_the_old_or_the_new_program() {
    let steps = testing::every_power_cut(
        |store| {
            let mut pls = programmed_in(store);
            assert_eq!(set(&mut pls, 37, &[2, 0]), 0);
        },
        |store| {
            let mut pls = AmetekPls::with_storage(Nvram::in_store(store));
            let mut changed = output_1();
            changed[8] = 10;
            set(&mut pls, 2, &changed) == 0 && set(&mut pls, 37, &[2, 0]) == 0
        },
        |store| {
            let mut pls = AmetekPls::with_storage(Nvram::in_store(store));
            (get(&mut pls, 0xC1, 2), get(&mut pls, 0xC1, 18))
        },
    );
    assert!(steps > 100, "{steps} steps");
}

#[test]
fn selectable_by_name() {
    let p = crate::Profile::from_name("ametek-pls").unwrap();
    assert_eq!(p.name(), "ametek-pls");
    assert_eq!(p.identity().product_name, "7500 PLS");
}
