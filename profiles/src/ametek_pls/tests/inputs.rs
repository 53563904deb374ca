//! Issue 25 item 3: the reset to preset inputs (subset and whole group, average, window),
//! output enable advanced, force outputs, capture at the resolver's zero, input offsets
//! after a reconfiguration, and the NS LED's timed-out state, in virtual time.

extern crate std;

use core::net::Ipv4Addr;
use std::vec::Vec;

use enip_stack::device::{
    CloseReason, ConnectionEvent, ConnectionInfo, ConnectionPoints, Kind as ConnectionKind,
};
use enip_stack::wire::forward_open::Triad;
use enip_stack::{Device, Instant};

use super::super::leds::NetworkStatus;
use super::super::AmetekPls;
use super::{execute, input, output, programmed, request, set, words};

const RUN: u16 = 1;

/// Places group 1 at `pos` with a home offset.
fn home(pls: &mut AmetekPls, pos: u16) {
    assert_eq!(set(pls, 36, &[0b01, pos, 0, 0, 0, 0, 0, 0, 0]), 0);
}

/// Input 9 programmed with `words` (bit register, masks, type, P1-P3).
fn input_9(pls: &mut AmetekPls, words: [u16; 7]) {
    let mut w = [0u16; 112];
    w[56..63].copy_from_slice(&words);
    assert_eq!(set(pls, 34, &w), 0);
}

/// Soft input 9 at `level`, Run Enable on.
fn soft(pls: &mut AmetekPls, level: bool) {
    assert_eq!(output(pls, [RUN, 0, 0, 0, 0, 0, u16::from(level)]), 0);
}

/// A rising edge of soft input 9 (active high).
fn pulse(pls: &mut AmetekPls) {
    soft(pls, false);
    soft(pls, true);
}

/// Output status as one mask (bit 0 = output 1, bit 16 = output 17).
fn outputs(pls: &mut AmetekPls) -> u32 {
    let w = input(pls);
    u32::from(w[10]) | u32::from(w[11]) << 16
}

/// Class 0xC0 attribute `a` as words.
fn status(pls: &mut AmetekPls, a: u8) -> Vec<u16> {
    let (s, d) = execute(pls, &request(0x0E, 0xC0, 1, Some(a), &[]));
    assert_eq!(s, 0);
    words(&d)
}

const OUT1: u32 = 1;
const OUT17: u32 = 1 << 16;

#[test]
fn reset_to_preset_of_a_subset_leaves_the_group_position() {
    let mut pls = programmed();
    home(&mut pls, 250);
    // Type 20, mask output 1 only: output 1 restarts from 150, the group stays at 250.
    input_9(&mut pls, [1, 0x0001, 0, 20, 150, 0, 0]);
    soft(&mut pls, false);
    assert_eq!(outputs(&mut pls), 0);
    soft(&mut pls, true);
    assert_eq!(input(&mut pls)[0], 250);
    assert_eq!(outputs(&mut pls), OUT1, "output 1 at 150 (inside 100-200)");
    assert_eq!(status(&mut pls, 3)[16], 150, "input 9's offset");
}

#[test]
fn reset_to_preset_of_the_whole_group_resets_the_group_position() {
    for kind in [20, 120] {
        let mut pls = programmed();
        home(&mut pls, 250);
        // The mask covers both outputs of group 1 (1 and 17): the group resets.
        input_9(&mut pls, [1, 0x0001, 0x0001, kind, 55, 0, 0]);
        pulse(&mut pls);
        assert_eq!(input(&mut pls)[0], 55, "type {kind}");
        assert_eq!(outputs(&mut pls), OUT17, "output 17 at 55 (inside 50-60)");
        assert_eq!(status(&mut pls, 3)[0], 55, "group offset");
        assert_eq!(status(&mut pls, 3)[16], 55, "input 9's offset");
    }
}

