//! The manual's explicit examples and error cases, through the stack (`Adapter::execute`,
//! unconnected): classes 0x64 and 0x65, tags, status parameters, identity.

mod audit;
mod binary;
mod class1;
mod tags;

extern crate std;

use core::net::Ipv4Addr;
use std::vec;
use std::vec::Vec;

use enip_stack::{Adapter, Device, Instant, NetworkConfig};

use super::params::Value;
use super::ParkerIpa;

/// Runs Message Router request `bytes`; returns the whole reply.
pub fn raw(ipa: &mut ParkerIpa, bytes: &[u8]) -> Vec<u8> {
    let net = NetworkConfig::new_static(
        Ipv4Addr::new(198, 18, 0, 2),
        Ipv4Addr::new(255, 255, 255, 0),
        [2, 0, 0, 0, 0, 1],
    );
    let mut adapter = Adapter::new(core::mem::take(ipa), net, 1);
    let mut buf = [0u8; 600];
    let n = adapter.execute(bytes, Instant(0), &mut buf);
    *ipa = adapter.into_device();
    buf[..n].to_vec()
}

/// General status, additional words count and data of a request.
fn run(ipa: &mut ParkerIpa, bytes: &[u8]) -> (u8, u8, Vec<u8>) {
    let r = raw(ipa, bytes);
    let extra = 2 * usize::from(r[3]);
    (r[2], r[3], r[4 + extra..].to_vec())
}

/// A request to `class`/`instance` (16-bit segment) with attribute 1.
fn req(service: u8, class: u8, instance: u16, data: &[u8]) -> Vec<u8> {
    let i = instance.to_le_bytes();
    let mut v = vec![service, 4, 0x20, class, 0x25, 0x00, i[0], i[1], 0x30, 0x01];
    v.extend_from_slice(data);
    v
}

/// A tag request: `91 len name [pad]`.
fn tag(service: u8, name: &str, data: &[u8]) -> Vec<u8> {
    let mut path = vec![0x91, name.len() as u8];
    path.extend_from_slice(name.as_bytes());
    if path.len() % 2 == 1 {
        path.push(0);
    }
    let mut v = vec![service, (path.len() / 2) as u8];
    v.extend(path);
    v.extend_from_slice(data);
    v
}

fn floats(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|f| f.to_le_bytes()).collect()
}

fn longs(values: &[i32]) -> Vec<u8> {
    values.iter().flat_map(|l| l.to_le_bytes()).collect()
}

