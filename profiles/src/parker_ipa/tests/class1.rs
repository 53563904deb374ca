//! Class 1 and Class 3 through the adapter's entry points in virtual time: the RSLogix
//! example, a 4-group configuration, one Class 1 connection at a time, the configuration
//! errors of Table 3 in P37433-P37437, RPI limits, timeouts, run/idle, Write Binary over
//! Class 3.

extern crate std;

use core::net::SocketAddrV4;
use std::vec;
use std::vec::Vec;

use enip_stack::virtual_scanner::{Opened, VirtualScanner, SCANNER_IP};
use enip_stack::wire::forward_open::{ForwardOpenRepr, NetworkParams, Triad};
use enip_stack::Device;

use super::super::ParkerIpa;
use crate::Profile;

/// Point-to-point, scheduled priority, fixed size.
const P2P: u16 = 0x4800;
/// Multicast, scheduled, fixed.
const MULTICAST: u16 = 0x2800;
/// A 4-group configuration, two groups each way: P = 16, C = 20 bytes.
const FOUR_GROUPS: [[i32; 4]; 4] = [
    [38912, 2, 0, 1],
    [39168, 2, 0, 2],
    [39000, 3, 1, 1],
    [39300, 2, 1, 2],
];
/// Connection path 3/102/101 (configuration, consumed, produced).
const IO_PATH: [u8; 8] = [0x20, 0x04, 0x24, 0x03, 0x2C, 0x66, 0x2C, 0x65];

/// The controller behind a virtual scanner, with the requests these tests make.
struct Rig<D: Device = ParkerIpa> {
    scanner: VirtualScanner<D>,
}

impl Rig {
    fn new() -> Rig {
        Rig::with(ParkerIpa::new())
    }
}

impl<D: Device> Rig<D> {
    /// The controller as `device` (the profile itself, or [`Profile`] holding it).
    fn with(device: D) -> Rig<D> {
        Rig {
            scanner: VirtualScanner::new(device),
        }
    }

    /// An unconnected Message Router request (raw bytes); the status and reply data.
    fn ucmm(&mut self, mr: &[u8]) -> (u8, Option<u16>, Vec<u8>) {
        let (general, extended, data) = self.scanner.unconnected(mr).unwrap();
        (general, extended, data.to_vec())
    }

    /// A connected (Class 3) request over connection `id`.
    fn connected(&mut self, id: u32, seq: u16, mr: &[u8]) -> (u8, Vec<u8>) {
        let (general, _, data) = self.scanner.connected(id, seq, mr).unwrap();
        (general, data.to_vec())
    }

    fn forward_open(&mut self, fo: &ForwardOpenRepr<'_>) -> Opened {
        self.scanner.forward_open(fo)
    }

    fn forward_close(&mut self, serial: u16) -> u8 {
        let mut mr = vec![0x4E, 0x02, 0x20, 0x06, 0x24, 0x01, 0x0A, 0x0E];
        mr.extend_from_slice(&serial.to_le_bytes());
        mr.extend_from_slice(&0x1337u16.to_le_bytes());
        mr.extend_from_slice(&0xC0FFEEu32.to_le_bytes());
        mr.extend_from_slice(&[(IO_PATH.len() / 2) as u8, 0]);
        mr.extend_from_slice(&IO_PATH);
        self.ucmm(&mr).0
    }

    /// P(first).. read with 0x53.
    fn longs(&mut self, first: u16, n: i32) -> Vec<i32> {
        let mut mr = vec![0x53, 0x03, 0x20, 0x64, 0x25, 0x00];
        mr.extend_from_slice(&first.to_le_bytes());
        mr.extend_from_slice(&n.to_le_bytes());
        let (g, _, d) = self.ucmm(&mr);
        assert_eq!(g, 0);
        d.chunks(4)
            .map(|c| i32::from_le_bytes(c.try_into().unwrap()))
            .collect()
    }

    /// Writes longs from P(first) with 0x52.
    fn write_longs(&mut self, first: u16, values: &[i32]) {
        let mut mr = vec![0x52, 0x03, 0x20, 0x64, 0x25, 0x00];
        mr.extend_from_slice(&first.to_le_bytes());
        mr.extend(values.iter().flat_map(|v| v.to_le_bytes()));
        assert_eq!(self.ucmm(&mr).0, 0);
    }

