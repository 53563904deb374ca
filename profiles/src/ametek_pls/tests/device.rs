//! The limit switch as a PLC sees it in the input data: positions and windows, Run Enable,
//! forces and their precedence, minimum speed disable, speed compensation, the input
//! functions, the add-on test and a moving resolver, in virtual time (`Device::poll`).

extern crate std;

use std::vec::Vec;

use enip_stack::device::{CloseReason, ConnectionEvent};
use enip_stack::{Device, Instant};

use super::super::device::window;
use super::super::AmetekPls;
use super::{input, output, output_1, pls_object, programmed, set};

const RUN: u16 = 1;
const ADDON: u16 = 2;

/// Places group 1 at `pos` with a home offset.
fn home(pls: &mut AmetekPls, pos: u16) {
    assert_eq!(set(pls, 36, &[0b01, pos, 0, 0, 0, 0, 0, 0, 0]), 0);
}

/// Output status words 11-12 as one mask (bit 0 = output 1).
fn outputs(pls: &mut AmetekPls) -> u32 {
    let w = input(pls);
    u32::from(w[10]) | u32::from(w[11]) << 16
}

fn run(pls: &mut AmetekPls) {
    assert_eq!(output(pls, [RUN, 0, 0, 0, 0, 0, 0]), 0);
}

#[test]
fn outputs_follow_the_windows_of_4_1_to_4_3() {
    let mut pls = programmed();
    run(&mut pls);
    for (pos, out1, out17) in [(150, 1, 0), (250, 0, 0), (315, 1, 0), (55, 0, 1)] {
        home(&mut pls, pos);
        let w = input(&mut pls);
        assert_eq!(w[0], pos);
        assert_eq!((w[10] & 1, w[11] & 1), (out1, out17), "at {pos}");
    }
    // Window edges: on inclusive, off exclusive.
    for (pos, on) in [(99, 0), (100, 1), (199, 1), (200, 0), (330, 0)] {
        home(&mut pls, pos);
        assert_eq!(outputs(&mut pls) & 1, on, "at {pos}");
    }
    // Words 1-8 stay below their scale factor; word 10 no fault; 9 RPM 0.
    let w = input(&mut pls);
    assert!(w[..8].iter().all(|&p| p < 360));
    assert_eq!((w[8], w[9]), (0, 0));
}

#[test]
fn run_enable_and_forces_with_their_precedence() {
    let mut pls = programmed();
    home(&mut pls, 150);
    // Run Enable 0: every output off, even forced.
    assert_eq!(output(&mut pls, [0, 0b01, 0, 0b01, 0, 0b01, 0]), 0);
    assert_eq!(outputs(&mut pls), 0);
    run(&mut pls);
    assert_eq!(outputs(&mut pls), 1);
    // Force off at 150.
    assert_eq!(output(&mut pls, [RUN, 0b10, 0, 0, 0, 0, 0]), 0);
    assert_eq!(outputs(&mut pls), 0);
    // Force on at 250.
    home(&mut pls, 250);
    assert_eq!(output(&mut pls, [RUN, 0b01, 0, 0, 0, 0, 0]), 0);
    assert_eq!(outputs(&mut pls), 1);
    // Reserved code 11 is unforce.
    assert_eq!(output(&mut pls, [RUN, 0b11, 0, 0, 0, 0, 0]), 0);
    assert_eq!(outputs(&mut pls), 0);
    // Word 4 bits 1..0 force output 17 on.
    assert_eq!(output(&mut pls, [RUN, 0, 0, 0b01, 0, 0, 0]), 0);
    assert_eq!(outputs(&mut pls), 1 << 16);
    // Group force on overrides the individual force off: outputs 1 and 17 on.
    assert_eq!(output(&mut pls, [RUN, 0b10, 0, 0b10, 0, 0b01, 0]), 0);
    assert_eq!(outputs(&mut pls), 1 | 1 << 16);
    // Group force off overrides an individual force on.
    assert_eq!(output(&mut pls, [RUN, 0b01, 0, 0b01, 0, 0b10, 0]), 0);
    assert_eq!(outputs(&mut pls), 0);
    // Group 2 force has no outputs; output 2 belongs to no group: never on.
    assert_eq!(output(&mut pls, [RUN, 0b0100, 0, 0, 0, 0b0100, 0]), 0);
    assert_eq!(outputs(&mut pls), 0);
}

