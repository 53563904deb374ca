//! Map type 2: EIP.CMDMAP / EIP.RSPMAP over explicit messaging and bytes 36-63 of the
//! command and response assemblies.

use super::*;

const RSPMAP: u16 = id::EIP_RSPMAP;
const CMDMAP: u16 = id::EIP_CMDMAP;

/// A list value: up to 7 instances, the rest 0.
fn list(entries: &[u16]) -> Vec<u8> {
    let mut out = vec![0u8; 14];
    for (pair, e) in out.chunks_exact_mut(2).zip(entries) {
        pair.copy_from_slice(&e.to_le_bytes());
    }
    out
}

/// `c` with map type `map` and the dynamic map slots `slots`.
fn mapped(mut c: [u8; 64], map: u8, slots: &[i32]) -> [u8; 64] {
    c[33] = map;
    for (k, v) in slots.iter().enumerate() {
        c[36 + 4 * k..40 + 4 * k].copy_from_slice(&v.to_le_bytes());
    }
    c
}

fn slot(r: &[u8], k: usize) -> i32 {
    dint(r, 36 + 4 * k)
}

impl Bench {
    fn set_list(&mut self, instance: u16, entries: &[u16]) -> CipResult {
        self.explicit(0x10, 0x0F, instance, Some(1), &list(entries))
            .0
    }
    fn get_param(&mut self, instance: u16) -> Vec<u8> {
        let (r, data) = self.explicit(0x0E, 0x0F, instance, Some(1), &[]);
        r.unwrap();
        data
    }
}

#[test]
fn the_lists_are_parameters_with_the_documented_statuses() {
    let mut b = Bench::new();
    for map in [CMDMAP, RSPMAP] {
        assert_eq!(
            b.explicit(0x0E, 0x0F, map, Some(1), &[]),
            (Ok(()), list(&[]))
        );
        assert_eq!(
            b.explicit(0x0E, 0x0F, map, Some(5), &[]),
            (Ok(()), vec![0xC7])
        );
        assert_eq!(
            b.explicit(0x0E, 0x0F, map, Some(6), &[]),
            (Ok(()), vec![14])
        );
        assert_eq!(
            b.explicit(0x0E, 0x0F, map, Some(2), &[]).0,
            err(General::AttributeNotSupported)
        );
    }
    assert_eq!(
        b.explicit(0x0E, 0x0F, RSPMAP + 1, Some(1), &[]).0,
        err(General::ObjectDoesNotExist)
    );
    // Class attribute 2, the highest instance, is EIP.RSPMAP's.
    assert_eq!(
        b.explicit(0x0E, 0x0F, 0, Some(2), &[]),
        (Ok(()), RSPMAP.to_le_bytes().to_vec())
    );
    // Not through command type 0x1F: 14 bytes do not fit bytes 24-31 (unknown instance).
    b.send(cmd(EN, 0x1F, 0x20, i32::from(RSPMAP)));
    assert_eq!(
        b.send(cmd(EN | LOAD, 0x1F, 0x20, i32::from(RSPMAP)))[4],
        0x16
    );
    // Read-only and read-write parameters in the response list, low words of 8-byte ones.
    let rsp = [id::PL_FB, 4, id::DRV_MOTIONSTAT, 0, id::HOME_P + 1, 0, 1];
    b.set_list(RSPMAP, &rsp).unwrap();
    assert_eq!(b.get_param(RSPMAP), list(&rsp));
    // Refused, changing nothing: unknown instance, a command, a list, wrong lengths.
    for bad in [[12u16], [id::HOME_MOVE], [RSPMAP], [CMDMAP]] {
        assert_eq!(
            b.set_list(RSPMAP, &[id::PL_FB, 4, bad[0]]),
            err(General::InvalidAttributeValue)
        );
    }
    let set = |b: &mut Bench, d: &[u8]| b.explicit(0x10, 0x0F, RSPMAP, Some(1), d).0;
    assert_eq!(set(&mut b, &[0; 13]), err(General::NotEnoughData));
    assert_eq!(set(&mut b, &[0; 15]), err(General::TooMuchData));
    assert_eq!(b.get_param(RSPMAP), list(&rsp));
    // The command list takes read-write parameters only.
    assert_eq!(
        b.set_list(CMDMAP, &[id::MT_TPOSWND, id::PL_FB]),
        err(General::InvalidAttributeValue)
    );
    assert_eq!(b.get_param(CMDMAP), list(&[]));
    b.set_list(CMDMAP, &[id::MT_TPOSWND, id::HOME_P + 1])
        .unwrap();
    assert_eq!(b.get_param(CMDMAP), list(&[id::MT_TPOSWND, id::HOME_P + 1]));
    // Power-up (Identity reset) empties them.
    b.akd.reset(0).unwrap();
    assert_eq!(b.get_param(CMDMAP), list(&[]));
}

