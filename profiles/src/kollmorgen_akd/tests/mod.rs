//! The profile as the stack sees it: the manual's handshake example and control bits
//! through the command assembly in virtual time, the response layout of the seed page,
//! explicit access to classes 0x25 and 0x0F with the manual's statuses, and Class 1
//! connections through the adapter's entry points.

mod class1;
mod dynamic_map;
mod explicit;
mod fidelity;
mod motion;
mod storage;

extern crate std;

use core::net::Ipv4Addr;
use std::vec;
use std::vec::Vec;

use enip_stack::cip::{CipError, CipResult, General};
use enip_stack::nv::{CutFlash, SharedStore};
use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use enip_stack::wire::forward_open::{ForwardOpenRepr, NetworkParams, Triad};
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
        g => (Err(CipError::new(General::try_from(g).unwrap())), data),
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