#[test]
fn idle_and_owner_loss_release_the_output_data() {
    for event in [
        ConnectionEvent::RunIdle(false),
        ConnectionEvent::OwnershipLost(CloseReason::Timeout),
    ] {
        let mut pls = programmed();
        home(&mut pls, 150);
        assert_eq!(output(&mut pls, [RUN, 0, 0, 0b01, 0, 0, 0]), 0);
        assert_eq!(outputs(&mut pls), 1 | 1 << 16);
        pls.connection_event(event);
        assert_eq!(outputs(&mut pls), 0, "{event:?}");
    }
}

#[test]
fn minimum_speed_disable() {
    let mut pls = programmed();
    let mut w = pls_object();
    w[4] = 10;
    w[5] = 0x0001;
    assert_eq!(set(&mut pls, 1, &w), 0);
    home(&mut pls, 150);
    run(&mut pls);
    assert_eq!(outputs(&mut pls) & 1, 0, "RPM 0 < 10");
    // At 10 RPM (not below) the output works; the move in one ms is a fraction of a count.
    pls.set_resolver(10, false);
    run(&mut pls);
    assert_eq!(outputs(&mut pls) & 1, 1);
    pls.set_resolver(0, false);
    w[4] = 0;
    assert_eq!(set(&mut pls, 1, &w), 0);
    assert_eq!(outputs(&mut pls) & 1, 1, "min speed 0 = off");
}

#[test]
fn linear_speed_compensation_advances_the_edges() {
    let mut pls = programmed();
    let mut w = output_1();
    // 100 RPM: no shift; 1000 RPM: both edges 90 counts earlier.
    w[..6].copy_from_slice(&[100, 0, 0, 1000, 90, 90]);
    assert_eq!(set(&mut pls, 2, &w), 0);
    run(&mut pls);
    let at = |pls: &mut AmetekPls, rpm: u16, pos: u16| {
        pls.set_resolver(rpm, false);
        home(pls, pos);
        outputs(pls) & 1
    };
    assert_eq!(at(&mut pls, 0, 100), 1);
    assert_eq!(at(&mut pls, 1000, 10), 1);
    assert_eq!(at(&mut pls, 1000, 110), 0);
    assert_eq!(at(&mut pls, 1000, 9), 0);
    // Half way (550 RPM): 45 counts.
    assert_eq!(at(&mut pls, 550, 55), 1);
    assert_eq!(at(&mut pls, 550, 54), 0);
    // Above the end RPM: clamped.
    assert_eq!(at(&mut pls, 2000, 10), 1);
}

/// Input 9 programmed with `words` (7 words).
fn input_9(pls: &mut AmetekPls, words: [u16; 7]) {
    let mut w = [0u16; 112];
    w[56..63].copy_from_slice(&words);
    assert_eq!(set(pls, 34, &w), 0);
}

fn soft(pls: &mut AmetekPls, level: bool) {
    assert_eq!(output(pls, [RUN, 0, 0, 0, 0, 0, u16::from(level)]), 0);
}

#[test]
fn reset_to_preset_group_on_the_leading_edge_only() {
    let mut pls = programmed();
    input_9(&mut pls, [0b011, 0, 0, 120, 77, 0, 0]);
    home(&mut pls, 150);
    soft(&mut pls, false);
    soft(&mut pls, true);
    assert_eq!(input(&mut pls)[0], 77);
    // Held high: a new position stays.
    home(&mut pls, 150);
    soft(&mut pls, true);
    assert_eq!(input(&mut pls)[0], 150);
    soft(&mut pls, false);
    assert_eq!(input(&mut pls)[0], 150);
    soft(&mut pls, true);
    assert_eq!(input(&mut pls)[0], 77);
    // 0xC0/2 input 9: leading and trailing positions 150 (where they were seen; the pair
    // is published at the leading edge, update mode 1), transition: leading and
    // trailing seen this revolution; 0xC0/3: input 9's offset is the group's new offset.
    let status = super::words(&get_c0(&mut pls, 2));
    assert_eq!(status[24..27], [150, 150, 3]);
    let offsets = super::words(&get_c0(&mut pls, 3));
    assert_eq!(offsets[16], offsets[0]);
    // Active low: the falling edge resets.
    input_9(&mut pls, [0b010, 0, 0, 120, 77, 0, 0]);
    soft(&mut pls, true);
    home(&mut pls, 150);
    soft(&mut pls, false);
    assert_eq!(input(&mut pls)[0], 77);
}

