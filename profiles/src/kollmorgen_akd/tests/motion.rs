//! The simulated drive through the command assembly in virtual time: jogs and stops, homing
//! and moves, motion tasks, torque mode, software limits, units.

use super::*;

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
    // Completed and reached; a normal move never crosses its target (bit 14).
    assert_eq!(ms & (1 << 11 | 1 << 14 | 1 << 15), 1 << 11 | 1 << 15);
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
    let r = b.run_ms(1_000);
    // Velocity settles where viscous friction takes the whole torque: 500 mA at 100 mA
    // per rev/s is 5 rev/s (327680 units/s); the reported torque is 500 mA.
    assert!(
        (327_670..=327_680).contains(&dint(&r, 12)),
        "{}",
        dint(&r, 12)
    );
    assert!((499..=500).contains(&dint(&r, 4)), "{}", dint(&r, 4));
    let (s, t) = b.explicit(0x0E, 0x25, 1, Some(25), &[]);
    s.unwrap();
    assert_eq!(t, r[4..8]);
}

#[test]
fn software_limits_stop_and_report() {
    let mut b = Bench::new();
    b.enable_and_home();
    let set = |b: &mut Bench, i: u16, d: &[u8]| b.explicit(0x10, 0x0F, i, Some(1), d).0.unwrap();
    set(&mut b, id::SWLS_LIMIT1, &1000i64.to_le_bytes());
    // SWLS.EN bit 1: the positive limit only.
    set(&mut b, id::SWLS_EN, &[2]);
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
