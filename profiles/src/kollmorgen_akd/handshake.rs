//! The command/response handshake run on every consumed command assembly (manual p.11-16).
//!
//! - Enable, Hard Stop and Smooth Stop are levels; Enable acts when it changes (so an
//!   explicit write of attribute 17 is not undone by the next datagram), and the first
//!   command after a connection opens compares with a control word of 0 (\[R\]).
//! - Load/Start: the command data is taken only on its 0 -> 1 transition. Success sets Load
//!   Complete; Load Complete clears once Load/Start is 0 again. A load that fails puts the
//!   error response in the response assembly: type 0x14, byte 4 the CIP general status,
//!   byte 5 the additional code 0xFF, bytes 6-7 the command's bytes 2-3. It stays until the
//!   next successful load (\[R\] item 9); Load Complete stays 0.
//! - Start Block (0 -> 1 with Load/Start 0) runs motion task byte 1 ([`super::motion_tasks`]); an
//!   undefined task answers the error response with 0x16 (object does not exist), a task
//!   the drive refuses (not homed) 0x10. A successful start clears an error response.
//! - Map type 2: the command dynamic map (bytes 36-63) is command data like the rest, taken
//!   on the Load/Start edge before the command type runs ([`dynamic_map`]); a value a
//!   parameter refuses refuses the load (0x09).
//!
//! The response assembly ([`encode`]) reports the drive's state and what the handshake left.

use enip_stack::cip::{CipError, General};
use enip_stack::wire::Writer;

use super::assemblies::{
    command_type as ty, control, map_type, response_type, status1, status2, Command, SIZE,
};
use super::classes::{parameter, position_controller};
use super::device::{Mode, Refusal};
use super::dynamic_map;
use super::motion_tasks::StartError;
use super::params;
use super::state::State;
use super::storage::NvCopy;

/// Additional code of every error response (the manual's table gives 0xFF throughout).
pub const ADDITIONAL: u8 = 0xFF;

/// The error response (type 0x14) of a refused load.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LoadError {
    /// Byte 4: the CIP general status.
    pub code: u8,
    /// Byte 5: the additional code.
    pub additional: u8,
    /// Bytes 6-7: the command's bytes 2-3.
    pub echo: [u8; 2],
}

/// Handshake state: the last command and what its loads left.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Handshake {
    previous: u8,
    command: [u8; SIZE],
    error: Option<LoadError>,
    parameter: Option<[u8; 8]>,
}

impl Default for Handshake {
    fn default() -> Self {
        Self::new()
    }
}

impl Handshake {
    /// No command received yet.
    pub const fn new() -> Self {
        Handshake {
            previous: 0,
            command: [0; SIZE],
            error: None,
            parameter: None,
        }
    }
    /// The last command assembly.
    pub fn command(&self) -> &[u8] {
        &self.command
    }
    /// The error response of the last refused load, until a load succeeds.
    pub fn error(&self) -> Option<LoadError> {
        self.error
    }
    /// The result of the last completed 0x1F command (the value read or written).
    pub fn parameter_result(&self) -> Option<[u8; 8]> {
        self.parameter
    }
    /// A connection opened: the next control word is compared with 0.
    pub fn restart(&mut self) {
        self.previous = 0;
    }
}

fn general(g: General) -> u8 {
    g as u8
}

impl Handshake {
    /// Applies one command assembly (O->T data or an explicit Set of the command assembly) to
    /// the drive's `state` (a DRV.NVSAVE through a parameter command saves to `nv`).
    pub fn consume(&mut self, state: &mut State, nv: &mut NvCopy, data: &[u8]) {
        let cmd = Command(data);
        let now = cmd.control();
        let rising = now & !self.previous;
        let falling = !now & self.previous;
        let drive = &mut state.drive;
        if falling & control::ENABLE != 0 {
            drive.set_enable(false);
        }
        if rising & control::ENABLE != 0 && (!drive.enabled() || drive.hard_stopped()) {
            drive.set_enable(true);
        }
        if now & control::HARD_STOP != 0 {
            drive.hard_stop();
        }
        drive.set_smooth_stop(now & control::SMOOTH_STOP != 0);

        if rising & control::LOAD_START != 0 {
            match self.load(state, nv, &cmd) {
                Ok(()) => {
                    state.load_complete = true;
                    self.error = None;
                }
                Err(e) => {
                    state.load_complete = false;
                    self.error = Some(LoadError {
                        code: e.general,
                        additional: ADDITIONAL,
                        echo: [cmd.byte(2), cmd.byte(3)],
                    });
                }
            }
        } else if now & control::LOAD_START == 0 {
            state.load_complete = false;
        }
        if rising & control::START_BLOCK != 0 && now & control::LOAD_START == 0 {
            let code = match state.start_task(cmd.byte(1)) {
                Ok(_) => None,
                Err(StartError::Undefined) => Some(General::ObjectDoesNotExist),
                Err(StartError::Drive(_)) => Some(General::DeviceStateConflict),
            };
            self.error = code.map(|g| LoadError {
                code: general(g),
                additional: ADDITIONAL,
                echo: [cmd.byte(2), cmd.byte(3)],
            });
        }
        self.previous = now;
        for (dst, src) in self
            .command
            .iter_mut()
            .zip(data.iter().chain(core::iter::repeat(&0)))
        {
            *dst = *src;
        }
    }