fn get_c0(pls: &mut AmetekPls, a: u8) -> Vec<u8> {
    let (s, d) = super::execute(pls, &super::request(0x0E, 0xC0, 1, Some(a), &[]));
    assert_eq!(s, 0);
    d
}

#[test]
fn force_group_and_output_enable_group_inputs() {
    let mut pls = programmed();
    home(&mut pls, 250);
    input_9(&mut pls, [1, 0, 0, 140, 1, 0, 0]);
    soft(&mut pls, true);
    assert_eq!(outputs(&mut pls), 1 | 1 << 16);
    soft(&mut pls, false);
    assert_eq!(outputs(&mut pls), 0);
    // Type 130: inactive, outputs off inside their windows; active, normal.
    input_9(&mut pls, [1, 0, 0, 130, 0, 0, 0]);
    home(&mut pls, 150);
    assert_eq!(outputs(&mut pls), 0);
    soft(&mut pls, true);
    assert_eq!(outputs(&mut pls), 1);
    // The network's group force wins over the input's.
    input_9(&mut pls, [1, 0, 0, 140, 1, 0, 0]);
    assert_eq!(output(&mut pls, [RUN, 0, 0, 0, 0, 0b10, 1]), 0);
    assert_eq!(outputs(&mut pls), 0);
}

#[test]
fn remote_offset_and_setpoint_tune() {
    let mut pls = programmed();
    home(&mut pls, 150);
    input_9(&mut pls, [1, 0, 0, 110, (-10i16) as u16, 0, 0]);
    soft(&mut pls, true);
    soft(&mut pls, false);
    soft(&mut pls, true);
    assert_eq!(input(&mut pls)[0], 130);
    // Setpoint tune +60 on output 1: window 100-200 becomes 40-140.
    input_9(&mut pls, [1, 1, 0, 10, 60, 0, 0]);
    soft(&mut pls, false);
    home(&mut pls, 150);
    assert_eq!(outputs(&mut pls) & 1, 1);
    soft(&mut pls, true);
    assert_eq!(outputs(&mut pls) & 1, 0);
    home(&mut pls, 40);
    assert_eq!(outputs(&mut pls) & 1, 1);
}

/// Polls `pls` every millisecond from `from` for `ms`; the output 1 samples.
fn sample(pls: &mut AmetekPls, from: u64, ms: u64) -> Vec<bool> {
    (0..ms)
        .map(|t| {
            pls.poll(Instant::from_micros((from + t) * 1000));
            pls.engine().outputs() & 1 == 1
        })
        .collect()
}

fn toggles(s: &[bool]) -> usize {
    s.windows(2).filter(|w| w[0] != w[1]).count()
}

#[test]
fn add_on_test_timed_and_held() {
    let mut pls = programmed();
    home(&mut pls, 250);
    assert_eq!(set(&mut pls, 35, &[60, 1500, 0x0001]), 0);
    run(&mut pls);
    pls.poll(Instant(0));
    assert_eq!(output(&mut pls, [RUN | ADDON, 0, 0, 0, 0, 0, 0]), 0);
    let during = sample(&mut pls, 0, 1500);
    assert!(toggles(&during) >= 2, "output 1 fires during the test");
    let after = sample(&mut pls, 1501, 1000);
    assert!(after.iter().all(|on| !on), "ends after 1500 ms");
    assert_eq!(input(&mut pls)[0], 250, "positions are unaffected");
    assert_eq!(input(&mut pls)[8], 0, "RPM is unaffected");
    // Time 0: runs while the bit is held, stops when it clears.
    assert_eq!(set(&mut pls, 35, &[60, 0, 0x0001]), 0);
    run(&mut pls);
    assert_eq!(output(&mut pls, [RUN | ADDON, 0, 0, 0, 0, 0, 0]), 0);
    let held = sample(&mut pls, 3000, 2500);
    assert!(toggles(&held[2000..]) >= 1, "still running beyond 2 s");
    run(&mut pls);
    let stopped = sample(&mut pls, 5500, 1000);
    assert!(stopped.iter().all(|on| !on));
}

