//! The three assemblies (manual p.10-11) and the byte layouts of the command (O->T) and
//! response (T->O) assemblies: the command as a view whose getters cannot panic, the
//! response encoded from the drive's state every time the stack produces it.
//!
//! Every multi-byte field is least significant byte first (p.11, p.14).

use enip_stack::wire::Writer;
use enip_stack::{AssemblyInfo, AssemblyRole};

use super::classes::position_controller;
use super::dynamic_map;
use super::handshake::Handshake;
use super::state::State;

/// Configuration assembly: 0 bytes (p.11).
pub const CONFIG: u16 = 100;
/// Command assembly, O->T with the run/idle header: the instance is on a page break no
/// copy shows; 101 (\[R\] item 1), next to 100 and 102.
pub const COMMAND: u16 = 101;
/// Response assembly, T->O without header (p.10).
pub const RESPONSE: u16 = 102;
/// Both I/O assemblies are 64 bytes.
pub const SIZE: usize = 64;

/// The assembly instances.
pub const INFOS: [AssemblyInfo; 3] = [
    AssemblyInfo {
        instance: CONFIG,
        role: AssemblyRole::Config,
        size: 0,
        run_idle_header: false,
    },
    AssemblyInfo {
        instance: COMMAND,
        role: AssemblyRole::Output,
        size: SIZE as u16,
        run_idle_header: true,
    },
    AssemblyInfo {
        instance: RESPONSE,
        role: AssemblyRole::Input,
        size: SIZE as u16,
        run_idle_header: false,
    },
];

/// Control word bits (command byte 0, p.12).
pub mod control {
    /// Bit 7: enable the amplifier.
    pub const ENABLE: u8 = 1 << 7;
    /// Bit 5: hard stop.
    pub const HARD_STOP: u8 = 1 << 5;
    /// Bit 4: smooth stop.
    pub const SMOOTH_STOP: u8 = 1 << 4;
    /// Bit 3: direction (velocity mode): 1 positive, 0 negative.
    pub const DIRECTION: u8 = 1 << 3;
    /// Bit 2: relative (position mode): 0 absolute, 1 incremental.
    pub const RELATIVE: u8 = 1 << 2;
    /// Bit 1: start the motion task of byte 1.
    pub const START_BLOCK: u8 = 1 << 1;
    /// Bit 0: load the command data (on its 0 -> 1 transition).
    pub const LOAD_START: u8 = 1 << 0;
}

/// Status Word 1 bits (response byte 0, seed page).
pub mod status1 {
    /// Bit 7: enable state.
    pub const ENABLED: u8 = 1 << 7;
    /// Bit 5: homed.
    pub const HOMED: u8 = 1 << 5;
    /// Bit 4: current direction (1 positive).
    pub const DIRECTION: u8 = 1 << 4;
    /// Bit 3: general fault.
    pub const FAULT: u8 = 1 << 3;
    /// Bit 2: in position.
    pub const IN_POSITION: u8 = 1 << 2;
    /// Bit 1: block in execution.
    pub const BLOCK: u8 = 1 << 1;
    /// Bit 0: in motion.
    pub const IN_MOTION: u8 = 1 << 0;
}

/// Status Word 2 bits (response byte 2, p.15).
pub mod status2 {
    /// Bit 7: load complete.
    pub const LOAD_COMPLETE: u8 = 1 << 7;
    /// Bit 4: at or beyond the negative software limit.
    pub const NEGATIVE_SW_LIMIT: u8 = 1 << 4;
    /// Bit 3: at or beyond the positive software limit.
    pub const POSITIVE_SW_LIMIT: u8 = 1 << 3;
    /// Bit 2: negative hardware limit input.
    pub const NEGATIVE_HW_LIMIT: u8 = 1 << 2;
    /// Bit 1: positive hardware limit input.
    pub const POSITIVE_HW_LIMIT: u8 = 1 << 1;
}