    /// Loads the command's data; motion starts when the command type matches the mode.
    fn load(
        &mut self,
        state: &mut State,
        nv: &mut NvCopy,
        cmd: &Command<'_>,
    ) -> Result<(), CipError> {
        let (axis, kind) = cmd.command_type();
        if axis > 1 {
            return Err(invalid());
        }
        // Map type 2: the command dynamic map is command data, loaded first (all slots or none).
        if cmd.map_type() == map_type::DYNAMIC {
            dynamic_map::apply_command(state, &cmd.dynamic_map())?;
        }
        let ctrl = cmd.control();
        let positive = ctrl & control::DIRECTION != 0;
        let relative = ctrl & control::RELATIVE != 0;
        let s: &mut State = state;
        // A new load replaces a running motion task.
        s.tasks.running = None;
        let mode = s.drive.config.mode;
        match kind {
            ty::TARGET_POSITION => {
                s.pc.target_position = cmd.data();
                s.pc.incremental = relative;
                if mode == Mode::Position {
                    s.start_profile(positive).map_err(refused)?;
                }
            }
            ty::TARGET_VELOCITY => {
                s.check_profile(i64::from(cmd.data()).abs().max(1), false)?;
                s.pc.target_velocity = cmd.data();
                if mode == Mode::Velocity {
                    s.start_profile(positive).map_err(refused)?;
                }
            }
            ty::ACCELERATION => {
                s.check_profile(i64::from(cmd.data()), true)?;
                s.pc.acceleration = cmd.data();
            }
            ty::DECELERATION => {
                s.check_profile(i64::from(cmd.data()), true)?;
                s.pc.deceleration = cmd.data();
            }
            ty::TORQUE => {
                let bytes = cmd.data().to_le_bytes();
                position_controller::write(s, position_controller::attr::TORQUE, &bytes)?;
            }
            ty::POSITION_MOVE => {
                let v = s.check_profile(i64::from(cmd.velocity()), false)?;
                let acc = s.check_profile(i64::from(cmd.acceleration()), true)?;
                let dec = s.check_profile(i64::from(cmd.deceleration()), true)?;
                s.pc.target_position = cmd.position();
                s.pc.target_velocity = cmd.velocity();
                if mode == Mode::Position {
                    let distance = s.pos_counts(i64::from(cmd.position()));
                    let target = if relative {
                        s.drive.target().saturating_add(distance)
                    } else {
                        distance
                    };
                    s.drive.start_move(target, v, acc, dec).map_err(refused)?;
                }
            }
            ty::JOG => {
                let v = s.check_profile(i64::from(cmd.velocity()).abs(), false)?;
                let acc = s.check_profile(i64::from(cmd.acceleration()), true)?;
                let dec = s.check_profile(i64::from(cmd.deceleration()), true)?;
                if mode != Mode::Torque {
                    let v = if positive { v } else { v.saturating_neg() };
                    s.drive.start_jog(v, acc, dec);
                }
            }
            ty::SET_ATTRIBUTE => {
                let id = u16::from(cmd.byte(24));
                let def = position_controller::CLASS_DEF
                    .attribute(id)
                    .ok_or(CipError::new(General::AttributeNotSupported))?;
                if !def.access.settable() {
                    return Err(General::AttributeNotSettable.into());
                }
                let bytes = cmd.data().to_le_bytes();
                let n = def.data_type.fixed_size().unwrap_or(4).min(4);
                position_controller::write(s, id, bytes.get(..n).unwrap_or(&bytes))?;
            }
            ty::PARAMETER => {
                let instance = u16::from_le_bytes([cmd.byte(4), cmd.byte(5)]);
                let view = params::view(u32::from(instance))
                    .ok_or(CipError::new(General::ObjectDoesNotExist))?;
                let result = match cmd.byte(6) {
                    0 => parameter::value(s, &view),
                    1 => {
                        let data = cmd.parameter_data();
                        let value = parameter::decode(
                            &view,
                            data.get(..usize::from(view.data_len())).unwrap_or(&data),
                        )?;
                        parameter::write(s, nv, &view, value)?;
                        parameter::value(s, &view)
                    }
                    _ => return Err(invalid()),
                };
                let mut out = [0u8; 8];
                let bytes = result.to_le_bytes();
                let n = usize::from(view.data_len()).min(8);
                for (dst, src) in out.iter_mut().zip(bytes.iter()).take(n) {
                    *dst = *src;
                }
                self.parameter = Some(out);
            }
            _ => return Err(invalid()),
        }
        Ok(())
    }
}

fn refused(r: Refusal) -> CipError {
    match r {
        Refusal::NotHomed | Refusal::NotReady => CipError::new(General::DeviceStateConflict),
    }
}

fn invalid() -> CipError {
    CipError::new(General::InvalidParameter)
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
