//! The response assembly (T->O, manual p.13-16), encoded from the drive's state and what the
//! handshake left every time the stack produces it: the status words, the response type's
//! data, position, velocity, DRV.MOTIONSTAT, the attribute or parameter result, and bytes
//! 36-63 by map type.

use enip_stack::wire::Writer;

use super::assemblies::{map_type, response_type, status1, status2, Command, SIZE};
use super::classes::position_controller;
use super::dynamic_map;
use super::handshake::Handshake;
use super::state::State;

/// Status Word 1 from the drive's state.
pub fn status_word_1(state: &State) -> u8 {
    let d = &state.drive;
    let mut s = 0;
    for (on, bit) in [
        (d.enabled(), status1::ENABLED),
        (d.homed(), status1::HOMED),
        (d.positive(), status1::DIRECTION),
        (d.fault().is_some(), status1::FAULT),
        (d.in_position(), status1::IN_POSITION),
        (state.executing_task().is_some(), status1::BLOCK),
        (d.in_motion(), status1::IN_MOTION),
    ] {
        if on {
            s |= bit;
        }
    }
    s
}

/// Status Word 2 from the drive's state and the handshake.
pub fn status_word_2(state: &State) -> u8 {
    let d = &state.drive;
    let mut s = 0;
    for (on, bit) in [
        (state.load_complete, status2::LOAD_COMPLETE),
        (d.negative_limit(), status2::NEGATIVE_SW_LIMIT),
        (d.positive_limit(), status2::POSITIVE_SW_LIMIT),
    ] {
        if on {
            s |= bit;
        }
    }
    s
}

/// Bytes 4-7 for response type `kind`.
fn response_data(state: &State, kind: u8) -> i32 {
    let d = &state.drive;
    match kind {
        response_type::ACTUAL_POSITION => state.pos_units(d.position()),
        response_type::COMMANDED_POSITION => state.pos_units(d.commanded_position()),
        response_type::ACTUAL_VELOCITY => state.prof_units(d.velocity()),
        response_type::COMMANDED_VELOCITY => state.prof_units(d.commanded_velocity()),
        response_type::TORQUE => d.torque(),
        _ => 0,
    }
}

/// Custom map 1 (map type 1), a fixed project map of bytes 36-63: commanded position,
/// commanded velocity, actual torque (mA), target position (attribute 6), target velocity
/// (attribute 7), Position Controller mode, and 4 reserved bytes.
pub fn custom_map(state: &State) -> [i32; 7] {
    let d = &state.drive;
    [
        state.pos_units(d.commanded_position()),
        state.prof_units(d.commanded_velocity()),
        d.torque(),
        state.pc.target_position,
        state.pc.target_velocity,
        i32::from(d.config.mode.code()),
        0,
    ]
}

/// Encodes the response assembly into `out` (64 bytes); returns the length.
pub fn encode(state: &State, io: &Handshake, out: &mut [u8]) -> usize {
    let cmd = Command(io.command());
    let mut r = [0u8; SIZE];
    r[0] = status_word_1(state);
    r[1] = state.executing_task().unwrap_or(0);
    r[2] = status_word_2(state);
    match io.error() {
        Some(e) => {
            r[3] = response_type::ERROR | (cmd.byte(3) & 0xE0);
            r[4..8].copy_from_slice(&[e.code, e.additional, e.echo[0], e.echo[1]]);
        }
        None => {
            r[3] = cmd.byte(3);
            r[4..8].copy_from_slice(&response_data(state, cmd.response_type()).to_le_bytes());
        }
    }
    let d = &state.drive;
    r[8..12].copy_from_slice(&state.pos_units(d.position()).to_le_bytes());
    r[12..16].copy_from_slice(&state.prof_units(d.velocity()).to_le_bytes());
    r[16..20].copy_from_slice(&d.motionstat().to_le_bytes());
    let attribute = cmd.attribute_to_get();
    if attribute != 0 {
        let mut value = [0u8; 8];
        let mut w = Writer::new(&mut value);
        // An attribute that does not exist, or is longer than 8 bytes, reports zeros.
        if position_controller::read(state, u16::from(attribute), &mut w).is_err() {
            value = [0; 8];
        }
        r[24..32].copy_from_slice(&value);
    } else if let Some(result) = io.parameter_result() {
        r[24..32].copy_from_slice(&result);
    }
    r[32] = attribute;
    r[33] = cmd.map_type();
    match cmd.map_type() {
        map_type::CUSTOM_1 => {
            for (chunk, v) in r[36..64].chunks_exact_mut(4).zip(custom_map(state)) {
                chunk.copy_from_slice(&v.to_le_bytes());
            }
        }
        map_type::DYNAMIC => r[36..64].copy_from_slice(&dynamic_map::response(state)),
        // Static map (and any other value): bytes 36-63 stay 0.
        _ => {}
    }
    let n = out.len().min(SIZE);
    for (o, b) in out.iter_mut().zip(&r) {
        *o = *b;
    }
    n
}