    /// Sets P37434 = `groups.len()` and the groups.
    fn configure(&mut self, groups: &[[i32; 4]]) {
        self.write_longs(37434, &[groups.len() as i32]);
        for (g, entry) in groups.iter().enumerate() {
            self.write_longs(37440 + 4 * g as u16, entry);
        }
    }

    /// O->T data on connection `id`, Run or Idle.
    fn o_t(&mut self, id: u32, run: bool, data: &[u8]) {
        self.scanner.send_io(id, Some(run), data).unwrap();
    }

    /// Advances time by `us`, returns the T->O datagrams' data (after the sequence count).
    fn advance(&mut self, us: u64) -> Vec<(SocketAddrV4, Vec<u8>)> {
        let mut out = Vec::new();
        self.scanner
            .advance(us, |to, data| out.push((to, data.to_vec())));
        out
    }
}

fn params(kind: u16, size: u16) -> NetworkParams {
    NetworkParams::from_u16(kind | size)
}

/// An exclusive owner of 102/101 with data sizes `o_t`/`t_o` and RPIs in µs.
fn fo(serial: u16, o_t: u16, t_o: u16, o_t_rpi: u32, t_o_rpi: u32) -> ForwardOpenRepr<'static> {
    ForwardOpenRepr {
        large: false,
        priority_tick: 0x0A,
        timeout_ticks: 0x0E,
        o_t_connection_id: 0,
        t_o_connection_id: 0x7000_0000 + u32::from(serial),
        triad: Triad {
            connection_serial: serial,
            vendor_id: 0x1337,
            originator_serial: 0xC0FFEE,
        },
        timeout_multiplier: 1,
        o_t_rpi,
        o_t_params: params(P2P, o_t + 6),
        t_o_rpi,
        t_o_params: params(P2P, t_o + 2),
        transport: 0x01,
        path: &IO_PATH,
    }
}

