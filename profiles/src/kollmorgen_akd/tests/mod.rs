//! The profile as the stack sees it: the manual's handshake example and control bits
//! through the command assembly in virtual time, the response layout of the seed page,
//! explicit access to classes 0x25 and 0x0F with the manual's statuses, and Class 1
//! connections through the adapter's entry points.

extern crate std;

use core::net::Ipv4Addr;
use std::vec;
use std::vec::Vec;

use enip_stack::cip::{CipError, CipResult, General};
use enip_stack::nv::{CutFlash, SharedStore};
use enip_stack::wire::epath::{LogicalType, Segment};
use enip_stack::wire::forward_open::{ForwardOpen, NetworkParams, Triad};
use enip_stack::wire::Writer;
use enip_stack::{Adapter, Device, Instant, NetworkConfig};

use super::assemblies::{control, status1, status2, COMMAND, RESPONSE};
use super::device::COUNTS_PER_REV;
use super::params::id;
use super::storage::NvCopy;
use super::KollmorgenAkd;
use crate::storage::testing;

const EN: u8 = control::ENABLE;
const LOAD: u8 = control::LOAD_START;
const DIR: u8 = control::DIRECTION;

/// A command assembly: control word, command byte 2, response byte 3, data bytes 4-7.
fn cmd(control: u8, command: u8, response: u8, data: i32) -> [u8; 64] {
    let mut c = [0u8; 64];
    c[0] = control;
    c[2] = command;
    c[3] = response;
    c[4..8].copy_from_slice(&data.to_le_bytes());
    c
}

/// A motion command (type 6 or 7) with position, velocity, acceleration and deceleration.
fn motion(control: u8, command: u8, position: i32, v: i32, acc: i32, dec: i32) -> [u8; 64] {
    let mut c = cmd(control, command, 0x20, 0);
    for (i, x) in [position, v, acc, dec].into_iter().enumerate() {
        c[8 + 4 * i..12 + 4 * i].copy_from_slice(&x.to_le_bytes());
    }
    c
}

/// `c` with response byte 3 set to `response`.
fn respond(mut c: [u8; 64], response: u8) -> [u8; 64] {
    c[3] = response;
    c
}

/// The drive driven directly through its Device hooks, in virtual time (1 ms steps).
struct Bench {
    akd: KollmorgenAkd,
    now: u64,
}

impl Bench {
    fn new() -> Self {
        let mut b = Bench {
            akd: KollmorgenAkd::new(),
            now: 0,
        };
        b.akd.poll(Instant(0));
        b
    }
    fn send(&mut self, c: [u8; 64]) -> [u8; 64] {
        self.akd.write_assembly(COMMAND, &c).unwrap();
        self.response()
    }
    fn response(&mut self) -> [u8; 64] {
        let mut r = [0u8; 64];
        assert_eq!(self.akd.read_assembly(RESPONSE, &mut r), Ok(64));
        r
    }
    fn run_ms(&mut self, ms: u64) -> [u8; 64] {
        for _ in 0..ms {
            self.now += 1_000;
            self.akd.poll(Instant(self.now));
        }
        self.response()
    }
    /// Runs until `f(response)` holds (at most `ms`); returns the milliseconds taken.
    fn until(&mut self, ms: u64, f: impl Fn(&[u8; 64]) -> bool) -> Option<u64> {
        (0..=ms).find(|_| {
            let r = self.run_ms(1);
            f(&r)
        })
    }
    fn explicit(
        &mut self,
        service: u8,
        class: u8,
        instance: u16,
        attr: Option<u8>,
        data: &[u8],
    ) -> (CipResult, Vec<u8>) {
        execute(
            &mut self.akd,
            &request(service, class, instance, attr, data),
            self.now,
        )
    }
    /// Enable, then home through HOME.MOVE (0x0F/205/1 = 1).
    fn enable_and_home(&mut self) {
        self.send(cmd(EN, 0x21, 0x20, 0));
        let (r, _) = self.explicit(0x10, 0x0F, id::HOME_MOVE, Some(1), &[1]);
        r.unwrap();
        assert!(self.until(100, |r| r[0] & status1::HOMED != 0).is_some());
    }
}

fn dint(r: &[u8], i: usize) -> i32 {
    i32::from_le_bytes([r[i], r[i + 1], r[i + 2], r[i + 3]])
}

/// Message Router request bytes: 8-bit class, 16-bit instance, optional attribute, data.
fn request(service: u8, class: u8, instance: u16, attribute: Option<u8>, data: &[u8]) -> Vec<u8> {
    let mut path = vec![0x20, class, 0x25, 0x00];
    path.extend_from_slice(&instance.to_le_bytes());
    if let Some(a) = attribute {
        path.extend_from_slice(&[0x30, a]);
    }
    let mut out = vec![service, (path.len() / 2) as u8];
    out.extend(path);
    out.extend_from_slice(data);
    out
}