#[test]
fn reset_to_preset_without_a_mask_resets_the_group() {
    // §2.6: a reset to preset "is used to reset the position of a PLS group"; only a mask
    // that is a subset of the group's outputs narrows it. Masks 0 and 0: the whole group.
    for kind in [20, 21, 23] {
        let mut pls = programmed();
        home(&mut pls, 250);
        input_9(&mut pls, [1, 0, 0, kind, 55, 0, 300]);
        pulse(&mut pls);
        assert_eq!(input(&mut pls)[0], 55, "type {kind}");
        assert_eq!(status(&mut pls, 3)[0], 55, "group offset, type {kind}");
    }
    // Average of 2 without a mask: inputs at 250 and 100 set the group to 175.
    let mut pls = programmed();
    input_9(&mut pls, [1, 0, 0, 22, 2, 0, 0]);
    home(&mut pls, 250);
    pulse(&mut pls);
    home(&mut pls, 100);
    pulse(&mut pls);
    assert_eq!(input(&mut pls)[0], 175, "type 22");
    // Single shot without a mask: a revolution with no new input forces the group's
    // outputs off, output 17 included.
    let mut pls = programmed();
    input_9(&mut pls, [1, 0, 0, 21, 55, 0, 0]);
    pls.set_resolver(60, false);
    pls.poll(Instant(0));
    soft(&mut pls, true);
    let mut on = 0;
    for ms in (1100..2100).step_by(5) {
        pls.poll(Instant::from_micros(ms * 1000));
        on |= outputs(&mut pls);
    }
    assert_eq!(on, 0, "forced off after a revolution without an input");
}

#[test]
fn average_reset_settles_at_the_average_of_the_input_positions() {
    let mut pls = programmed();
    // Type 122, 2 positions averaged.
    input_9(&mut pls, [1, 0, 0, 122, 2, 0, 0]);
    let mut seen = Vec::new();
    for at in [100, 110, 120] {
        home(&mut pls, at);
        pulse(&mut pls);
        seen.push(input(&mut pls)[0]);
    }
    // The inputs came at 100, 110, 120: the position becomes 100, 105, 115.
    assert_eq!(seen, [100, 105, 115]);
    // More inputs at the same place (120): the average settles there and stays.
    for _ in 0..4 {
        pulse(&mut pls);
        assert_eq!(input(&mut pls)[0], 120);
    }
    assert_eq!(status(&mut pls, 3)[16], 120, "input 9's offset");
}

#[test]
fn average_reset_of_a_subset_moves_only_its_outputs() {
    let mut pls = programmed();
    // Type 22 on output 1 only, 2 positions.
    input_9(&mut pls, [1, 0x0001, 0, 22, 2, 0, 0]);
    home(&mut pls, 250);
    pulse(&mut pls);
    home(&mut pls, 50);
    pulse(&mut pls);
    // The group reads 50 (output 17 on in 50-60); output 1 operates from the average
    // 150 (on in 100-200).
    assert_eq!(input(&mut pls)[0], 50);
    assert_eq!(outputs(&mut pls), OUT1 | OUT17);
    // Again at the same group position: output 1's average is now 50 (off).
    pulse(&mut pls);
    assert_eq!(outputs(&mut pls), OUT17);
}

#[test]
fn window_reset_ignores_inputs_outside_the_window() {
    let mut pls = programmed();
    input_9(&mut pls, [1, 0, 0, 123, 77, 100, 200]);
    home(&mut pls, 250);
    pulse(&mut pls);
    assert_eq!(input(&mut pls)[0], 250, "outside 100-200: ignored");
    home(&mut pls, 150);
    pulse(&mut pls);
    assert_eq!(input(&mut pls)[0], 77, "inside: reset");
    // Type 23 on output 1: output 1 restarts from 77 (off), the group stays at 150.
    input_9(&mut pls, [1, 0x0001, 0, 23, 77, 100, 200]);
    home(&mut pls, 150);
    assert_eq!(outputs(&mut pls), OUT1);
    pulse(&mut pls);
    assert_eq!(input(&mut pls)[0], 150);
    assert_eq!(outputs(&mut pls), 0);
}

/// Polls until `ms` and returns (group 1 position, outputs).
fn at(pls: &mut AmetekPls, ms: u64) -> (u16, u32) {
    pls.poll(Instant::from_micros(ms * 1000));
    (input(pls)[0], outputs(pls))
}