/// Command types (byte 2 bits 0-4).
pub mod command_type {
    /// Target position (data bytes 4-7).
    pub const TARGET_POSITION: u8 = 0x01;
    /// Target velocity (data bytes 4-7; \[R\] item 5, ODVA numbering).
    pub const TARGET_VELOCITY: u8 = 0x02;
    /// Acceleration (data bytes 4-7; \[R\] item 5).
    pub const ACCELERATION: u8 = 0x03;
    /// Deceleration (data bytes 4-7; \[R\] item 5).
    pub const DECELERATION: u8 = 0x04;
    /// Torque, mA (data bytes 4-7).
    pub const TORQUE: u8 = 0x05;
    /// Position move (bytes 8-23).
    pub const POSITION_MOVE: u8 = 0x06;
    /// Jog move (bytes 12-23).
    pub const JOG: u8 = 0x07;
    /// Set an attribute of the Position Controller object (\[R\] item 6 layout).
    pub const SET_ATTRIBUTE: u8 = 0x1B;
    /// Read or write a parameter value (\[R\] item 6 layout).
    pub const PARAMETER: u8 = 0x1F;
}

/// Response types (byte 3 bits 0-4).
pub mod response_type {
    /// No data.
    pub const NONE: u8 = 0x00;
    /// Actual position (\[R\] item 5).
    pub const ACTUAL_POSITION: u8 = 0x01;
    /// Commanded position (\[R\] item 5).
    pub const COMMANDED_POSITION: u8 = 0x02;
    /// Actual velocity (\[R\] item 5).
    pub const ACTUAL_VELOCITY: u8 = 0x03;
    /// Commanded velocity (\[R\] item 5).
    pub const COMMANDED_VELOCITY: u8 = 0x04;
    /// Actual torque, mA (p.15).
    pub const TORQUE: u8 = 0x05;
    /// Command/response error (p.15-16).
    pub const ERROR: u8 = 0x14;
}

/// Map types (byte 33).
pub mod map_type {
    /// Static map: bytes 36-63 are 0.
    pub const STATIC: u8 = 0;
    /// Custom map 1: the project's fixed map (see [`super::custom_map`]).
    pub const CUSTOM_1: u8 = 1;
    /// Dynamic map: bytes 36-63 per EIP.RSPMAP / EIP.CMDMAP (see [`super::super::dynamic_map`]).
    pub const DYNAMIC: u8 = 2;
}

/// A command assembly's bytes (any length; missing bytes read as 0).
#[derive(Debug, Clone, Copy)]
pub struct Command<'a>(pub &'a [u8]);

impl Command<'_> {
    /// Byte `i`.
    pub fn byte(&self, i: usize) -> u8 {
        self.0.get(i).copied().unwrap_or(0)
    }
    /// The 32-bit signed field at `i`.
    pub fn dint(&self, i: usize) -> i32 {
        i32::from_le_bytes([
            self.byte(i),
            self.byte(i.saturating_add(1)),
            self.byte(i.saturating_add(2)),
            self.byte(i.saturating_add(3)),
        ])
    }
    /// Byte 0, the control word.
    pub fn control(&self) -> u8 {
        self.byte(0)
    }
    /// Byte 2 split into (axis, command type).
    pub fn command_type(&self) -> (u8, u8) {
        (self.byte(2) >> 5, self.byte(2) & 0x1F)
    }
    /// Byte 3 bits 0-4: the response type asked for.
    pub fn response_type(&self) -> u8 {
        self.byte(3) & 0x1F
    }
    /// Bytes 4-7.
    pub fn data(&self) -> i32 {
        self.dint(4)
    }
    /// Bytes 8-11.
    pub fn position(&self) -> i32 {
        self.dint(8)
    }
    /// Bytes 12-15.
    pub fn velocity(&self) -> i32 {
        self.dint(12)
    }
    /// Bytes 16-19.
    pub fn acceleration(&self) -> i32 {
        self.dint(16)
    }
    /// Bytes 20-23.
    pub fn deceleration(&self) -> i32 {
        self.dint(20)
    }
    /// Bytes 24-31.
    pub fn parameter_data(&self) -> [u8; 8] {
        core::array::from_fn(|i| self.byte(i.saturating_add(24)))
    }
    /// Byte 32: the Position Controller attribute to report in response bytes 24-31.
    pub fn attribute_to_get(&self) -> u8 {
        self.byte(32)
    }
    /// Byte 33: the map type.
    pub fn map_type(&self) -> u8 {
        self.byte(33)
    }
    /// Bytes 36-63: the command dynamic map.
    pub fn dynamic_map(&self) -> [u8; dynamic_map::LEN] {
        core::array::from_fn(|i| self.byte(i.saturating_add(dynamic_map::START)))
    }
}

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
        (
            super::motion_tasks::executing(state).is_some(),
            status1::BLOCK,
        ),
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
    r[1] = super::motion_tasks::executing(state).unwrap_or(0);
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