fn read_longs(ipa: &mut ParkerIpa, p: u16, n: i32) -> Vec<i32> {
    let (g, _, d) = run(ipa, &req(0x53, 0x64, p, &n.to_le_bytes()));
    assert_eq!(g, 0, "0x53 P{p}");
    d.chunks(4)
        .map(|c| i32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

fn read_floats(ipa: &mut ParkerIpa, p: u16, n: i32) -> Vec<f32> {
    let (g, _, d) = run(ipa, &req(0x51, 0x64, p, &n.to_le_bytes()));
    assert_eq!(g, 0, "0x51 P{p}");
    d.chunks(4)
        .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

#[test]
fn figures_4_5_jog_write_reads_back() {
    let mut ipa = ParkerIpa::new();
    // The request bytes of the digest (R8.1), as the PLC sends them.
    let bytes = [
        0x50, 0x04, 0x20, 0x64, 0x25, 0x00, 0x3C, 0x30, 0x30, 0x01, 0x00, 0x00, 0x70, 0x41, 0x00,
        0x00, 0x16, 0x43, 0x00, 0x00, 0xFA, 0x42, 0x00, 0x40, 0x1C, 0x44,
    ];
    assert_eq!(raw(&mut ipa, &bytes), [0xD0, 0, 0, 0]);
    assert_eq!(read_floats(&mut ipa, 12348, 4), [15.0, 150.0, 125.0, 625.0]);
}

#[test]
fn figures_6_7_quaternary_axis_flags() {
    let mut ipa = ParkerIpa::new();
    let bytes = [
        0x53, 0x04, 0x20, 0x64, 0x25, 0x00, 0x08, 0x11, 0x30, 0x01, 0x03, 0, 0, 0,
    ];
    let mut expected = vec![0xD3, 0, 0, 0];
    expected.extend_from_slice(&[
        0x20, 0x00, 0x30, 0x61, 0x20, 0x00, 0x30, 0x61, 0, 0, 0x50, 0,
    ]);
    assert_eq!(raw(&mut ipa, &bytes), expected);
    assert_eq!(
        read_longs(&mut ipa, 4360, 8),
        [1630535712, 1630535712, 5242880, 0, 0, 0, 0, 0]
    );
}

#[test]
fn figures_8_9_and_or() {
    let mut ipa = ParkerIpa::new();
    assert_eq!(
        run(&mut ipa, &req(0x52, 0x64, 4111, &longs(&[0x12345678]))).0,
        0
    );
    let bytes = [
        0x54, 0x04, 0x20, 0x64, 0x25, 0x00, 0x0F, 0x10, 0x30, 0x01, 0x00, 0xFF, 0xFF, 0xFF, 0x55,
        0x00, 0x00, 0x00,
    ];
    assert_eq!(raw(&mut ipa, &bytes), [0xD4, 0, 0, 0]);
    assert_eq!(read_longs(&mut ipa, 4111, 1), [0x12345655]);
    // Case 5: fewer than 8 bytes, 4 and 0.
    assert_eq!(raw(&mut ipa, &bytes[..14]), [0xD4, 0, 0x13, 0]);
    assert_eq!(raw(&mut ipa, &bytes[..10]), [0xD4, 0, 0x13, 0]);
    assert_eq!(read_longs(&mut ipa, 4111, 1), [0x12345655]);
}

#[test]
fn and_or_on_a_float_goes_through_the_long() {
    let mut ipa = ParkerIpa::new();
    run(&mut ipa, &req(0x50, 0x64, 39200, &floats(&[7.9])));
    assert_eq!(
        run(&mut ipa, &req(0x54, 0x64, 39200, &longs(&[!1, 0x10]))).0,
        0
    );
    assert_eq!(read_floats(&mut ipa, 39200, 1), [22.0]);
}

#[test]
fn conversion_of_page_23() {
    let mut ipa = ParkerIpa::new();
    assert_eq!(
        run(&mut ipa, &req(0x50, 0x64, 12304, &floats(&[1234.75]))).0,
        0
    );
    assert_eq!(read_longs(&mut ipa, 12304, 1), [1234]);
    assert_eq!(read_floats(&mut ipa, 12304, 1), [1234.75]);
    // Truncation toward zero, saturation, NaN 0 (R9.4).
    run(
        &mut ipa,
        &req(0x50, 0x64, 12305, &floats(&[-2.9, 1e20, f32::NAN])),
    );
    assert_eq!(read_longs(&mut ipa, 12305, 3), [-2, i32::MAX, 0]);
    // A long written as float and read back.
    run(&mut ipa, &req(0x52, 0x64, 39201, &longs(&[-3])));
    assert_eq!(read_floats(&mut ipa, 39201, 1), [-3.0]);
    run(&mut ipa, &req(0x50, 0x64, 38913, &floats(&[77.0])));
    assert_eq!(read_longs(&mut ipa, 38913, 1), [77]);
}

#[test]
fn table_8_cases_on_class_0x64() {
    let mut ipa = ParkerIpa::new();
    let status = |ipa: &mut ParkerIpa, b: &[u8]| {
        let (g, n, _) = run(ipa, b);
        assert_eq!(n, 0, "no extended status");
        g
    };
    // Case 1: other services on the class.
    assert_eq!(status(&mut ipa, &req(0x0E, 0x64, 4100, &[])), 0x08);
    assert_eq!(status(&mut ipa, &req(0x55, 0x64, 4100, &[])), 0x08);
    assert_eq!(status(&mut ipa, &req(0x4C, 0x64, 4112, &[1, 0])), 0x08);
    assert_eq!(
        status(&mut ipa, &req(0x10, 0x64, 4100, &[1, 0, 0, 0])),
        0x08
    );
    // Case 3: reads of 17; 0 and negative counts too.
    for svc in [0x51, 0x53] {
        assert_eq!(
            status(&mut ipa, &req(svc, 0x64, 4096, &17i32.to_le_bytes())),
            0x20
        );
        assert_eq!(
            status(&mut ipa, &req(svc, 0x64, 4096, &0i32.to_le_bytes())),
            0x20
        );
        assert_eq!(
            status(&mut ipa, &req(svc, 0x64, 4096, &(-1i32).to_le_bytes())),
            0x20
        );
        assert_eq!(status(&mut ipa, &req(svc, 0x64, 4096, &[1, 0])), 0x13);
        assert_eq!(
            status(&mut ipa, &req(svc, 0x64, 4096, &16i32.to_le_bytes())),
            0
        );
    }
    // Case 4: writes of 17 values; the target stays unchanged.
    assert_eq!(
        status(&mut ipa, &req(0x52, 0x64, 38912, &longs(&[5; 17]))),
        0x15
    );
    assert_eq!(
        status(&mut ipa, &req(0x50, 0x64, 39168, &floats(&[5.0; 17]))),
        0x15
    );
    assert_eq!(read_longs(&mut ipa, 38912, 16), [0; 16]);
    assert_eq!(read_floats(&mut ipa, 39168, 1), [0.0]);
    // Empty or ragged write data.
    assert_eq!(status(&mut ipa, &req(0x52, 0x64, 38912, &[])), 0x13);
    assert_eq!(
        status(&mut ipa, &req(0x52, 0x64, 38912, &[1, 2, 3, 4, 5])),
        0x13
    );
    // Unknown parameters: P10 (not dimensioned), a range running off the end.
    assert_eq!(
        status(&mut ipa, &req(0x53, 0x64, 10, &1i32.to_le_bytes())),
        0x05
    );
    assert_eq!(
        status(&mut ipa, &req(0x52, 0x64, 39422, &longs(&[1, 2, 3]))),
        0x05
    );
    assert_eq!(read_floats(&mut ipa, 39422, 2), [0.0, 0.0]);
    assert_eq!(
        status(&mut ipa, &req(0x54, 0x64, 5000, &longs(&[0, 1]))),
        0x05
    );
}

#[test]
fn the_attribute_is_ignored() {
    let mut ipa = ParkerIpa::new();
    let count = 3i32.to_le_bytes();
    let with = |attr: Option<u8>, eight_bit: bool| {
        let mut v = vec![0x53, 0, 0x20, 0x64];
        if eight_bit {
            v.extend_from_slice(&[0x24, 0x10]); // 8-bit instance segment: P16
        } else {
            v.extend_from_slice(&[0x25, 0x00, 0x08, 0x11]);
        }
        if let Some(a) = attr {
            v.extend_from_slice(&[0x30, a]);
        }
        v[1] = ((v.len() - 2) / 2) as u8;
        v.extend_from_slice(&count);
        v
    };
    let expected = run(&mut ipa, &with(Some(1), false));
    assert_eq!(expected.0, 0);
    assert_eq!(run(&mut ipa, &with(None, false)), expected);
    assert_eq!(run(&mut ipa, &with(Some(7), false)), expected);
    // An 8-bit instance segment addresses P16 (not dimensioned).
    assert_eq!(run(&mut ipa, &with(Some(1), true)).0, 0x05);
}

#[test]
fn read_group_figure_10_and_axis_positions() {
    let mut ipa = ParkerIpa::new();
    for k in 0..4u16 {
        run(
            &mut ipa,
            &req(0x50, 0x64, 12304 + 256 * k, &floats(&[10.5 + f32::from(k)])),
        );
    }
    let bytes = [
        0x53, 0x04, 0x20, 0x65, 0x25, 0x00, 0x10, 0x30, 0x30, 0x01, 0x04, 0, 0, 0,
    ];
    let mut expected = vec![0xD3, 0, 0, 0];
    expected.extend(floats(&[10.5, 11.5, 12.5, 13.5]));
    assert_eq!(raw(&mut ipa, &bytes), expected);
    // Group 0x30 index 2: the actual positions of axes 0-7 (longs).
    for a in 0..8u16 {
        run(
            &mut ipa,
            &req(
                0x52,
                0x64,
                12290 + 256 * a,
                &longs(&[1000 * i32::from(a) - 3]),
            ),
        );
    }
    let (g, _, d) = run(&mut ipa, &req(0x53, 0x65, 0x3002, &8i32.to_le_bytes()));
    assert_eq!(g, 0);
    let mut individual = Vec::new();
    for a in 0..8u16 {
        individual.extend(longs(&read_longs(&mut ipa, 12290 + 256 * a, 1)));
    }
    assert_eq!(d, individual);
    assert_eq!(d.len(), 32);
}

#[test]
fn table_8_cases_on_class_0x65() {
    let mut ipa = ParkerIpa::new();
    let one = 1i32.to_le_bytes();
    // Case 6: block sizes 0 and 9.
    assert_eq!(
        raw(&mut ipa, &req(0x53, 0x65, 12304, &0i32.to_le_bytes())),
        [0xD3, 0, 0x20, 0]
    );
    assert_eq!(
        raw(&mut ipa, &req(0x53, 0x65, 12304, &9i32.to_le_bytes())),
        [0xD3, 0, 0x20, 0]
    );
    // Case 7: group codes 0x80 and 0xBF; 0xC0 is valid (but has no parameters here).
    assert_eq!(
        raw(&mut ipa, &req(0x53, 0x65, 0x8002, &one)),
        [0xD3, 0, 0x05, 0]
    );
    assert_eq!(
        raw(&mut ipa, &req(0x53, 0x65, 0xBF00, &one)),
        [0xD3, 0, 0x05, 0]
    );
    // 0x7F: valid code; P32512 does not exist.
    assert_eq!(
        raw(&mut ipa, &req(0x53, 0x65, 0x7F00, &one)),
        [0xD3, 0, 0x05, 0]
    );
    // An element off the axes: P12304 + 256 x 8 = P14352 does not exist.
    assert_eq!(
        run(&mut ipa, &req(0x53, 0x65, 12304, &8i32.to_le_bytes())).0,
        0
    );
    assert_eq!(
        run(
            &mut ipa,
            &req(0x53, 0x65, 12305 + 256 * 7, &2i32.to_le_bytes())
        )
        .0,
        0x05
    );
    // Case 1: 0x50 on the group class.
    assert_eq!(
        run(&mut ipa, &req(0x50, 0x65, 12304, &floats(&[1.0]))).0,
        0x08
    );
    assert_eq!(run(&mut ipa, &req(0x0E, 0x65, 12304, &[])).0, 0x08);
    // Case 2: Write Binary unconnected.
    assert_eq!(
        raw(&mut ipa, &req(0x34, 0x65, 1, &[1, 2, 3, 4])),
        [0xB4, 0, 0x10, 0]
    );
    assert_eq!(ipa.binary_bytes, 0);
}

#[test]
fn status_parameters_at_power_up() {
    let mut ipa = ParkerIpa::new();
    let s = read_longs(&mut ipa, 37424, 16);
    // Only the requests counted so far (this one) and the 16 groups of the AOI layout.
    assert_eq!(s[2], 1, "P37426 counts this request");
    assert_eq!(s[10], 16, "P37434");
    assert_eq!(s[9], 0, "P37433");
    assert_eq!([s[0], s[1], s[3], s[4], s[5], s[6]], [0; 6]);
    // Writes are accepted and overwritten (R7.2), P37434 is read/write.
    assert_eq!(run(&mut ipa, &req(0x52, 0x64, 37433, &longs(&[5]))).0, 0);
    assert_eq!(read_longs(&mut ipa, 37433, 1), [0]);
    assert_eq!(run(&mut ipa, &req(0x52, 0x64, 37434, &longs(&[4]))).0, 0);
    assert_eq!(read_longs(&mut ipa, 37434, 1), [4]);
}

#[test]
fn aoi_configuration_is_loaded_at_power_up_and_writable() {
    let mut ipa = ParkerIpa::new();
    let table: Vec<i32> = super::params::AOI_GROUPS
        .iter()
        .flatten()
        .copied()
        .collect();
    for (k, chunk) in table.chunks(16).enumerate() {
        assert_eq!(read_longs(&mut ipa, 37440 + 16 * k as u16, 16), chunk);
    }
    // Written back with 0x52, read back.
    for (k, chunk) in table.chunks(16).enumerate() {
        let (g, _, _) = run(
            &mut ipa,
            &req(0x52, 0x64, 37440 + 16 * k as u16, &longs(chunk)),
        );
        assert_eq!(g, 0);
        assert_eq!(read_longs(&mut ipa, 37440 + 16 * k as u16, 16), chunk);
    }
}

#[test]
fn identity_and_class_attributes() {
    let mut ipa = ParkerIpa::new();
    let get = |ipa: &mut ParkerIpa, class: u8, instance: u8, attr: u8| {
        run(ipa, &[0x0E, 3, 0x20, class, 0x24, instance, 0x30, attr])
    };
    assert_eq!(get(&mut ipa, 1, 1, 1).2, 620u16.to_le_bytes());
    assert_eq!(get(&mut ipa, 1, 1, 2).2, 0x2Bu16.to_le_bytes());
    assert_eq!(get(&mut ipa, 1, 1, 4).2, [4, 40]);
    let mut name = vec![14u8];
    name.extend_from_slice(b"IPA Controller");
    assert_eq!(get(&mut ipa, 1, 1, 7).2, name);
    // The vendor classes answer their class attributes (revision 1).
    assert_eq!(get(&mut ipa, 0x64, 0, 1).2, [1, 0]);
    assert_eq!(get(&mut ipa, 0x65, 0, 1).2, [1, 0]);
}

/// Polls every millisecond for `ms` from `t` (µs); returns the new time.
fn run_for(ipa: &mut ParkerIpa, t: u64, ms: u64) -> u64 {
    let mut now = t;
    for _ in 0..ms {
        now += 1_000;
        ipa.poll(Instant(now));
    }
    now
}

fn flags(ipa: &ParkerIpa, axis: u32) -> i32 {
    ipa.get(4360 + axis).unwrap().as_long()
}

/// The manual's figure 4 write sets a jog profile and starts nothing; an axis moves only
/// while its jog forward or reverse bit is set, and its jog-active flag shows it.
#[test]
fn axes_move_only_on_a_jog_command() {
    use super::device::{JOG_ACTIVE, JOG_FORWARD, JOG_REVERSE};
    let mut ipa = ParkerIpa::new();
    ipa.poll(Instant(0));
    let figure_4 = req(0x50, 0x64, 12348, &floats(&[15.0, 150.0, 125.0, 625.0]));
    assert_eq!(run(&mut ipa, &figure_4).0, 0);
    ipa.set(12348 + 256 * 3, Value::Float(500.0));
    let t = run_for(&mut ipa, 0, 1_000);
    assert_eq!(
        ipa.get(12288),
        Some(Value::Long(0)),
        "figure 4 starts nothing"
    );
    assert_eq!(ipa.get(12290 + 768), Some(Value::Long(0)));
    assert_eq!(flags(&ipa, 0), 1630535712, "Fig. 7 flags, not jogging");
    // Jog forward on axis 0 (15 units/s), reverse on axis 3 (500 units/s).
    ipa.set(4360, Value::Long(flags(&ipa, 0) | JOG_FORWARD));
    ipa.set(4363, Value::Long(JOG_REVERSE));
    let t = run_for(&mut ipa, t, 2_000);
    assert_eq!(ipa.get(12288), Some(Value::Long(30)));
    assert_eq!(ipa.get(12290), Some(Value::Long(30)));
    assert_eq!(ipa.get(12290 + 768), Some(Value::Long(-1000)));
    assert_eq!(flags(&ipa, 0), 1630535712 | JOG_FORWARD | JOG_ACTIVE);
    assert_eq!(flags(&ipa, 3), JOG_REVERSE | JOG_ACTIVE);
    assert_eq!(
        ipa.get(12290 + 256),
        Some(Value::Long(0)),
        "axis 1 has no command"
    );
    // Both bits: no motion. A zero velocity with the bit set: no motion, not active.
    ipa.set(4360, Value::Long(flags(&ipa, 0) | JOG_REVERSE));
    ipa.set(12348 + 256 * 3, Value::Float(0.0));
    let t = run_for(&mut ipa, t, 500);
    assert_eq!(ipa.get(12288), Some(Value::Long(30)));
    assert_eq!(ipa.get(12290 + 768), Some(Value::Long(-1000)));
    assert_eq!(flags(&ipa, 0) & JOG_ACTIVE, 0);
    assert_eq!(flags(&ipa, 3), JOG_REVERSE);
    // The command cleared: the axis stops.
    ipa.set(4360, Value::Long(1630535712));
    run_for(&mut ipa, t, 500);
    assert_eq!(ipa.get(12288), Some(Value::Long(30)));
    assert_eq!(flags(&ipa, 0), 1630535712);
}

#[test]
fn assembly_data_by_get_attribute_single() {
    let mut ipa = ParkerIpa::new();
    run(&mut ipa, &req(0x52, 0x64, 38912, &longs(&[5, 6])));
    let (g, _, d) = run(&mut ipa, &[0x0E, 3, 0x20, 0x04, 0x24, 101, 0x30, 3]);
    assert_eq!(g, 0);
    assert_eq!(d.len(), 400);
    // The AOI layout: group 2 (P4360) at 36, group 10 (P38912..) at 160, zeros from 192.
    assert_eq!(d[36..40], 1630535712i32.to_le_bytes());
    assert_eq!(d[160..168], longs(&[5, 6])[..]);
    assert!(d[192..].iter().all(|&b| b == 0));
    // 102 reads the consumed parameters in their layout; 3 is empty.
    assert_eq!(
        run(&mut ipa, &[0x0E, 3, 0x20, 0x04, 0x24, 102, 0x30, 3])
            .2
            .len(),
        400
    );
    assert_eq!(
        run(&mut ipa, &[0x0E, 3, 0x20, 0x04, 0x24, 3, 0x30, 3])
            .2
            .len(),
        0
    );
}

#[test]
fn selectable_by_name() {
    let p = crate::Profile::from_name("parker-ipa").unwrap();
    assert_eq!(p.name(), "parker-ipa");
    assert_eq!(p.identity().product_name, "IPA Controller");
}

/// A small deterministic generator (xorshift) for the robustness test.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn below(&mut self, n: u64) -> usize {
        (self.next() % n) as usize
    }
}

#[test]
fn random_requests_never_panic_and_always_answer() {
    let mut ipa = ParkerIpa::new();
    let mut rng = Rng(0x5EED_1234_ABCD_0001);
    let services = [
        0x34, 0x48, 0x4C, 0x4D, 0x4E, 0x50, 0x51, 0x52, 0x53, 0x54, 0x0E, 0x01,
    ];
    let names = [
        "P4096", "P39200", "p12348", "P37424", "P0", "P99999", "P", "Q1", "P4607",
    ];
    for round in 0..3000 {
        let service = services[rng.below(services.len() as u64)];
        let mut data = vec![0u8; rng.below(80)];
        data.iter_mut().for_each(|b| *b = rng.next() as u8);
        // Small counts and known types often enough to reach the deep paths.
        if data.len() >= 4 && rng.below(2) == 0 {
            data[0] = rng.below(20) as u8;
            data[1] = 0;
            data[2] = if rng.below(2) == 0 {
                0
            } else {
                rng.below(20) as u8
            };
            data[3] = 0;
        }
        if service == 0x4D && data.len() >= 2 && rng.below(2) == 0 {
            data[0] = if rng.below(2) == 0 { 0xC4 } else { 0xCA };
            data[1] = 0;
        }
        let bytes = match rng.below(3) {
            0 => req(service, 0x64, rng.next() as u16, &data),
            1 => req(service, 0x65, rng.next() as u16, &data),
            _ => tag(service, names[rng.below(names.len() as u64)], &data),
        };
        let reply = raw(&mut ipa, &bytes);
        assert!(reply.len() >= 4, "round {round}: {bytes:02x?}");
        assert_eq!(reply[0], service | 0x80, "round {round}");
    }
    // Random configurations and O->T data: validation never panics, data always applies.
    for _ in 0..2000 {
        let mut config = [0i32; super::params::CONFIG_COUNT];
        for (k, c) in config.iter_mut().enumerate() {
            *c = match k % 4 {
                0 => {
                    [4096, 12288, 38912, 39168, 37424, 10, -1][rng.below(7)] + rng.below(300) as i32
                }
                1 => rng.below(11) as i32 - 1,
                _ => rng.below(4) as i32 - 1,
            };
        }
        let groups = rng.below(19) as i32 - 1;
        if let Ok(layout) = super::ioconfig::validate(groups, &config) {
            assert!(layout.longs(super::ioconfig::Direction::Produce) <= 100);
            ipa.layout = layout;
            let mut out = [0u8; 400];
            assert_eq!(ipa.read_assembly(101, &mut out), Ok(400));
            let data: Vec<u8> = (0..400).map(|_| rng.next() as u8).collect();
            assert_eq!(ipa.write_assembly(102, &data), Ok(()));
        }
    }
}