#[test]
fn a_moving_resolver_is_consistent_with_the_windows() {
    let mut pls = programmed();
    pls.set_resolver(600, false);
    run(&mut pls);
    let mut on = 0;
    for t in 0..1000u64 {
        pls.poll(Instant::from_micros(t * 1000));
        let w = input(&mut pls);
        assert_eq!(w[8], 600);
        let pos = w[0];
        let near_edge = [100u16, 200, 300, 330]
            .iter()
            .any(|&e| pos.abs_diff(e) <= 1);
        let expected = window(pos, 100, 200) || window(pos, 300, 330);
        if !near_edge {
            assert_eq!(w[10] & 1 == 1, expected, "at {pos}");
        }
        on += usize::from(w[10] & 1);
    }
    // 10 revolutions a second, 130 of 360 counts on: about 36 % of the samples.
    assert!((300..=420).contains(&on), "{on}");
}

#[test]
fn time_based_and_motion_detect_setpoints() {
    let mut pls = programmed();
    let mut w = output_1();
    w[6] = 1;
    w[7] = 3;
    w[8] = 0;
    w[9] = 20;
    assert_eq!(set(&mut pls, 2, &w), 0);
    pls.set_resolver(60, false);
    run(&mut pls);
    // 1 rev/s: crossing position 0 every second turns output 1 on for 20 ms.
    let s = sample(&mut pls, 0, 2100);
    let on = s.iter().filter(|b| **b).count();
    assert!((38..=42).contains(&on), "{on}");
    // Motion detect at 60 RPM: on while the RPM is at least 60.
    w[7] = 4;
    w[8] = 60;
    assert_eq!(set(&mut pls, 2, &w), 0);
    assert_eq!(outputs(&mut pls) & 1, 1);
    w[8] = 61;
    assert_eq!(set(&mut pls, 2, &w), 0);
    assert_eq!(outputs(&mut pls) & 1, 0);
}

#[test]
fn output_enable_single_shot_window_and_warning_map() {
    let mut pls = programmed();
    // Input 9: output enable group single shot, window 100..200.
    input_9(&mut pls, [1, 0, 0, 131, 100, 200, 0]);
    home(&mut pls, 150);
    run(&mut pls);
    assert_eq!(outputs(&mut pls) & 1, 0, "not enabled before an input");
    soft(&mut pls, true);
    assert_eq!(outputs(&mut pls) & 1, 1, "input inside the window");
    soft(&mut pls, false);
    home(&mut pls, 250);
    soft(&mut pls, true);
    home(&mut pls, 150);
    assert_eq!(
        outputs(&mut pls) & 1,
        0,
        "input outside the window: forced off"
    );
    // Moving: a revolution without an input in the window sets warning bit 8 (input 9).
    soft(&mut pls, false);
    pls.set_resolver(600, false);
    sample(&mut pls, 0, 120);
    assert_eq!(input(&mut pls)[13], 1 << 8);
    // An input inside the window clears it at the window's end.
    let mut t = 120;
    while !(110..190).contains(&input(&mut pls)[0]) && t < 1000 {
        pls.poll(Instant::from_micros(t * 1000));
        t += 1;
    }
    soft(&mut pls, true);
    sample(&mut pls, t, 30);
    assert_eq!(input(&mut pls)[13], 0);
}

#[test]
fn reset_to_preset_single_shot_expires_after_a_revolution() {
    let mut pls = programmed();
    input_9(&mut pls, [1, 0, 0, 121, 150, 0, 0]);
    run(&mut pls);
    pls.set_resolver(60, false);
    pls.poll(Instant(0));
    soft(&mut pls, true);
    assert_eq!(input(&mut pls)[0], 150);
    let first = sample(&mut pls, 1, 900);
    assert!(first.iter().any(|on| *on), "fires during the revolution");
    let after = sample(&mut pls, 1100, 1000);
    assert!(after.iter().all(|on| !on), "forced off with no new input");
    soft(&mut pls, false);
    soft(&mut pls, true);
    let again = sample(&mut pls, 2100, 900);
    assert!(again.iter().any(|on| *on), "a new input fires again");
}

#[test]
fn leds_follow_configuration_fault_and_connections() {
    use super::super::leds::{ModuleStatus, NetworkStatus};
    let mut pls = AmetekPls::new();
    assert_eq!(pls.leds().module_status(), ModuleStatus::Standby);
    assert_eq!(set(&mut pls, 1, &pls_object()), 0);
    assert_eq!(pls.leds().module_status(), ModuleStatus::Operating);
    pls.set_resolver(0, true);
    pls.poll(Instant(0));
    assert_eq!(pls.leds().module_status(), ModuleStatus::RecoverableFault);
    assert_eq!(pls.leds().network_status(), NetworkStatus::NoConnection);
}