#[test]
fn map_type_2_response_carries_the_rspmap_values_every_cycle() {
    let mut b = Bench::new();
    b.explicit(0x10, 0x0F, 4, Some(1), &(-3i16).to_le_bytes())
        .0
        .unwrap();
    let rsp = [
        id::PL_FB,
        4,
        id::EIP_PROFUNIT,
        0,
        id::VL_FB + 1,
        id::DRV_MOTIONSTAT,
        id::MT_TPOSWND,
    ];
    b.set_list(RSPMAP, &rsp).unwrap();
    // Velocity mode: a jog in position mode would need homing first (p.11).
    b.explicit(0x10, 0x25, 1, Some(3), &[1]).0.unwrap();
    b.send(cmd(EN, 0x27, 0x20, 0));
    let r = b.send(mapped(
        motion(EN | LOAD | DIR, 0x27, 0, 1000, 10_000, 10_000),
        2,
        &[],
    ));
    assert_eq!(r[33], 2);
    assert_eq!(slot(&r, 1), -3); // AIN.OFFSET, sign-extended
    assert_eq!(slot(&r, 2), 65_536); // EIP.PROFUNIT
    assert_eq!(slot(&r, 3), 0); // empty slot
    assert_eq!(slot(&r, 6), 32_768); // MT.TPOSWND, 0.5 rev
                                     // A jog: position and velocity follow the drive in every response.
    for _ in 0..5 {
        let r = b.run_ms(40);
        assert_eq!(slot(&r, 0), dint(&r, 8));
        assert_eq!(slot(&r, 4), dint(&r, 12));
        assert_eq!(slot(&r, 5), dint(&r, 16));
    }
    let r = b.response();
    assert!(slot(&r, 0) > 0 && slot(&r, 4) > 0);
    // Map type 0: bytes 36-63 are 0; map type 1: custom map 1 as before.
    let r = b.send(mapped(
        motion(EN | LOAD | DIR, 0x27, 0, 1000, 10_000, 10_000),
        0,
        &[],
    ));
    assert_eq!(r[36..64], [0; 28]);
    let r = b.send(mapped(
        motion(EN | LOAD | DIR, 0x27, 0, 1000, 10_000, 10_000),
        1,
        &[],
    ));
    assert_eq!(dint(&r, 52), 65_536); // target velocity
    assert_eq!(dint(&r, 56), 1); // velocity mode
}

#[test]
fn map_type_2_command_writes_the_cmdmap_on_the_load_edge() {
    let mut b = Bench::new();
    b.set_list(CMDMAP, &[id::MT_TPOSWND, 4, 0, id::MT_NUM, id::HOME_P + 1])
        .unwrap();
    let slots = [10, -5, 77, 3, -2];
    // No edge: nothing written.
    b.send(mapped(cmd(EN, 0x03, 0x20, 100_000), 2, &slots));
    assert_eq!(b.get_param(id::MT_TPOSWND), 32_768i64.to_le_bytes());
    // The edge: every slot written, with the command type's data.
    let r = b.send(mapped(cmd(EN | LOAD, 0x03, 0x20, 100_000), 2, &slots));
    assert_ne!(r[2] & status2::LOAD_COMPLETE, 0);
    assert_eq!(b.get_param(id::MT_TPOSWND), 10i64.to_le_bytes());
    assert_eq!(b.get_param(4), (-5i16).to_le_bytes());
    assert_eq!(b.get_param(id::MT_NUM), [3]);
    assert_eq!(b.get_param(id::HOME_P), (-2i64).to_le_bytes());
    assert_eq!(b.get_param(id::DRV_ACC), 100_000i64.to_le_bytes());
    // Changed while Load/Start stays 1: not written.
    b.send(mapped(cmd(EN | LOAD, 0x03, 0x20, 100_000), 2, &[20]));
    assert_eq!(b.get_param(id::MT_TPOSWND), 10i64.to_le_bytes());
    // A value a parameter refuses (MT.NUM 200): error response 0x09, no slot kept, the
    // command type not run.
    b.send(mapped(cmd(EN, 0x03, 0x20, 200_000), 2, &[]));
    let r = b.send(mapped(
        cmd(EN | LOAD, 0x03, 0x20, 200_000),
        2,
        &[30, -6, 0, 200],
    ));
    assert_eq!(r[3], 0x34); // 0x14 with byte 3's axis bits
    assert_eq!(r[4..8], [0x09, 0xFF, 0x03, 0x20]);
    assert_eq!(r[2] & status2::LOAD_COMPLETE, 0);
    assert_eq!(b.get_param(id::MT_TPOSWND), 10i64.to_le_bytes());
    assert_eq!(b.get_param(4), (-5i16).to_le_bytes());
    assert_eq!(b.get_param(id::DRV_ACC), 100_000i64.to_le_bytes());
    // Out of a 2-byte signed parameter's range: refused too.
    b.send(mapped(cmd(EN, 0x03, 0x20, 200_000), 2, &[]));
    let r = b.send(mapped(
        cmd(EN | LOAD, 0x03, 0x20, 200_000),
        2,
        &[30, 40_000],
    ));
    assert_eq!(r[4], 0x09);
    // Map type 0 or 1 on an edge: bytes 36-63 ignored.
    for map in [0, 1] {
        b.send(mapped(cmd(EN, 0x03, 0x20, 200_000), map, &[]));
        let r = b.send(mapped(cmd(EN | LOAD, 0x03, 0x20, 200_000), map, &[50]));
        assert_ne!(r[2] & status2::LOAD_COMPLETE, 0);
        assert_eq!(b.get_param(id::MT_TPOSWND), 10i64.to_le_bytes());
    }
}