#[test]
fn output_enable_advanced_enables_from_the_enable_position_for_a_revolution() {
    for (kind, mask) in [(132, OUT1 | OUT17), (32, OUT1)] {
        let mut pls = programmed();
        // Window 100-200, enable position 150; output 1 only for type 32.
        input_9(&mut pls, [1, 0x0001, 0, kind, 100, 200, 150]);
        soft(&mut pls, false);
        pls.set_resolver(60, false);
        pls.poll(Instant(0));
        // 60 RPM at SF 360: 0.36 counts per ms. Before any input: held off.
        let (pos, out) = at(&mut pls, 420);
        assert!((150..=152).contains(&pos), "{pos}");
        assert_eq!(out & mask, 0, "type {kind}: no input yet");
        // Input at ~120 (t = 1333 ms, second revolution): not before 150.
        at(&mut pls, 1333);
        soft(&mut pls, true);
        let (pos, out) = at(&mut pls, 1400);
        assert!((143..=145).contains(&pos), "{pos}");
        assert_eq!(out & mask, 0, "type {kind}: before the enable position");
        let (_, out) = at(&mut pls, 1450);
        assert_eq!(out & OUT1, OUT1, "type {kind}: enabled at 162");
        let (_, out) = at(&mut pls, 1870);
        assert_eq!(out & OUT1, OUT1, "type {kind}: still enabled at 313");
        let (pos, out) = at(&mut pls, 2360);
        assert!((129..=131).contains(&pos), "{pos}");
        assert_eq!(
            out & OUT1,
            OUT1,
            "type {kind}: a revolution from 150 not over"
        );
        let (_, out) = at(&mut pls, 2450);
        assert_eq!(out & OUT1, 0, "type {kind}: a revolution has passed");
        // An input outside the window (at ~250) enables nothing.
        soft(&mut pls, false);
        at(&mut pls, 3694);
        soft(&mut pls, true);
        let (pos, out) = at(&mut pls, 4150);
        assert!((53..=55).contains(&pos), "{pos}");
        if kind == 32 {
            assert_eq!(out & OUT17, OUT17, "output 17 is not in the mask");
        }
        let (_, out) = at(&mut pls, 4450);
        assert_eq!(out & OUT1, 0, "type {kind}: input outside the window");
    }
}

#[test]
fn force_outputs_input_forces_its_mask_only() {
    let mut pls = programmed();
    home(&mut pls, 55);
    // Type 40 on output 1: on while active, off while inactive.
    input_9(&mut pls, [1, 0x0001, 0, 40, 1, 2, 0]);
    soft(&mut pls, true);
    assert_eq!(outputs(&mut pls), OUT1 | OUT17);
    soft(&mut pls, false);
    assert_eq!(outputs(&mut pls), OUT17);
    // Unforced while inactive: output 1 follows its pattern (off at 55, on at 150).
    input_9(&mut pls, [1, 0x0001, 0, 40, 2, 0, 0]);
    home(&mut pls, 150);
    assert_eq!(outputs(&mut pls), OUT1);
    soft(&mut pls, true);
    assert_eq!(outputs(&mut pls), 0);
}

#[test]
fn capture_mode_0_publishes_at_the_resolvers_zero() {
    let mut pls = programmed();
    // Group 1 runs 100 counts ahead of the resolver; input 9 captures at zero (mode 0).
    input_9(&mut pls, [1, 0, 0, 0, 0, 0, 0]);
    home(&mut pls, 100);
    soft(&mut pls, false);
    pls.set_resolver(60, false);
    pls.poll(Instant(0));
    let (leading, _) = at(&mut pls, 100);
    soft(&mut pls, true);
    let (trailing, _) = at(&mut pls, 200);
    soft(&mut pls, false);
    assert!((135..=136).contains(&leading) && (171..=172).contains(&trailing));
    // The group passes its zero at ~722 ms, the resolver at 1000 ms.
    at(&mut pls, 800);
    assert_eq!(
        status(&mut pls, 2)[24..26],
        [0, 0],
        "not at the group's zero"
    );
    at(&mut pls, 1010);
    assert_eq!(
        status(&mut pls, 2)[24..26],
        [leading, trailing],
        "at the resolver's zero"
    );
}

