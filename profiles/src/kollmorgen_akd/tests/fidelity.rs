//! What a PLC engineer holding the manual and the AKD parameter reference found wrong in
//! the simulated drive (issue 25 item 2), each shown through the command assembly and
//! explicit messages: motion tasks followed to their end, DRV.MOTIONSTAT bits 10/14/15, a
//! jog that needs homing, zero velocities, and the parameters' own ranges and defaults.
//! (Program mode and the owner's loss are in `class1.rs`, refused loads in
//! `dynamic_map.rs`, objects 0x24/0x25 and the vendor in `explicit.rs`.)

use super::*;

/// DRV.MOTIONSTAT from a response.
fn motionstat(r: &[u8]) -> u32 {
    dint(r, 16) as u32
}

const INVALID: u32 = 1 << 10;
const COMPLETED: u32 = 1 << 11;
const CROSSED: u32 = 1 << 14;
const REACHED: u32 = 1 << 15;

/// Writes parameter `instance` (attribute 1).
fn set(b: &mut Bench, instance: u16, data: &[u8]) -> CipResult {
    b.explicit(0x10, 0x0F, instance, Some(1), data).0
}

/// Reads parameter `instance` (attribute 1).
fn get(b: &mut Bench, instance: u16) -> Vec<u8> {
    let (status, data) = b.explicit(0x0E, 0x0F, instance, Some(1), &[]);
    status.unwrap();
    data
}

/// Stores motion task `n` (MT.NUM, MT.P, MT.V, MT.ACC, MT.DEC, MT.CNTL, then MT.SET); the
/// status of MT.SET.
fn store_task(b: &mut Bench, n: u8, p: i64, v: i64, acc: i64, cntl: u32) -> CipResult {
    set(b, id::MT_NUM, &[n]).unwrap();
    set(b, id::MT_P, &p.to_le_bytes()).unwrap();
    set(b, id::MT_V, &v.to_le_bytes()).unwrap();
    set(b, id::MT_ACC, &acc.to_le_bytes()).unwrap();
    set(b, id::MT_DEC, &acc.to_le_bytes()).unwrap();
    set(b, id::MT_CNTL, &cntl.to_le_bytes()).unwrap();
    set(b, id::MT_SET, &[1])
}

/// Start Block of task `n` (an edge from 0).
fn start_block(b: &mut Bench, n: u8) -> [u8; 64] {
    let mut c = cmd(EN, 0x21, 0x20, 0);
    c[1] = n;
    b.send(c);
    c[0] |= control::START_BLOCK;
    b.send(c)
}

/// A load edge of `c` (Load/Start 0 then 1), its response.
fn load(b: &mut Bench, c: [u8; 64]) -> [u8; 64] {
    let mut low = c;
    low[0] &= !LOAD;
    b.send(low);
    let mut high = c;
    high[0] |= LOAD;
    b.send(high)
}

#[test]
fn a_load_leaves_the_running_motion_task_running_to_its_end() {
    let mut b = Bench::new();
    b.enable_and_home();
    store_task(&mut b, 2, 5000, 2000, 20_000, 0).unwrap();
    start_block(&mut b, 2);
    let r = b.run_ms(100);
    assert_eq!((r[1], r[0] & status1::BLOCK), (2, status1::BLOCK));
    // A refused load (undefined command type): the error response, the task runs on.
    let r = load(&mut b, cmd(EN, 0x0A, 0x20, 0));
    assert_eq!(r[3..5], [0x34, 0x20]);
    let r = b.run_ms(50);
    assert_eq!((r[1], r[0] & status1::BLOCK), (2, status1::BLOCK));
    // A load that starts no motion (acceleration): accepted, the task runs on.
    let r = load(&mut b, cmd(EN, 0x03, 0x20, 30_000));
    assert_ne!(r[2] & status2::LOAD_COMPLETE, 0);
    let r = b.run_ms(50);
    assert_eq!((r[1], r[0] & status1::BLOCK), (2, status1::BLOCK));
    assert_ne!(r[0] & status1::IN_MOTION, 0);
    // Both fall with the end of the move, on the task's target.
    let t = b.until(5000, |r| r[0] & status1::IN_MOTION == 0).unwrap();
    assert!(t > 2000, "the task's 2.6 s move ended after {t} ms more");
    let r = b.response();
    assert_eq!((r[1], r[0] & status1::BLOCK, dint(&r, 8)), (0, 0, 5000));
}

