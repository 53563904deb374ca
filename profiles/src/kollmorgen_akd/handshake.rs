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
//!   on the Load/Start edge after the command type and axis are found valid and before the
//!   command runs ([`dynamic_map`]); a value a parameter refuses refuses the load (0x09).
//! - A refused load changes nothing: the settings it wrote (map, targets) are put back; only
//!   the drive's own reaction stays (the not-homed fault of p.11). A load that is refused or
//!   starts nothing leaves a running motion task running (byte 1, Status Word 1 bit 1).
//!
//! The response assembly ([`super::response`]) reports what the handshake left.

use enip_stack::cip::{CipError, General};

use super::assemblies::{command_type as ty, control, map_type, Command, SIZE};
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

/// Applies one command assembly (O->T data or an explicit Set of the command assembly) to
/// the drive's `state` (a DRV.NVSAVE through a parameter command saves to `nv`).
pub fn consume(io: &mut Handshake, state: &mut State, nv: &mut NvCopy, data: &[u8]) {
    let cmd = Command(data);
    let now = cmd.control();
    let rising = now & !io.previous;
    let falling = !now & io.previous;
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
        let before = state.snapshot();
        match load(io, state, nv, &cmd) {
            Ok(()) => {
                state.load_complete = true;
                io.error = None;
            }
            Err(e) => {
                state.restore(&before);
                state.load_complete = false;
                io.error = Some(LoadError {
                    code: e.general.into(),
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
        io.error = code.map(|g| LoadError {
            code: general(g),
            additional: ADDITIONAL,
            echo: [cmd.byte(2), cmd.byte(3)],
        });
    }
    io.previous = now;
    for (dst, src) in io
        .command
        .iter_mut()
        .zip(data.iter().chain(core::iter::repeat(&0)))
    {
        *dst = *src;
    }
}

/// Loads the command's data; motion starts when the command type matches the mode.
fn load(
    io: &mut Handshake,
    state: &mut State,
    nv: &mut NvCopy,
    cmd: &Command<'_>,
) -> Result<(), CipError> {
    let (axis, kind) = cmd.command_type();
    if axis > 1 || !ty::is_defined(kind) {
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
    let mode = s.drive.config.mode;
    match kind {
        ty::TARGET_POSITION => {
            s.pc.target_position = cmd.data();
            s.pc.incremental = relative;
            if mode == Mode::Position {
                s.start_profile(s.pc.target_velocity, positive)
                    .map_err(refused)?;
            }
        }
        ty::TARGET_VELOCITY => {
            // 0 is a velocity setpoint like any other: the drive ramps down and the
            // trajectory ends.
            s.check_profile(i64::from(cmd.data()).abs().max(1), false)?;
            s.pc.target_velocity = cmd.data();
            if mode == Mode::Velocity {
                s.start_profile(cmd.data(), positive).map_err(refused)?;
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
            let profile = [
                s.check_profile(i64::from(cmd.velocity()), false),
                s.check_profile(i64::from(cmd.acceleration()), true),
                s.check_profile(i64::from(cmd.deceleration()), true),
            ];
            let [v, acc, dec] = match profile {
                [Ok(v), Ok(acc), Ok(dec)] => [v, acc, dec],
                // A move the drive cannot run (e.g. velocity 0): an invalid motion task
                // in position mode (DRV.MOTIONSTAT bit 10), data out of range (0x09).
                _ => {
                    if mode == Mode::Position && s.drive.ready() {
                        s.drive.task_rejected();
                    }
                    return Err(CipError::new(General::InvalidAttributeValue));
                }
            };
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
                s.drive.start_jog(v, acc, dec).map_err(refused)?;
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
            io.parameter = Some(out);
        }
        _ => return Err(invalid()),
    }
    Ok(())
}

fn refused(r: Refusal) -> CipError {
    match r {
        Refusal::NotHomed | Refusal::NotReady => CipError::new(General::DeviceStateConflict),
        Refusal::Invalid => CipError::new(General::InvalidAttributeValue),
    }
}

fn invalid() -> CipError {
    CipError::new(General::InvalidParameter)
}