fn net() -> NetworkConfig {
    NetworkConfig::new_static(
        Ipv4Addr::new(198, 18, 0, 2),
        Ipv4Addr::new(255, 255, 255, 0),
        [2, 0, 0, 0, 0, 1],
    )
}

/// Runs a Message Router request through the stack; the status and the reply data.
fn execute(akd: &mut KollmorgenAkd, bytes: &[u8], now: u64) -> (CipResult, Vec<u8>) {
    execute_with_store(akd, None, bytes, now)
}

/// [`execute`] with `store` attached to the adapter too (its TCP/IP settings).
fn execute_with_store(
    akd: &mut KollmorgenAkd,
    store: Option<SharedStore>,
    bytes: &[u8],
    now: u64,
) -> (CipResult, Vec<u8>) {
    let mut adapter = Adapter::new(core::mem::take(akd), net(), 1);
    if let Some(store) = store {
        // A store that cannot be read still serves, at factory settings.
        let _ = adapter.attach_store(std::boxed::Box::leak(std::boxed::Box::new(store)));
    }
    let mut buf = [0u8; 512];
    let n = adapter.execute(bytes, Instant(now), &mut buf);
    *akd = adapter.into_device();
    let reply = &buf[..n];
    let data = reply[4 + 2 * usize::from(reply[3])..].to_vec();
    match reply[2] {
        0 => (Ok(()), data),
        g => (Err(CipError::raw(g)), data),
    }
}

fn err(g: General) -> CipResult {
    Err(CipError::new(g))
}

#[test]
fn handshake_example_6_2_4() {
    // [HS]: the controller enables with a target position of 1000 (command axis 1 type 1,
    // response axis 1 type 0) and Load/Start 0; the amplifier answers 84 00 00 20 0...
    let mut b = Bench::new();
    b.explicit(0x10, 0x25, 1, Some(3), &[1]).0.unwrap(); // velocity mode: data only
    let step1 = [0x80, 0x00, 0x21, 0x20, 0xE8, 0x03, 0x00, 0x00];
    let mut c = [0u8; 64];
    c[..8].copy_from_slice(&step1);
    let r = b.send(c);
    assert_eq!(r[..8], [0x84, 0x00, 0x00, 0x20, 0x00, 0x00, 0x00, 0x00]);
    // Step 2: Load Complete is low, so the controller sets Load/Start.
    c[0] |= LOAD;
    let r = b.send(c);
    assert_eq!(r[2] & status2::LOAD_COMPLETE, status2::LOAD_COMPLETE);
    let (s, attr6) = b.explicit(0x0E, 0x25, 1, Some(6), &[]);
    s.unwrap();
    assert_eq!(attr6, 1000i32.to_le_bytes());
    // Target position in velocity mode starts no motion.
    let r = b.run_ms(50);
    assert_eq!(r[0] & status1::IN_MOTION, 0);
    assert_eq!(dint(&r, 8), 0);
    // Step 3: Load/Start cleared, Load Complete follows.
    c[0] &= !LOAD;
    let r = b.send(c);
    assert_eq!(r[2] & status2::LOAD_COMPLETE, 0);
}

#[test]
fn data_is_taken_only_on_the_load_start_edge() {
    let mut b = Bench::new();
    b.send(cmd(EN, 0x02, 0x20, 100));
    let r = b.send(cmd(EN | LOAD, 0x02, 0x20, 100));
    assert_ne!(r[2] & status2::LOAD_COMPLETE, 0);
    // Changed data while Load/Start stays 1: not loaded.
    b.send(cmd(EN | LOAD, 0x02, 0x20, 5555));
    let get = |b: &mut Bench| b.explicit(0x0E, 0x25, 1, Some(7), &[]).1;
    assert_eq!(get(&mut b), 100i32.to_le_bytes());
    // Load Complete stays set while Load/Start stays set, clears with it.
    assert_ne!(b.run_ms(30)[2] & status2::LOAD_COMPLETE, 0);
    assert_eq!(
        b.send(cmd(EN, 0x02, 0x20, 5555))[2] & status2::LOAD_COMPLETE,
        0
    );
    b.send(cmd(EN | LOAD, 0x02, 0x20, 5555));
    assert_eq!(get(&mut b), 5555i32.to_le_bytes());
}