#[test]
fn motionstat_15_is_reached_before_the_end_and_14_only_when_a_stop_crosses_the_target() {
    let mut b = Bench::new();
    b.enable_and_home();
    // 1.5 rev at 0.75 rev/s: MT.TPOSWND (0.5 rev) is entered about 0.7 s before the end.
    let mv = |c| motion(c, 0x26, 98_304, 49_152, 491_520, 491_520);
    load(&mut b, mv(EN));
    let r = b.run_ms(50);
    assert_eq!(motionstat(&r) & (REACHED | COMPLETED), 0);
    let t = b.until(3000, |r| motionstat(r) & REACHED != 0).unwrap();
    let r = b.response();
    assert_ne!(
        r[0] & status1::IN_MOTION,
        0,
        "reached after {t} ms, still moving"
    );
    assert_eq!(motionstat(&r) & COMPLETED, 0);
    b.until(3000, |r| r[0] & status1::IN_MOTION == 0).unwrap();
    let r = b.response();
    assert_eq!(
        motionstat(&r) & (REACHED | COMPLETED | CROSSED),
        REACHED | COMPLETED
    );
    // A stop slower than the move's own braking, triggered near the target, runs past it.
    set(&mut b, id::DRV_DECSTOP, &65_536i64.to_le_bytes()).unwrap();
    let back = |c| motion(c, 0x26, 0, 65_536, 655_360, 655_360);
    load(&mut b, back(EN));
    b.until(3000, |r| dint(r, 8) < 20_000).unwrap();
    let r = b.send(back(EN | LOAD | control::HARD_STOP));
    assert_eq!(motionstat(&r) & CROSSED, 0);
    b.until(3000, |r| r[0] & status1::IN_MOTION == 0).unwrap();
    let r = b.response();
    assert!(dint(&r, 8) < 0, "stopped at {}", dint(&r, 8));
    assert_ne!(motionstat(&r) & CROSSED, 0);
}

#[test]
fn an_invalid_motion_task_sets_motionstat_10() {
    let mut b = Bench::new();
    b.enable_and_home();
    // Start Block of a task never stored: 0x16 and bit 10.
    let r = start_block(&mut b, 7);
    assert_eq!(r[3..5], [0x34, 0x16]);
    assert_ne!(motionstat(&r) & INVALID, 0);
    // A valid move clears it.
    let r = load(&mut b, motion(EN, 0x26, 100, 1000, 10_000, 10_000));
    assert_eq!(motionstat(&r) & INVALID, 0);
    b.until(2000, |r| r[0] & status1::IN_MOTION == 0).unwrap();
    // A position move at velocity 0 cannot move: 0x09 and bit 10, no motion.
    let r = load(&mut b, motion(EN, 0x26, 5000, 0, 10_000, 10_000));
    assert_eq!(r[3..5], [0x34, 0x09]);
    assert_ne!(motionstat(&r) & INVALID, 0);
    let r = b.run_ms(100);
    assert_eq!((r[0] & status1::IN_MOTION, dint(&r, 8)), (0, 100));
}

#[test]
fn a_jog_in_position_mode_needs_homing() {
    let mut b = Bench::new();
    let r = load(&mut b, motion(EN | DIR, 0x27, 0, 1000, 10_000, 10_000));
    assert_eq!(r[3..5], [0x34, 0x10]);
    assert_eq!(r[0] & (status1::FAULT | status1::ENABLED), status1::FAULT);
    let r = b.run_ms(100);
    assert_eq!((r[0] & status1::IN_MOTION, dint(&r, 12)), (0, 0));
}

#[test]
fn a_zero_velocity_ramps_down_and_ends_the_motion() {
    let mut b = Bench::new();
    b.explicit(0x10, 0x25, 1, Some(3), &[1]).0.unwrap();
    load(&mut b, motion(EN | DIR, 0x27, 0, 1000, 10_000, 10_000));
    assert_eq!(dint(&b.run_ms(150), 12), 1000);
    // Deceleration (type 4) 10000 units/s², then target velocity 0 (type 2): down in
    // 100 ms, then no trajectory.
    load(&mut b, cmd(EN | DIR, 0x04, 0x20, 10_000));
    let r = load(&mut b, cmd(EN | DIR, 0x02, 0x20, 0));
    assert_ne!(r[2] & status2::LOAD_COMPLETE, 0);
    let t = b.until(1000, |r| r[0] & status1::IN_MOTION == 0).unwrap();
    assert!((95..=110).contains(&t), "In Motion fell after {t} ms");
    assert_eq!(dint(&b.run_ms(100), 12), 0);
    // A jog (type 7) at 0 is no motion: data out of range, nothing starts.
    let r = load(&mut b, motion(EN | DIR, 0x27, 0, 0, 10_000, 10_000));
    assert_eq!(r[3..5], [0x34, 0x09]);
    let r = b.run_ms(5);
    assert_eq!((r[0] & status1::IN_MOTION, dint(&r, 12)), (0, 0));
}

#[test]
fn swls_en_is_a_bitmask_of_the_two_limits() {
    let mut b = Bench::new();
    b.enable_and_home();
    set(&mut b, id::SWLS_LIMIT0, &(-1000i64).to_le_bytes()).unwrap();
    set(&mut b, id::SWLS_LIMIT1, &1000i64.to_le_bytes()).unwrap();
    assert_eq!(
        set(&mut b, id::SWLS_EN, &[4]),
        err(General::InvalidAttributeValue)
    );
    set(&mut b, id::SWLS_EN, &[3]).unwrap();
    // Bit 0 only: the negative limit stops a move, the positive one does not.
    set(&mut b, id::SWLS_EN, &[1]).unwrap();
    load(&mut b, motion(EN, 0x26, 3000, 4000, 40_000, 40_000));
    b.until(3000, |r| r[0] & status1::IN_MOTION == 0).unwrap();
    let r = b.response();
    assert_eq!((dint(&r, 8), r[2] & 0x18), (3000, 0));
    load(&mut b, motion(EN, 0x26, -3000, 4000, 40_000, 40_000));
    b.until(3000, |r| r[0] & status1::IN_MOTION == 0).unwrap();
    let r = b.response();
    assert!((-1500..=-1000).contains(&dint(&r, 8)), "{}", dint(&r, 8));
    assert_eq!(r[2] & 0x18, status2::NEGATIVE_SW_LIMIT);
    assert_eq!(get(&mut b, id::SWLS_EN), [1]);
}