#[test]
fn a_refused_load_changes_no_mapped_parameter() {
    let mut b = Bench::new();
    b.set_list(CMDMAP, &[id::MT_TPOSWND, id::EIP_PROFUNIT])
        .unwrap();
    // An undefined command type (0x0A): the map is not applied.
    b.send(mapped(cmd(EN, 0x0A, 0x20, 0), 2, &[10, 1000]));
    let r = b.send(mapped(cmd(EN | LOAD, 0x0A, 0x20, 0), 2, &[10, 1000]));
    assert_eq!(r[3..6], [0x34, 0x20, 0xFF]);
    assert_eq!(b.get_param(id::MT_TPOSWND), 32_768i64.to_le_bytes());
    assert_eq!(b.get_param(id::EIP_PROFUNIT), 65_536u32.to_le_bytes());
    // Another axis: the same.
    b.send(mapped(cmd(EN, 0x43, 0x20, 100_000), 2, &[10, 1000]));
    let r = b.send(mapped(cmd(EN | LOAD, 0x43, 0x20, 100_000), 2, &[10, 1000]));
    assert_eq!(r[4], 0x20);
    assert_eq!(b.get_param(id::MT_TPOSWND), 32_768i64.to_le_bytes());
    // A valid type whose own data is refused after the map was applied (acceleration 0):
    // the map's values are put back.
    b.send(mapped(cmd(EN, 0x03, 0x20, 0), 2, &[10, 1000]));
    let r = b.send(mapped(cmd(EN | LOAD, 0x03, 0x20, 0), 2, &[10, 1000]));
    assert_eq!(r[4..6], [0x09, 0xFF]);
    assert_eq!(b.get_param(id::MT_TPOSWND), 32_768i64.to_le_bytes());
    assert_eq!(b.get_param(id::EIP_PROFUNIT), 65_536u32.to_le_bytes());
    // A move before homing is refused and faults the drive (its own reaction stays), but
    // the mapped parameters are not changed.
    b.send(mapped(
        motion(EN, 0x26, 100, 1000, 10_000, 10_000),
        2,
        &[10, 1000],
    ));
    let r = b.send(mapped(
        motion(EN | LOAD, 0x26, 100, 1000, 10_000, 10_000),
        2,
        &[10, 1000],
    ));
    assert_eq!(r[4], 0x10);
    assert_ne!(r[0] & status1::FAULT, 0);
    assert_eq!(b.get_param(id::MT_TPOSWND), 32_768i64.to_le_bytes());
    assert_eq!(b.get_param(id::EIP_PROFUNIT), 65_536u32.to_le_bytes());
    // The same load accepted: both written.
    b.send(mapped(cmd(EN, 0x03, 0x20, 100_000), 2, &[10, 1000]));
    let r = b.send(mapped(cmd(EN | LOAD, 0x03, 0x20, 100_000), 2, &[10, 1000]));
    assert_ne!(r[2] & status2::LOAD_COMPLETE, 0);
    assert_eq!(b.get_param(id::MT_TPOSWND), 10i64.to_le_bytes());
    assert_eq!(b.get_param(id::EIP_PROFUNIT), 1000u32.to_le_bytes());
}

#[test]
fn both_maps_on_one_connection() {
    // The same parameter commanded and reported: the response shows the loaded value.
    let mut b = Bench::new();
    b.set_list(CMDMAP, &[id::SWLS_LIMIT1 + 1]).unwrap();
    b.set_list(RSPMAP, &[id::SWLS_LIMIT1]).unwrap();
    b.send(mapped(cmd(EN, 0x03, 0x20, 100_000), 2, &[]));
    let r = b.send(mapped(cmd(EN | LOAD, 0x03, 0x20, 100_000), 2, &[123_456]));
    assert_eq!(slot(&r, 0), 123_456);
}