#[test]
fn a_refused_load_answers_the_error_response() {
    let mut b = Bench::new();
    b.send(cmd(EN, 0x2A, 0x25, 7));
    let r = b.send(cmd(EN | LOAD, 0x2A, 0x25, 7));
    // Type 0x14 (axis bits of byte 3 kept), invalid parameter 0x20, additional 0xFF,
    // echo of command bytes 2-3; Load Complete 0.
    assert_eq!(r[3], 0x34);
    assert_eq!(r[4..8], [0x20, 0xFF, 0x2A, 0x25]);
    assert_eq!(r[2] & status2::LOAD_COMPLETE, 0);
    // Kept after Load/Start clears, until the next successful load.
    let r = b.send(cmd(EN, 0x2A, 0x25, 7));
    assert_eq!((r[3], r[4]), (0x34, 0x20));
    b.send(cmd(EN | LOAD, 0x22, 0x25, 100));
    let r = b.response();
    assert_eq!(r[3], 0x25);
    assert_ne!(r[2] & status2::LOAD_COMPLETE, 0);
    // An axis other than 0/1, and data out of range (a zero velocity), are refused too.
    b.send(cmd(EN, 0x41, 0x20, 0));
    assert_eq!(
        b.send(cmd(EN | LOAD, 0x41, 0x20, 0))[4..8],
        [0x20, 0xFF, 0x41, 0x20]
    );
    b.send(cmd(EN, 0x27, 0x20, 0));
    let r = b.send(motion(EN | LOAD, 0x27, 0, 0, 100, 100));
    assert_eq!(r[4..8], [0x09, 0xFF, 0x27, 0x20]);
    // Start Block: motion tasks are not modelled (object does not exist).
    b.send(cmd(EN, 0x21, 0x20, 0));
    let r = b.send(cmd(EN | control::START_BLOCK, 0x21, 0x20, 0));
    assert_eq!(r[4..8], [0x16, 0xFF, 0x21, 0x20]);
}

#[test]
fn response_layout_of_the_seed_page() {
    let mut b = Bench::new();
    let mut c = cmd(EN, 0x21, 0x23, 0);
    c[32] = 3; // attribute to get: mode
    let r = b.send(c);
    assert_eq!(r[3], 0x23);
    assert_eq!(r[32], 3);
    assert_eq!(r[24..32], [0; 8]); // mode 0
    assert_eq!(r[33], 0);
    assert_eq!(r[20..24], [0; 4]);
    assert_eq!(r[34..64], [0; 30]);
    // Attribute to Get follows an explicit change in the next response.
    b.explicit(0x10, 0x25, 1, Some(3), &[1]).0.unwrap();
    assert_eq!(b.response()[24], 1);
    c[32] = 4; // position units: 65536, four bytes
    assert_eq!(b.send(c)[24..32], [0, 0, 1, 0, 0, 0, 0, 0]);
    c[32] = 200; // no such attribute: zeros
    assert_eq!(b.send(c)[24..32], [0; 8]);
    // Custom map 1 fills bytes 36-63; map type mirrors byte 33.
    c[32] = 0;
    c[33] = 1;
    let r = b.send(c);
    assert_eq!(r[33], 1);
    assert_eq!(dint(&r, 52), 65_536); // target velocity
    assert_eq!(dint(&r, 56), 1); // mode
    c[33] = 2;
    assert_eq!(b.send(c)[36..64], [0; 28]);
}

#[test]
fn jog_follows_the_direction_bit_and_smooth_stop_stops_it() {
    let mut b = Bench::new();
    b.explicit(0x10, 0x25, 1, Some(3), &[1]).0.unwrap();
    b.send(cmd(EN, 0x27, 0x23, 0));
    // 1000 units/s, 10000 units/s²: at speed after 100 ms.
    let jog = |c| respond(motion(c, 0x27, 0, 1000, 10_000, 10_000), 0x23);
    b.send(jog(EN | DIR | LOAD));
    let r = b.run_ms(150);
    assert_ne!(r[0] & status1::IN_MOTION, 0);
    assert_eq!(dint(&r, 12), 1000);
    assert_eq!(dint(&r, 4), 1000); // response type 3: actual velocity
    assert_ne!(r[0] & status1::DIRECTION, 0);
    assert!(dint(&r, 8) > 0);
    assert_ne!(
        u32::from_le_bytes([r[16], r[17], r[18], r[19]]) & (1 << 12),
        0
    );
    // Smooth Stop: velocity 0 and In Motion 0 after 100 ms of deceleration.
    b.send(jog(EN | DIR | control::SMOOTH_STOP));
    let t = b.until(1000, |r| r[0] & status1::IN_MOTION == 0).unwrap();
    assert!((95..=110).contains(&t), "stopped after {t} ms");
    assert_eq!(dint(&b.response(), 12), 0);
    // The other direction.
    b.send(jog(EN));
    b.send(jog(EN | LOAD));
    let r = b.run_ms(150);
    assert_eq!(dint(&r, 12), -1000);
    assert_eq!(r[0] & status1::DIRECTION, 0);
}