#[test]
fn mt_num_spans_the_drives_0_to_128() {
    let mut b = Bench::new();
    b.enable_and_home();
    assert_eq!(
        set(&mut b, id::MT_NUM, &[129]),
        err(General::InvalidAttributeValue)
    );
    store_task(&mut b, 128, 1000, 4000, 40_000, 0).unwrap();
    let r = start_block(&mut b, 128);
    assert_eq!(r[3], 0x20, "no error response");
    let r = b.run_ms(50);
    assert_eq!((r[1], r[0] & status1::BLOCK), (128, status1::BLOCK));
}

#[test]
fn mt_set_refuses_a_task_that_cannot_move() {
    let mut b = Bench::new();
    // The power-up values (MT.V, MT.ACC, MT.DEC 0): refused, nothing stored.
    assert_eq!(
        set(&mut b, id::MT_SET, &[1]),
        err(General::InvalidAttributeValue)
    );
    b.enable_and_home();
    assert_eq!(start_block(&mut b, 0)[3..5], [0x34, 0x16]);
}

#[test]
fn mt_cntl_3_is_relative_to_the_previous_target() {
    let mut b = Bench::new();
    b.enable_and_home();
    assert_eq!(store_task(&mut b, 5, 1000, 4000, 40_000, 3), Ok(()));
    // 2 is no task type.
    assert_eq!(
        set(&mut b, id::MT_CNTL, &2u32.to_le_bytes()),
        err(General::InvalidAttributeValue)
    );
    // A move to 5000 stopped short (Smooth Stop) leaves its target at 5000: task 5 goes
    // to 6000, not to where the motor stopped + 1000.
    let mv = |c| motion(c, 0x26, 5000, 4000, 40_000, 40_000);
    load(&mut b, mv(EN));
    b.run_ms(300);
    b.send(mv(EN | control::SMOOTH_STOP));
    b.until(1000, |r| r[0] & status1::IN_MOTION == 0).unwrap();
    let stopped = dint(&b.response(), 8);
    assert!(stopped < 4000, "stopped at {stopped}");
    b.send(mv(EN));
    start_block(&mut b, 5);
    b.until(5000, |r| r[0] & status1::IN_MOTION == 0).unwrap();
    assert_eq!(dint(&b.response(), 8), 6000);
    // The same task as type 1 (relative to the command position): 1000 further.
    store_task(&mut b, 5, 1000, 4000, 40_000, 1).unwrap();
    start_block(&mut b, 5);
    b.until(5000, |r| r[0] & status1::IN_MOTION == 0).unwrap();
    assert_eq!(dint(&b.response(), 8), 7000);
}

#[test]
fn tposwnd_defaults_to_half_a_revolution() {
    let mut b = Bench::new();
    assert_eq!(get(&mut b, id::MT_TPOSWND), 32_768i64.to_le_bytes());
}

#[test]
fn reported_torque_stays_within_the_drives_peak_current() {
    let mut b = Bench::new();
    b.explicit(0x10, 0x25, 1, Some(3), &[1]).0.unwrap();
    // 1 rev/s at 100 rev/s²: 200 mA of inertia and up to 100 mA of friction on the ramp,
    // 100 mA of friction at speed.
    let jog = |c, v, acc| respond(motion(c, 0x27, 0, v, acc, acc), 0x25);
    load(&mut b, jog(EN | DIR, 65_536, 6_553_600));
    let mut peak = 0;
    for _ in 0..100 {
        let r = b.run_ms(1);
        peak = peak.max(dint(&r, 4));
        let il_fb = i32::from_le_bytes(get(&mut b, id::IL_FB).try_into().unwrap());
        assert_eq!(il_fb, dint(&r, 4));
    }
    assert!((200..=300).contains(&peak), "torque {peak} mA on the ramp");
    assert_eq!(dint(&b.response(), 4), 100);
    // To 50 rev/s at 10000 rev/s²: the ramp asks 20 A of inertia plus friction, more than
    // the power stage has: 20 A reported. At speed, 5 A of friction.
    load(&mut b, jog(EN | DIR, 3_276_800, 655_360_000));
    let mut peak = 0;
    for _ in 0..10 {
        peak = peak.max(dint(&b.run_ms(1), 4));
    }
    assert_eq!(peak, 20_000);
    assert_eq!(dint(&b.run_ms(10), 4), 5000);
}