#[test]
fn input_offsets_return_to_zero_when_the_input_is_no_longer_a_preset() {
    let mut pls = programmed();
    home(&mut pls, 250);
    input_9(&mut pls, [1, 0, 0, 120, 77, 0, 0]);
    pulse(&mut pls);
    assert_eq!(status(&mut pls, 3)[16], 77);
    // Reconfigured as output enable (level): no input offset any more.
    input_9(&mut pls, [1, 0, 0, 130, 0, 0, 0]);
    assert_eq!(status(&mut pls, 3)[16], 0);
    // Another preset type keeps reporting its own offset when it acts.
    input_9(&mut pls, [1, 0, 0, 120, 20, 0, 0]);
    assert_eq!(status(&mut pls, 3)[16], 0);
    pulse(&mut pls);
    assert_eq!(status(&mut pls, 3)[16], 20);
}

fn connection(originator: [u8; 4], kind: ConnectionKind, slot: usize) -> ConnectionInfo {
    let io = kind != ConnectionKind::Explicit;
    ConnectionInfo {
        slot,
        kind,
        triad: Triad {
            connection_serial: slot as u16,
            vendor_id: 1,
            originator_serial: 7,
        },
        originator: Ipv4Addr::from(originator),
        points: ConnectionPoints {
            config: io.then_some(1),
            consumed: io.then_some(150),
            produced: io.then_some(100),
        },
        o_t_id: 1,
        t_o_id: 2,
        o_t_rpi_us: 10_000,
        t_o_rpi_us: 10_000,
        multicast: false,
    }
}

#[test]
fn network_status_stays_red_until_every_timed_out_connection_is_back() {
    let mut pls = AmetekPls::new();
    let ns = |pls: &AmetekPls| pls.leds().network_status();
    let plc_a = connection([198, 18, 0, 1], ConnectionKind::ExclusiveOwner, 0);
    let plc_b = connection([198, 18, 0, 3], ConnectionKind::InputOnly, 1);
    for c in [plc_a, plc_b] {
        pls.connection_event(ConnectionEvent::Opened(c));
    }
    assert_eq!(ns(&pls), NetworkStatus::Connected);
    for c in [plc_a, plc_b] {
        pls.connection_event(ConnectionEvent::Closed(c, CloseReason::Timeout));
    }
    assert_eq!(ns(&pls), NetworkStatus::TimedOut);
    // An explicit connection, or another originator's I/O connection, is no re-establishment.
    let hmi = connection([198, 18, 0, 9], ConnectionKind::Explicit, 2);
    pls.connection_event(ConnectionEvent::Opened(hmi));
    let other = connection([198, 18, 0, 7], ConnectionKind::ExclusiveOwner, 3);
    pls.connection_event(ConnectionEvent::Opened(other));
    assert_eq!(ns(&pls), NetworkStatus::TimedOut);
    // A comes back: B is still out.
    pls.connection_event(ConnectionEvent::Opened(connection(
        [198, 18, 0, 1],
        ConnectionKind::ExclusiveOwner,
        4,
    )));
    assert_eq!(ns(&pls), NetworkStatus::TimedOut);
    pls.connection_event(ConnectionEvent::Opened(connection(
        [198, 18, 0, 3],
        ConnectionKind::InputOnly,
        5,
    )));
    assert_eq!(ns(&pls), NetworkStatus::Connected);
}

#[test]
fn an_identity_reset_leaves_the_timed_out_state() {
    let mut pls = AmetekPls::new();
    let plc = connection([198, 18, 0, 1], ConnectionKind::ExclusiveOwner, 0);
    pls.connection_event(ConnectionEvent::Opened(plc));
    pls.connection_event(ConnectionEvent::Closed(plc, CloseReason::Timeout));
    assert_eq!(pls.leds().network_status(), NetworkStatus::TimedOut);
    assert_eq!(pls.reset(0), Ok(()));
    assert_eq!(pls.leds().network_status(), NetworkStatus::NoConnection);
}

#[test]
fn the_build_time_resolver_speed_is_parsed_or_refused() {
    use super::super::board::{parse_rpm, BUILD_RPM};
    assert_eq!(parse_rpm("60"), Some(60));
    assert_eq!(parse_rpm("65535"), Some(65535));
    for bad in ["", "65536", "-1", "6O", "60 "] {
        assert_eq!(parse_rpm(bad), None, "{bad:?}");
    }
    // Without ENIP_PLS_RPM at build time the resolver stands still at power-up.
    let expected = option_env!("ENIP_PLS_RPM").and_then(parse_rpm).unwrap_or(0);
    assert_eq!(BUILD_RPM, expected);
    assert_eq!(AmetekPls::new().engine().rpm(), expected);
}