#[test]
fn hard_stop_needs_an_enable_cycle() {
    let mut b = Bench::new();
    b.explicit(0x10, 0x25, 1, Some(3), &[1]).0.unwrap();
    let jog = |c| motion(c, 0x27, 0, 1000, 10_000, 10_000);
    b.send(jog(EN | DIR));
    b.send(jog(EN | DIR | LOAD));
    b.run_ms(200);
    b.send(jog(EN | DIR | control::HARD_STOP));
    let t = b.until(1000, |r| r[0] & status1::IN_MOTION == 0).unwrap();
    assert!(t < 10, "DRV.DECSTOP is fast: {t} ms");
    let r = b.response();
    assert_eq!(r[0] & status1::ENABLED, 0);
    // A new load without an enable cycle starts no motion.
    b.send(jog(EN | DIR));
    b.send(jog(EN | DIR | LOAD));
    assert_eq!(b.run_ms(100)[0] & status1::IN_MOTION, 0);
    // After Enable 0 -> 1 it does.
    b.send(jog(DIR));
    b.send(jog(EN | DIR));
    assert_ne!(b.response()[0] & status1::ENABLED, 0);
    b.send(jog(EN | DIR | LOAD));
    assert_ne!(b.run_ms(50)[0] & status1::IN_MOTION, 0);
}

#[test]
fn move_before_homing_faults_and_an_enable_cycle_clears_it() {
    let mut b = Bench::new();
    b.send(cmd(EN, 0x26, 0x20, 0));
    let r = b.send(motion(EN | LOAD, 0x26, 1000, 1000, 10_000, 10_000));
    assert_ne!(r[0] & status1::FAULT, 0);
    assert_eq!(r[0] & status1::ENABLED, 0);
    assert_eq!(r[4..8], [0x10, 0xFF, 0x26, 0x20]);
    assert_eq!(b.run_ms(100)[0] & status1::IN_MOTION, 0);
    // The fault persists until the enable cycle.
    b.send(cmd(EN, 0x26, 0x20, 0));
    assert_ne!(b.response()[0] & status1::FAULT, 0);
    b.send(cmd(0, 0x26, 0x20, 0));
    let r = b.send(cmd(EN, 0x26, 0x20, 0));
    assert_eq!(r[0] & status1::FAULT, 0);
    assert_ne!(r[0] & status1::ENABLED, 0);
    // Or DRV.CLRFAULTS.
    b.send(motion(EN | LOAD, 0x26, 1000, 1000, 10_000, 10_000));
    assert_ne!(b.response()[0] & status1::FAULT, 0);
    b.explicit(0x10, 0x0F, id::DRV_CLRFAULTS, Some(1), &[1])
        .0
        .unwrap();
    assert_eq!(b.response()[0] & status1::FAULT, 0);
}

#[test]
fn after_homing_an_absolute_move_ends_in_position_at_the_target() {
    let mut b = Bench::new();
    b.enable_and_home();
    let r = b.response();
    assert_eq!(dint(&r, 8), 0);
    let ms = u32::from_le_bytes([r[16], r[17], r[18], r[19]]);
    assert_eq!(ms & 0b110, 0b110, "MOTIONSTAT home found and finished");
    b.send(cmd(EN, 0x26, 0x21, 0));
    b.send(respond(
        motion(EN | LOAD, 0x26, 5000, 2000, 20_000, 20_000),
        0x21,
    ));
    assert_ne!(b.run_ms(10)[0] & status1::IN_MOTION, 0);
    // 5000 units at 2000 units/s with 100 ms ramps: 2.6 s.
    let t = b.until(5000, |r| r[0] & status1::IN_MOTION == 0).unwrap();
    assert!((2550..=2700).contains(&t), "{t} ms");
    let r = b.response();
    assert_eq!(dint(&r, 8), 5000);
    assert_eq!(dint(&r, 4), 5000); // response type 1
    assert_ne!(r[0] & status1::IN_POSITION, 0);
    let ms = u32::from_le_bytes([r[16], r[17], r[18], r[19]]);
    assert_eq!(ms & (1 << 11 | 1 << 15), 1 << 11 | 1 << 15);
    // Relative: from 5000, -1500 more.
    b.send(motion(EN, 0x26, -1500, 2000, 20_000, 20_000));
    b.send(motion(
        EN | LOAD | control::RELATIVE,
        0x26,
        -1500,
        2000,
        20_000,
        20_000,
    ));
    b.until(5000, |r| r[0] & status1::IN_MOTION == 0).unwrap();
    assert_eq!(dint(&b.response(), 8), 3500);
    // Target position (type 1) in position mode moves at attribute 7's velocity.
    b.send(cmd(EN, 0x21, 0x21, 3600));
    b.send(cmd(EN | LOAD, 0x21, 0x21, 3600));
    b.until(5000, |r| r[0] & status1::IN_MOTION == 0).unwrap();
    assert_eq!(dint(&b.response(), 8), 3600);
}