fn f32s(d: &[u8]) -> Vec<f32> {
    d.chunks(4)
        .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

fn i32s(d: &[u8]) -> Vec<i32> {
    d.chunks(4)
        .map(|c| i32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

#[test]
fn rslogix_example_with_the_aoi_configuration() {
    let mut rig = Rig::new();
    rig.write_longs(38912, &[1, 2, 3, 4, 5, 6, 7, 8]);
    let open = rig.forward_open(&fo(1, 400, 400, 10_000, 10_000));
    assert_eq!(open.general, 0, "{open:?}");
    let status = rig.longs(37424, 16);
    assert_eq!(status[9], 1, "P37433");
    assert_eq!((status[7], status[8]), (10, 10), "P37431/P37432");
    assert_eq!(status[5] as u32, 0xC612_0001, "P37429");
    assert!(status[6] >= 1 && status[4] >= 1);
    // O->T: groups 11-15, 128 bytes; bytes 16..31 the jog profile (REAL).
    let mut out = vec![0u8; 400];
    out[0..16].copy_from_slice(&[1, 0, 0, 0, 2, 0, 0, 0, 3, 0, 0, 0, 4, 0, 0, 0]);
    for (k, v) in [15.0f32, 150.0, 125.0, 625.0].iter().enumerate() {
        out[16 + 4 * k..20 + 4 * k].copy_from_slice(&v.to_le_bytes());
    }
    out[32..36].copy_from_slice(&(-77i32).to_le_bytes());
    out[64..68].copy_from_slice(&2.5f32.to_le_bytes());
    out[200..204].copy_from_slice(&99i32.to_le_bytes()); // beyond C: ignored
    rig.o_t(open.o_t_id, true, &out);
    let mut mr = vec![0x51, 0x03, 0x20, 0x64, 0x25, 0x00];
    mr.extend_from_slice(&12348u16.to_le_bytes());
    mr.extend_from_slice(&4i32.to_le_bytes());
    assert_eq!(f32s(&rig.ucmm(&mr).2), [15.0, 150.0, 125.0, 625.0]);
    assert_eq!(rig.longs(4156, 4), [1, 2, 3, 4]);
    assert_eq!(rig.longs(39000, 1), [-77]);
    let mut mr = vec![0x51, 0x03, 0x20, 0x64, 0x25, 0x00];
    mr.extend_from_slice(&39200u16.to_le_bytes());
    mr.extend_from_slice(&1i32.to_le_bytes());
    assert_eq!(f32s(&rig.ucmm(&mr).2), [2.5]);
    // T->O: 400 bytes; the user DINTs at 160..192, zeros after 192.
    let sent = rig.advance(25_000);
    assert!(sent.len() >= 2, "{}", sent.len());
    let (to, data) = sent.last().unwrap();
    assert_eq!(*to, SocketAddrV4::new(SCANNER_IP, 2222));
    assert_eq!(data.len(), 400);
    assert_eq!(i32s(&data[160..192]), rig.longs(38912, 8));
    assert!(data[192..].iter().all(|&b| b == 0));
    // Quaternary flags (group 2) at offset 36, monitor floats (group 7) at 84.
    assert_eq!(i32s(&data[36..40]), [1630535712]);
    // The jog profile alone starts nothing: group 0 (current position) stays.
    let before = i32s(&data[0..4])[0];
    let mut later = Vec::new();
    for _ in 0..10 {
        rig.o_t(open.o_t_id, true, &out);
        later = rig.advance(10_000);
    }
    assert_eq!(i32s(&later.last().unwrap().1[0..4])[0], before);
    // Jog forward (P4360 bit 16, set with 0x54): axis 0 moves, bit 18 (jog active) shows.
    let mut mr = vec![0x54, 0x03, 0x20, 0x64, 0x25, 0x00];
    mr.extend_from_slice(&4360u16.to_le_bytes());
    mr.extend_from_slice(&(-1i32).to_le_bytes());
    mr.extend_from_slice(&(1i32 << 16).to_le_bytes());
    assert_eq!(rig.ucmm(&mr).0, 0);
    for _ in 0..20 {
        rig.o_t(open.o_t_id, true, &out);
        later = rig.advance(10_000);
    }
    let last = &later.last().unwrap().1;
    let after = i32s(&last[0..4])[0];
    assert!(after > before, "{before} -> {after}");
    assert_eq!(i32s(&last[36..40]), [1630535712 | 0b101 << 16]);
    // Counters.
    let status = rig.longs(37424, 4);
    assert!(status[1] >= 1 && status[2] >= 5, "{status:?}");
}

#[test]
fn four_groups_both_ways() {
    let mut rig = Rig::new();
    rig.configure(&FOUR_GROUPS);
    let open = rig.forward_open(&fo(1, 400, 400, 1_000, 1_000));
    assert_eq!(open.general, 0);
    rig.o_t(open.o_t_id, true, &[0; 400]);
    rig.write_longs(38913, &[4242]);
    let sent = rig.advance(2_000);
    assert!(!sent.is_empty());
    let data = &sent.last().unwrap().1;
    assert_eq!(i32s(&data[0..8]), [0, 4242]);
    // A long written into a REAL group goes out as a float.
    rig.write_longs(39169, &[-7]);
    let sent = rig.advance(2_000);
    assert_eq!(f32s(&sent.last().unwrap().1[8..16]), [0.0, -7.0]);
    // O->T: 3 DINTs then 2 REALs, converted to the parameters' types.
    let mut out = vec![0u8; 400];
    out[0..12].copy_from_slice(&[9, 0, 0, 0, 8, 0, 0, 0, 7, 0, 0, 0]);
    out[12..16].copy_from_slice(&1.75f32.to_le_bytes());
    out[16..20].copy_from_slice(&(-2.0f32).to_le_bytes());
    rig.o_t(open.o_t_id, true, &out);
    assert_eq!(rig.longs(39000, 3), [9, 8, 7]);
    assert_eq!(rig.longs(39300, 2), [1, -2]);
    // Idle data is not applied.
    out[0] = 100;
    rig.o_t(open.o_t_id, false, &out);
    assert_eq!(rig.longs(39000, 1), [9]);
    // RPI 1 ms reported.
    assert_eq!(rig.longs(37431, 3), [1, 1, 1]);
}

#[test]
fn one_class1_connection_at_a_time() {
    let mut rig = Rig::new();
    let first = rig.forward_open(&fo(1, 400, 400, 10_000, 10_000));
    assert_eq!(first.general, 0);
    rig.o_t(first.o_t_id, true, &[0; 400]);
    // A second one from another session.
    rig.scanner.open_session(1).unwrap();
    let second = rig.forward_open(&fo(2, 400, 400, 10_000, 10_000));
    rig.scanner.select_session(0);
    assert_eq!((second.general, second.extended), (0x01, Some(0x0106)));
    // Input only (not offered) and a duplicate triad.
    let dup = rig.forward_open(&fo(1, 400, 400, 10_000, 10_000));
    assert_eq!((dup.general, dup.extended), (0x01, Some(0x0100)));
    assert_eq!(rig.longs(37433, 1), [1]);
    // The refused second scanner leaves P37429/P37430 on the running connection's client.
    assert_eq!(rig.longs(37429, 2), [0xC612_0001u32 as i32, 1]);
    // The first keeps running.
    for _ in 2..5 {
        let sent = rig.advance(10_000);
        assert!(!sent.is_empty());
        rig.o_t(first.o_t_id, true, &[0; 400]);
    }
    assert_eq!(rig.forward_close(1), 0);
    assert_eq!(rig.longs(37433, 1), [0]);
    assert!(rig.advance(50_000).is_empty(), "T->O stops");
    assert_eq!(
        rig.forward_open(&fo(3, 400, 400, 10_000, 10_000)).general,
        0
    );
}

#[test]
fn timeout_closes_and_frees_the_slot() {
    let mut rig = Rig::new();
    let open = rig.forward_open(&fo(1, 400, 400, 2_000, 2_000));
    assert_eq!(open.general, 0);
    rig.o_t(open.o_t_id, true, &[0; 400]);
    // Multiplier x8 x 2 ms = 16 ms without O->T.
    rig.advance(200_000);
    assert!(rig.advance(20_000).is_empty());
    assert_eq!(rig.longs(37433, 1), [0]);
    assert_eq!(rig.forward_open(&fo(2, 400, 400, 2_000, 2_000)).general, 0);
    assert_eq!(rig.longs(37433, 1), [1]);
}

#[test]
fn configuration_errors_refuse_and_report() {
    let mut rig = Rig::new();
    let mut serial = 10;
    let mut attempt = |rig: &mut Rig| {
        serial += 1;
        let r = rig.forward_open(&fo(serial, 400, 400, 10_000, 10_000));
        assert_eq!((r.general, r.extended), (0x01, Some(0x0110)));
        rig.longs(37433, 5)
    };
    // The manual's example 2 (p.5): 4 groups, group 1 names P10.
    rig.configure(&[
        [4096, 2, 0, 1],
        [10, 8, 0, 1],
        [38912, 1, 0, 1],
        [39000, 1, 1, 1],
    ]);
    assert_eq!(attempt(&mut rig), [7, 4, 1, 10, 8]);
    // 2: more than 16 groups.
    rig.write_longs(37434, &[17]);
    assert_eq!(attempt(&mut rig)[0], 2);
    // 3: 9 parameters in group 2.
    rig.configure(&[[4096, 8, 0, 1], [4104, 8, 0, 1], [4112, 9, 0, 1]]);
    assert_eq!(attempt(&mut rig), [3, 3, 2, 4112, 9]);
    // 4: 13 x 8 = 104 longs produced.
    let produce: Vec<[i32; 4]> = (0..13).map(|g| [38912 + 8 * g, 8, 0, 1]).collect();
    rig.configure(&produce);
    assert_eq!(attempt(&mut rig)[0..3], [4, 13, 12]);
    // 5: 104 consumed.
    let consume: Vec<[i32; 4]> = (0..13).map(|g| [38912 + 8 * g, 8, 1, 2]).collect();
    rig.configure(&consume);
    assert_eq!(attempt(&mut rig)[0], 5);
    // 7 for a bad direction, a bad type, a count of 0, a range off the end.
    for bad in [
        [4096, 1, 2, 1],
        [4096, 1, 0, 3],
        [4096, 0, 0, 1],
        [39420, 8, 0, 2],
    ] {
        rig.configure(&[bad]);
        assert_eq!(attempt(&mut rig)[0], 7, "{bad:?}");
    }
    assert_eq!(rig.longs(37436, 1), [39424]);
    // Not counted as a connection; a valid configuration then connects.
    assert_eq!(rig.longs(37428, 1), [0]);
    rig.configure(&[[4096, 8, 0, 1]]);
    assert_eq!(
        rig.forward_open(&fo(99, 400, 400, 10_000, 10_000)).general,
        0
    );
    assert_eq!(rig.longs(37433, 5), [1, 1, 0, 4096, 8]);
}

#[test]
fn rpi_limits_sizes_and_configuration_data() {
    let mut rig = Rig::new();
    for (o_t, t_o) in [(500, 10_000), (10_000, 500)] {
        let r = rig.forward_open(&fo(1, 400, 400, o_t, t_o));
        assert_eq!(r.general, 0x01);
        assert!(matches!(r.extended, Some(0x0111 | 0x0112)), "{r:?}");
    }
    assert_eq!(rig.longs(37433, 1), [0]);
    // Sizes: 400 each way (data) and nothing else.
    for (o_t, t_o) in [(16, 400), (400, 16), (400, 404)] {
        assert_eq!(
            rig.forward_open(&fo(2, o_t, t_o, 1_000, 1_000)).general,
            0x01
        );
    }
    // Configuration data on instance 3 (the assembly has none): 0x0126.
    let path = [
        0x20, 0x04, 0x24, 0x03, 0x2C, 0x66, 0x2C, 0x65, 0x80, 0x01, 1, 2,
    ];
    let mut with_data = fo(3, 400, 400, 1_000, 1_000);
    with_data.path = &path;
    let r = rig.forward_open(&with_data);
    assert_eq!((r.general, r.extended), (0x01, Some(0x0126)));
    // Other assemblies: refused.
    let path = [0x20, 0x04, 0x24, 0x03, 0x2C, 0x66, 0x2C, 0x96];
    let mut other = fo(4, 400, 400, 1_000, 1_000);
    other.path = &path;
    assert_eq!(rig.forward_open(&other).general, 0x01);
    // Exactly 1 ms is accepted.
    assert_eq!(rig.forward_open(&fo(5, 400, 400, 1_000, 1_000)).general, 0);
}

#[test]
fn multicast_t_o() {
    let mut rig = Rig::new();
    let mut m = fo(1, 400, 400, 10_000, 10_000);
    m.t_o_params = params(MULTICAST, 402);
    let open = rig.forward_open(&m);
    assert_eq!(open.general, 0);
    rig.o_t(open.o_t_id, true, &[0; 400]);
    let sent = rig.advance(20_000);
    assert!(
        sent.iter().all(|(to, _)| to.ip().is_multicast()),
        "{sent:?}"
    );
}

#[test]
fn class3_connection_write_binary_and_status() {
    let mut rig = Rig::new();
    let mut c3 = fo(7, 0, 0, 100_000, 100_000);
    c3.transport = 0xA3;
    c3.o_t_params = params(P2P, 500);
    c3.t_o_params = params(P2P, 500);
    let path = [0x20, 0x02, 0x24, 0x01];
    c3.path = &path;
    let open = rig.forward_open(&c3);
    assert_eq!(open.general, 0, "{open:?}");
    assert_eq!(rig.longs(37424, 1), [2], "P37424: a Class 3 stream");
    // Binary Set Long P38912 = 66 runs over Class 3; a data packet request (Table 7 "No")
    // is refused with 0x08; unconnected, 0x10 (case 2).
    let binary = [
        0x34, 0x02, 0x20, 0x65, 0x24, 0x01, 0x00, 0x89, 0x00, 0x98, 66, 0, 0, 0,
    ];
    assert_eq!(rig.connected(open.o_t_id, 1, &binary), (0, vec![]));
    assert_eq!(rig.longs(38912, 1), [66]);
    let packet = [0x34, 0x02, 0x20, 0x65, 0x24, 0x01, 0x00, 0x18, 0x00, 0xFF];
    assert_eq!(rig.connected(open.o_t_id, 3, &packet).0, 0x08);
    assert_eq!(rig.ucmm(&binary).0, 0x10);
    assert_eq!(rig.scanner.adapter().device().binary_bytes, 8);
    // The same read over Class 3 and UCMM.
    let read = [
        0x53, 0x03, 0x20, 0x64, 0x25, 0x00, 0x08, 0x11, 0x03, 0, 0, 0,
    ];
    let (g, over_class3) = rig.connected(open.o_t_id, 2, &read);
    assert_eq!(g, 0);
    assert_eq!(over_class3, rig.ucmm(&read).2);
    // With a Class 1 connection too: two connections.
    let io = rig.forward_open(&fo(1, 400, 400, 10_000, 10_000));
    assert_eq!(io.general, 0);
    assert_eq!(rig.longs(37428, 1), [2]);
}

#[test]
fn intervals_are_reported_per_direction() {
    let mut rig = Rig::new();
    // O->T 20 ms, T->O 10 ms (R7.1): P37431 producing = 10, P37432 consuming = 20.
    let open = rig.forward_open(&fo(1, 400, 400, 20_000, 10_000));
    assert_eq!(open.general, 0);
    assert_eq!(rig.longs(37431, 3), [10, 20, 1]);
    assert_eq!(rig.longs(37429, 1), [0xC612_0001u32 as i32]);
}

/// R5.6's default: with a 4-group configuration (P = 16, C = 20 bytes) the exact sizes
/// connect (101/18, 102/26 on the wire) and T->O carries 16 bytes; below them is refused
/// with the 400-byte assembly as the acceptable size.
#[test]
fn exact_configured_sizes_connect() {
    exact_configured_sizes_connect_on(Rig::new());
}

/// The same through the run-time [`Profile`], which must forward the sizes the
/// configuration gives (`Device::accepts_connection_size`) rather than use the default.
#[test]
fn exact_configured_sizes_connect_through_the_profile_enum() {
    exact_configured_sizes_connect_on(Rig::with(Profile::from_name("parker-ipa").unwrap()));
}

fn exact_configured_sizes_connect_on<D: Device>(mut rig: Rig<D>) {
    rig.configure(&FOUR_GROUPS);
    let short = rig.forward_open(&fo(1, 16, 16, 10_000, 10_000));
    assert_eq!((short.general, short.extended), (0x01, Some(0x0127)));
    let short = rig.forward_open(&fo(2, 20, 12, 10_000, 10_000));
    assert_eq!((short.general, short.extended), (0x01, Some(0x0128)));
    let open = rig.forward_open(&fo(3, 20, 16, 10_000, 10_000));
    assert_eq!(open.general, 0);
    rig.write_longs(38913, &[77]);
    let sent = rig.advance(10_000);
    let data = &sent.last().unwrap().1;
    assert_eq!(data.len(), 16);
    assert_eq!(i32s(&data[0..8]), [0, 77]);
    let mut out = [0u8; 20];
    out[0..4].copy_from_slice(&5i32.to_le_bytes());
    rig.o_t(open.o_t_id, true, &out);
    assert_eq!(rig.longs(39000, 1), [5]);
}

/// A configuration written while a Class 1 connection runs changes nothing on it (the
/// layout latched at its Forward_Open stays, the connection is not closed); the next
/// Forward_Open uses it.
#[test]
fn a_configuration_change_waits_for_the_next_forward_open() {
    let mut rig = Rig::new();
    rig.write_longs(38912, &[11, 12]);
    rig.write_longs(39168, &[0, 0]);
    let open = rig.forward_open(&fo(1, 400, 400, 10_000, 10_000));
    assert_eq!(open.general, 0);
    rig.configure(&FOUR_GROUPS);
    let mut sent = Vec::new();
    for _ in 0..10 {
        rig.o_t(open.o_t_id, true, &[0; 400]);
        sent = rig.advance(10_000);
    }
    let data = &sent.last().expect("still producing").1;
    assert_eq!(data.len(), 400);
    assert_eq!(i32s(&data[160..168]), [11, 12], "the AOI layout still");
    assert_eq!(rig.longs(37433, 1), [1]);
    assert_eq!(rig.forward_close(1), 0);
    let open = rig.forward_open(&fo(2, 400, 400, 10_000, 10_000));
    assert_eq!(open.general, 0);
    let data = &rig.advance(10_000).last().unwrap().1.clone();
    assert_eq!(
        i32s(&data[0..8]),
        [11, 12],
        "group 0 of the new layout: P38912"
    );
}

/// The manual's "unlimited" Class 3 connections: 9 beside the Class 1 connection (the
/// stack's 10 slots), the next one refused with 0x0113.
#[test]
fn nine_class3_connections_beside_the_class1_connection() {
    let mut rig = Rig::new();
    assert_eq!(
        rig.forward_open(&fo(1, 400, 400, 10_000, 10_000)).general,
        0
    );
    let path = [0x20, 0x02, 0x24, 0x01];
    for serial in 10..20u16 {
        let mut c3 = fo(serial, 0, 0, 1_000_000, 1_000_000);
        c3.transport = 0xA3;
        c3.o_t_params = params(P2P, 500);
        c3.t_o_params = params(P2P, 500);
        c3.path = &path;
        let open = rig.forward_open(&c3);
        if serial < 19 {
            assert_eq!(open.general, 0, "Class 3 number {}", serial - 9);
        } else {
            assert_eq!((open.general, open.extended), (0x01, Some(0x0113)));
        }
    }
    assert_eq!(rig.longs(37428, 1), [10]);
}