#[test]
fn start_block_runs_a_stored_motion_task() {
    let mut b = Bench::new();
    b.enable_and_home();
    let set = |b: &mut Bench, i: u16, d: &[u8]| b.explicit(0x10, 0x0F, i, Some(1), d).0.unwrap();
    // Task 3: absolute 2000 at 2000 units/s, 20000 units/s² (MT.NUM, MT.P..., MT.SET).
    set(&mut b, id::MT_NUM, &[3]);
    set(&mut b, id::MT_P, &2000i64.to_le_bytes());
    set(&mut b, id::MT_V, &2000i64.to_le_bytes());
    set(&mut b, id::MT_ACC, &20_000i64.to_le_bytes());
    set(&mut b, id::MT_DEC, &20_000i64.to_le_bytes());
    set(&mut b, id::MT_SET, &[1]);
    set(&mut b, id::MT_P, &0i64.to_le_bytes());
    set(&mut b, id::MT_LOAD, &[1]);
    assert_eq!(
        b.explicit(0x0E, 0x0F, id::MT_P, Some(1), &[]).1,
        2000i64.to_le_bytes()
    );
    let mut c = cmd(EN, 0x21, 0x20, 0);
    c[1] = 3;
    b.send(c);
    c[0] |= control::START_BLOCK;
    b.send(c);
    let r = b.run_ms(100);
    assert_eq!((r[1], r[0] & status1::BLOCK), (3, status1::BLOCK));
    assert_eq!(r[3], 0x20, "no error response");
    b.until(5_000, |r| r[0] & status1::IN_MOTION == 0).unwrap();
    let r = b.response();
    assert_eq!((r[1], r[0] & status1::BLOCK, dint(&r, 8)), (0, 0, 2000));
    // An undefined task: the error response with 0x16.
    c[1] = 4;
    c[0] = EN;
    b.send(c);
    c[0] |= control::START_BLOCK;
    assert_eq!(b.send(c)[4..8], [0x16, 0xFF, 0x21, 0x20]);
}

#[test]
fn torque_mode_and_the_torque_response() {
    let mut b = Bench::new();
    b.explicit(0x10, 0x25, 1, Some(3), &[2]).0.unwrap();
    b.send(cmd(EN, 0x25, 0x25, 0));
    b.send(cmd(EN | LOAD, 0x25, 0x25, 500));
    let r = b.run_ms(5_000);
    // Velocity settles at torque x TORQUE_K counts/s: 500 units/s; torque 500 mA.
    assert!((495..=500).contains(&dint(&r, 12)), "{}", dint(&r, 12));
    assert!((495..=505).contains(&dint(&r, 4)), "{}", dint(&r, 4));
    let (s, t) = b.explicit(0x0E, 0x25, 1, Some(25), &[]);
    s.unwrap();
    assert_eq!(t, r[4..8]);
}

#[test]
fn set_attribute_and_parameter_commands_over_io() {
    let mut b = Bench::new();
    // 0x1B: attribute id in byte 24, value in bytes 4-7: mode := 1.
    let mut c = cmd(EN, 0x3B, 0x20, 1);
    c[24] = 3;
    b.send(c);
    c[0] |= LOAD;
    assert_ne!(b.send(c)[2] & status2::LOAD_COMPLETE, 0);
    assert_eq!(b.explicit(0x0E, 0x25, 1, Some(3), &[]).1, [1]);
    // 0x1F write: instance in bytes 4-5, byte 6 = 1, value in 24-31 (MT.TPOSWND := 3).
    let mut c = cmd(EN, 0x3F, 0x20, 0);
    c[4..7].copy_from_slice(&[
        (id::MT_TPOSWND & 0xFF) as u8,
        (id::MT_TPOSWND >> 8) as u8,
        1,
    ]);
    c[24] = 3;
    b.send(c);
    c[0] |= LOAD;
    let r = b.send(c);
    assert_eq!(r[24..32], [3, 0, 0, 0, 0, 0, 0, 0]);
    // 0x1F read of EIP.PROFUNIT (4 bytes).
    let mut c = cmd(EN, 0x3F, 0x20, 0);
    c[4..7].copy_from_slice(&[
        (id::EIP_PROFUNIT & 0xFF) as u8,
        (id::EIP_PROFUNIT >> 8) as u8,
        0,
    ]);
    b.send(c);
    c[0] |= LOAD;
    assert_eq!(b.send(c)[24..32], [0, 0, 1, 0, 0, 0, 0, 0]);
    // A read-only attribute through 0x1B: 0x0E in the error response.
    let mut c = cmd(EN, 0x3B, 0x20, 1);
    c[24] = 1;
    b.send(c);
    c[0] |= LOAD;
    assert_eq!(b.send(c)[4..8], [0x0E, 0xFF, 0x3B, 0x20]);
}

#[test]
fn position_controller_statuses() {
    let mut b = Bench::new();
    let mut get = |a: u8| b.explicit(0x0E, 0x25, 1, Some(a), &[]);
    assert_eq!(get(1), (Ok(()), vec![16]));
    let (s, list) = get(2);
    s.unwrap();
    assert_eq!(
        list,
        [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 17, 25, 58, 100, 101]
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
    // Classes the drive does not have: 0x16, "Class Not Supported".
    assert_eq!(
        b.explicit(0x0E, 0x24, 1, Some(1), &[]).0,
        err(General::ObjectDoesNotExist)
    );
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
fn nvsave_survives_a_reset_and_factory_reset_clears_it() {
    let mut b = Bench::new();
    let set = |b: &mut Bench, i: u16, d: &[u8]| b.explicit(0x10, 0x0F, i, Some(1), d).0.unwrap();
    set(&mut b, id::EIP_POSUNIT, &1000u32.to_le_bytes());
    set(&mut b, 1, &1234u32.to_le_bytes());
    set(&mut b, id::DRV_NVSAVE, &[1]);
    set(&mut b, 1, &1u32.to_le_bytes());
    b.akd.reset(0).unwrap();
    let get = |b: &mut Bench, i: u16| b.explicit(0x0E, 0x0F, i, Some(1), &[]).1;
    assert_eq!(get(&mut b, 1), 1234u32.to_le_bytes());
    assert_eq!(get(&mut b, id::EIP_POSUNIT), 1000u32.to_le_bytes());
    b.akd.reset(1).unwrap();
    assert_eq!(get(&mut b, 1), 5_000_000u32.to_le_bytes());
}

/// Parameter 1 as a fresh drive powered up from `store` reads it.
fn parameter_1_after_power_up(store: SharedStore) -> Vec<u8> {
    let mut akd = KollmorgenAkd::with_storage(NvCopy::in_store(store));
    execute(&mut akd, &request(0x0E, 0x0F, 1, Some(1), &[]), 0).1
}

/// Sets parameter 1 to `value` and saves with DRV.NVSAVE; true if both succeeded.
fn set_and_save(store: SharedStore, value: u32) -> bool {
    let mut akd = KollmorgenAkd::with_storage(NvCopy::in_store(store));
    let mut ok = |i: u16, d: &[u8]| execute(&mut akd, &request(0x10, 0x0F, i, Some(1), d), 0).0;
    ok(1, &value.to_le_bytes()).is_ok() && ok(id::DRV_NVSAVE, &[1]).is_ok()
}

#[test]
fn nvsave_survives_a_restart_in_the_store() {
    let store = testing::store();
    assert!(set_and_save(store, 1234));
    assert_eq!(parameter_1_after_power_up(store), 1234u32.to_le_bytes());
    let mut akd = KollmorgenAkd::with_storage(NvCopy::in_store(store));
    akd.reset(1).unwrap();
    assert_eq!(
        parameter_1_after_power_up(store),
        5_000_000u32.to_le_bytes()
    );
    // A store that cannot write refuses DRV.NVSAVE.
    let mut dead = CutFlash::new();
    dead.cut_after(0);
    assert!(!set_and_save(testing::store_on(dead).0, 7));
}

#[test]
fn every_power_cut_during_nvsave_keeps_the_old_or_the_new_parameters() {
    let steps = testing::every_power_cut(
        |store| assert!(set_and_save(store, 1234)),
        |store| set_and_save(store, 4321),
        parameter_1_after_power_up,
    );
    assert!(steps > 50, "{steps} steps");
}

/// Sends `bytes` to an adapter of a drive powered up from `store`, with the store attached
/// to the adapter too; whether it succeeded.
fn execute_on_store(store: SharedStore, bytes: &[u8]) -> bool {
    let mut akd = KollmorgenAkd::with_storage(NvCopy::in_store(store));
    execute_with_store(&mut akd, Some(store), bytes, 0)
        .0
        .is_ok()
}

/// Identity Reset type 1 (factory defaults) through the adapter.
fn factory_reset(store: SharedStore) -> bool {
    execute_on_store(store, &request(0x05, 0x01, 1, None, &[1]))
}

#[test]
fn every_power_cut_during_a_factory_reset_keeps_the_parameters_and_the_address_together() {
    use enip_stack::cip::tcpip::TcpIpState;
    let host_name = request(0x10, 0xF5, 1, Some(6), &[4, 0, b'a', b'k', b'd', b'1']);
    let steps = testing::every_power_cut(
        |store| {
            assert!(set_and_save(store, 1234));
            assert!(execute_on_store(store, &host_name));
        },
        factory_reset,
        |mut store| {
            let tcpip = TcpIpState::stored(&mut store).ok().flatten().is_some();
            (parameter_1_after_power_up(store), tcpip)
        },
    );
    // One save: the erase, the copy's header and CRC (3 units), the commit word.
    assert_eq!(steps, 5);
}

#[test]
fn software_limits_stop_and_report() {
    let mut b = Bench::new();
    b.enable_and_home();
    let set = |b: &mut Bench, i: u16, d: &[u8]| b.explicit(0x10, 0x0F, i, Some(1), d).0.unwrap();
    set(&mut b, id::SWLS_LIMIT1, &1000i64.to_le_bytes());
    set(&mut b, id::SWLS_EN, &[1]);
    b.send(motion(EN, 0x26, 5000, 2000, 20_000, 20_000));
    b.send(motion(EN | LOAD, 0x26, 5000, 2000, 20_000, 20_000));
    b.until(5000, |r| r[0] & status1::IN_MOTION == 0).unwrap();
    let r = b.response();
    assert!((1000..1100).contains(&dint(&r, 8)), "{}", dint(&r, 8));
    assert_ne!(r[2] & status2::POSITIVE_SW_LIMIT, 0);
    assert_eq!(r[2] & status2::NEGATIVE_SW_LIMIT, 0);
}

#[test]
fn units_scale_position_and_velocity() {
    let mut b = Bench::new();
    b.enable_and_home();
    // One position unit = one revolution.
    let units = (COUNTS_PER_REV as u32).to_le_bytes();
    assert_eq!(
        b.explicit(0x10, 0x25, 1, Some(4), &units).0,
        err(General::InvalidAttributeValue)
    );
    b.explicit(0x10, 0x25, 1, Some(4), &(1u32 << 20).to_le_bytes())
        .0
        .unwrap();
    b.send(motion(EN, 0x26, 100, 2000, 20_000, 20_000));
    b.send(motion(EN | LOAD, 0x26, 100, 2000, 20_000, 20_000));
    b.until(10_000, |r| r[0] & status1::IN_MOTION == 0).unwrap();
    let r = b.response();
    assert_eq!(dint(&r, 8), 100);
    assert_eq!(b.akd.state().drive.position(), 100 << 20);
}

#[test]
fn arbitrary_commands_never_panic() {
    // A fixed xorshift sequence: every command byte, extreme values, unit changes.
    let mut b = Bench::new();
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x
    };
    b.send(cmd(EN, 0x21, 0x20, 0));
    b.explicit(0x10, 0x0F, id::HOME_MOVE, Some(1), &[1])
        .0
        .unwrap();
    b.run_ms(50);
    let lists: [(u16, [u16; 7]); 2] = [
        (
            id::EIP_CMDMAP,
            [
                id::EIP_POSUNIT,
                id::MT_NUM,
                id::HOME_P,
                id::SWLS_EN,
                4,
                0,
                id::DRV_ACC + 1,
            ],
        ),
        (
            id::EIP_RSPMAP,
            [
                id::PL_FB,
                id::VL_FB + 1,
                id::IL_FB,
                id::HOME_P,
                4,
                0,
                id::MT_NUM,
            ],
        ),
    ];
    for (instance, entries) in lists {
        let data: Vec<u8> = entries.iter().flat_map(|e| e.to_le_bytes()).collect();
        b.explicit(0x10, 0x0F, instance, Some(1), &data).0.unwrap();
    }
    for i in 0..3_000 {
        let mut c = [0u8; 64];
        for chunk in c.chunks_mut(8) {
            let v = next().to_le_bytes();
            chunk.copy_from_slice(&v[..chunk.len()]);
        }
        c[2] = [0x21, 0x22, 0x23, 0x24, 0x25, 0x26, 0x27, 0x3B, 0x3F, c[2]][i % 10];
        if i % 5 == 0 {
            c[33] = 2;
        }
        if i % 7 == 0 {
            c[12..16].copy_from_slice(&i32::MAX.to_le_bytes());
            c[8..12].copy_from_slice(&i32::MIN.to_le_bytes());
        }
        if i % 97 == 0 {
            let units = [1u32, u32::MAX, 65_536][i % 3];
            let _ = b.explicit(0x10, 0x25, 1, Some(4), &units.to_le_bytes());
            let _ = b.explicit(0x10, 0x25, 1, Some(3), &[(i % 3) as u8]);
        }
        b.send(c);
        b.run_ms(3);
    }
}

mod dynamic_map;

/// The Class 1 path through the adapter: admission, sizes and the datagrams.
mod class1 {
    use super::*;
    use enip_stack::virtual_scanner::{Opened, VirtualScanner};

    /// The drive behind a virtual scanner.
    struct Scanner {
        scanner: VirtualScanner<KollmorgenAkd>,
    }

    impl Scanner {
        fn new() -> Self {
            Scanner {
                scanner: VirtualScanner::new(KollmorgenAkd::new()),
            }
        }
        /// Forward_Open 101 -> 102 with config 100.
        fn open(&mut self, rpi: u32, t_o_type: u16, transport: u8) -> Opened {
            let segs = [
                Segment::Logical(LogicalType::Class, 4),
                Segment::Logical(LogicalType::Instance, 100),
                Segment::Logical(LogicalType::ConnectionPoint, 101),
                Segment::Logical(LogicalType::ConnectionPoint, 102),
            ];
            let mut path = [0u8; 32];
            let mut w = Writer::new(&mut path);
            for s in &segs {
                s.emit(&mut w).unwrap();
            }
            let n = w.len();
            let fo = ForwardOpen {
                large: false,
                priority_tick: 0x0A,
                timeout_ticks: 0x0E,
                o_t_connection_id: 0,
                t_o_connection_id: 0x7000_0001,
                triad: Triad {
                    connection_serial: 1,
                    vendor_id: 0x1337,
                    originator_serial: 7,
                },
                timeout_multiplier: 1,
                o_t_rpi: rpi,
                o_t_params: NetworkParams::from_u16(0x4800 | (2 + 4 + 64)),
                t_o_rpi: rpi,
                t_o_params: NetworkParams::from_u16(t_o_type | (2 + 64)),
                transport,
                path: &path[..n],
            };
            self.scanner.forward_open(&fo)
        }
    }

    #[test]
    fn rpi_limits_and_triggers() {
        let mut s = Scanner::new();
        let o = s.open(5_000, 0x4800, 0x01);
        assert_eq!((o.general, o.extended), (0x01, Some(0x0112)));
        let o = s.open(10_000, 0x4800, 0x11);
        assert_eq!((o.general, o.extended), (0x01, Some(0x0103)));
        assert_eq!(
            s.open(10_000, 0x2800, 0x01).general,
            0,
            "multicast T->O at 10 ms"
        );
    }

    #[test]
    fn exclusive_owner_at_ten_milliseconds() {
        let mut s = Scanner::new();
        let o = s.open(10_000, 0x4800, 0x01);
        assert_eq!(o.general, 0);
        let mut c = cmd(EN, 0x21, 0x20, 1000);
        let mut seen = Vec::new();
        for k in 1..=20u32 {
            if k == 10 {
                c[0] |= LOAD;
            }
            s.scanner.send_io(o.o_t_id, Some(true), &c).unwrap();
            s.scanner.advance(10_000, |_, data| {
                assert_eq!(data.len(), 64);
                seen.push(data.to_vec());
            });
        }
        assert!(seen.len() >= 19, "{} datagrams", seen.len());
        let first = &seen[1];
        assert_eq!(first[..8], [0x84, 0, 0, 0x20, 0, 0, 0, 0]);
        // The load in position mode before homing: General Fault and the error response.
        let last = seen.last().unwrap();
        assert_ne!(last[0] & status1::FAULT, 0);
        assert_eq!(last[3], 0x34);
    }

    #[test]
    fn losing_the_owner_disables_the_drive() {
        let mut s = Scanner::new();
        let o = s.open(10_000, 0x4800, 0x01);
        assert_eq!(o.general, 0);
        s.scanner.advance(10_000, |_, _| {});
        let c = cmd(EN, 0x21, 0x20, 0);
        s.scanner.send_io(o.o_t_id, Some(true), &c).unwrap();
        assert!(s.scanner.adapter().device().state().drive.enabled());
        // Multiplier code 1: x8, so 80 ms without data closes the connection.
        s.scanner.advance(190_000, |_, _| {});
        assert!(s.scanner.adapter().connections().is_empty());
        assert!(!s.scanner.adapter().device().state().drive.enabled());
    }
}
