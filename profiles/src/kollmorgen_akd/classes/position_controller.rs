//! The Position Controller object (class 0x25, instance 1; manual Appendix A, p.37) as a
//! declared class: the stack answers the services and statuses, this module converts
//! values and applies writes to the drive.
//!
//! Attributes: Appendix A's, and 22 (jog velocity) that section 7 names for velocity-mode
//! starts.
//!
//! Services: Get_Attribute_Single (0x0E) and Set_Attribute_Single (0x10) as the manual
//! lists (p.9), and the attribute list services the stack adds; Get_Attributes_All answers
//! 0x08 (not in the manual's list). Statuses (p.10): read-only 0x0E, unknown attribute 0x14,
//! value out of range 0x09; attribute 101 is write-only (Get 0x2C); a mode change while the
//! drive moves 0x10.

use enip_stack::cip::object::{AttributeDef, ClassDef, DataType};
use enip_stack::cip::{CipError, CipResult, General};
use enip_stack::wire::Writer;

use super::super::device::{Mode, Refusal, MAX_TORQUE_MA, MAX_VELOCITY};
use super::super::params;
use super::super::state::State;

/// Class code.
pub const CLASS: u16 = 0x25;

/// Attribute IDs (Appendix A).
pub mod attr {
    /// Number of attributes.
    pub const COUNT: u16 = 1;
    /// Attribute list.
    pub const LIST: u16 = 2;
    /// Mode: 0 position, 1 velocity, 2 torque.
    pub const MODE: u16 = 3;
    /// Position units.
    pub const POSITION_UNITS: u16 = 4;
    /// Profile units.
    pub const PROFILE_UNITS: u16 = 5;
    /// Target position.
    pub const TARGET_POSITION: u16 = 6;
    /// Target velocity.
    pub const TARGET_VELOCITY: u16 = 7;
    /// Acceleration.
    pub const ACCELERATION: u16 = 8;
    /// Deceleration.
    pub const DECELERATION: u16 = 9;
    /// Incremental position flag.
    pub const INCREMENTAL: u16 = 10;
    /// Load data / profile handshake.
    pub const LOAD_DATA: u16 = 11;
    /// Enable (DRV.EN).
    pub const ENABLE: u16 = 17;
    /// Jog velocity: the velocity of a velocity-mode start through attribute 11.
    pub const JOG_VELOCITY: u16 = 22;
    /// Torque.
    pub const TORQUE: u16 = 25;
    /// Load data complete.
    pub const LOAD_COMPLETE: u16 = 58;
    /// Home mode.
    pub const HOME_MODE: u16 = 100;
    /// Home move (write-only).
    pub const HOME_MOVE: u16 = 101;
}

/// The attributes, in Appendix A's order.
const ATTRIBUTES: [AttributeDef; 17] = [
    AttributeDef::get(attr::COUNT, DataType::Usint, "Number of Attributes"),
    AttributeDef::get(attr::LIST, DataType::Bytes(17), "Attribute List"),
    AttributeDef::get_set(attr::MODE, DataType::Usint, "Mode"),
    AttributeDef::get_set(attr::POSITION_UNITS, DataType::Dint, "Position Units"),
    AttributeDef::get_set(attr::PROFILE_UNITS, DataType::Dint, "Profile Units"),
    AttributeDef::get_set(attr::TARGET_POSITION, DataType::Dint, "Target Position"),
    AttributeDef::get_set(attr::TARGET_VELOCITY, DataType::Dint, "Target Velocity"),
    AttributeDef::get_set(attr::ACCELERATION, DataType::Dint, "Acceleration"),
    AttributeDef::get_set(attr::DECELERATION, DataType::Dint, "Deceleration"),
    AttributeDef::get_set(
        attr::INCREMENTAL,
        DataType::Bool,
        "Incremental Position Flag",
    ),
    AttributeDef::get_set(
        attr::LOAD_DATA,
        DataType::Bool,
        "Load Data/Profile Handshake",
    ),
    AttributeDef::get_set(attr::ENABLE, DataType::Bool, "Enable"),
    AttributeDef::get_set(attr::JOG_VELOCITY, DataType::Dint, "Jog Velocity"),
    AttributeDef::get_set(attr::TORQUE, DataType::Dint, "Torque"),
    AttributeDef::get_set(attr::LOAD_COMPLETE, DataType::Bool, "Load Data Complete"),
    AttributeDef::get_set(attr::HOME_MODE, DataType::Int, "Home Mode"),
    AttributeDef::set(attr::HOME_MOVE, DataType::Bool, "Home Move"),
];

/// The class as the stack serves it: one instance, no Get_Attributes_All.
pub const CLASS_DEF: ClassDef = ClassDef {
    id: CLASS,
    name: "Position Controller",
    revision: 1,
    max_instance: 1,
    attributes: &ATTRIBUTES,
    get_all: &[],
    optional_attributes: &[],
};

fn out_of_range() -> CipError {
    CipError::new(General::InvalidAttributeValue)
}

/// Writes attribute `id`'s value (its own length, LSB first).
pub fn read(state: &State, id: u16, w: &mut Writer<'_>) -> CipResult {
    let d = &state.drive;
    let pc = &state.pc;
    match id {
        attr::COUNT => w.u8(ATTRIBUTES.len() as u8)?,
        attr::LIST => {
            for a in &ATTRIBUTES {
                w.u8(a.id as u8)?;
            }
        }
        attr::MODE => w.u8(d.config.mode.code())?,
        attr::POSITION_UNITS => w.u32(pc.position_units)?,
        attr::PROFILE_UNITS => w.u32(pc.profile_units)?,
        attr::TARGET_POSITION => w.u32(pc.target_position as u32)?,
        attr::TARGET_VELOCITY => w.u32(pc.target_velocity as u32)?,
        attr::ACCELERATION => w.u32(pc.acceleration as u32)?,
        attr::DECELERATION => w.u32(pc.deceleration as u32)?,
        attr::INCREMENTAL => w.u8(u8::from(pc.incremental))?,
        attr::LOAD_DATA => w.u8(u8::from(d.moving_to_target()))?,
        attr::ENABLE => w.u8(u8::from(d.enabled()))?,
        attr::JOG_VELOCITY => w.u32(pc.jog_velocity as u32)?,
        attr::TORQUE => w.u32(d.torque() as u32)?,
        attr::LOAD_COMPLETE => w.u8(u8::from(state.load_complete))?,
        attr::HOME_MODE => w.u16(d.config.home_mode as u16)?,
        _ => return Err(General::AttributeNotSupported.into()),
    }
    Ok(())
}

/// The value of a Set of attribute `id`: the attribute's bytes, sign-extended.
fn decode(id: u16, value: &[u8]) -> CipResult<i64> {
    let def = CLASS_DEF
        .attribute(id)
        .ok_or(CipError::new(General::AttributeNotSupported))?;
    let bytes = |n: usize| value.get(..n).ok_or(CipError::new(General::NotEnoughData));
    Ok(match def.data_type {
        DataType::Bool | DataType::Usint => i64::from(bytes(1)?.first().copied().unwrap_or(0)),
        DataType::Int => {
            let b = bytes(2)?;
            i64::from(i16::from_le_bytes([
                b.first().copied().unwrap_or(0),
                b.get(1).copied().unwrap_or(0),
            ]))
        }
        _ => {
            let mut four = [0u8; 4];
            four.copy_from_slice(bytes(4)?);
            i64::from(i32::from_le_bytes(four))
        }
    })
}

fn boolean(v: i64) -> CipResult<bool> {
    match v {
        0 => Ok(false),
        1 => Ok(true),
        _ => Err(out_of_range()),
    }
}

/// Applies a Set of attribute `id` (exactly its bytes), or refuses it and changes nothing.
pub fn write(state: &mut State, id: u16, value: &[u8]) -> CipResult {
    let v = decode(id, value)?;
    let positive = |v: i64| {
        u32::try_from(v)
            .ok()
            .filter(|&u| u > 0)
            .ok_or(out_of_range())
    };
    let dint = |v: i64| i32::try_from(v).map_err(|_| out_of_range());
    match id {
        attr::MODE => state.set_mode(u8::try_from(v).map_err(|_| out_of_range())?)?,
        attr::POSITION_UNITS => state.pc.position_units = positive(v)?,
        attr::PROFILE_UNITS => state.pc.profile_units = positive(v)?,
        attr::TARGET_POSITION => state.pc.target_position = dint(v)?,
        attr::TARGET_VELOCITY => {
            if state.prof_counts(v.abs()) > MAX_VELOCITY {
                return Err(out_of_range());
            }
            state.pc.target_velocity = dint(v)?;
        }
        attr::JOG_VELOCITY => {
            if state.prof_counts(v.abs()) > MAX_VELOCITY {
                return Err(out_of_range());
            }
            state.pc.jog_velocity = dint(v)?;
        }
        attr::ACCELERATION => {
            state.check_profile(v, true)?;
            state.pc.acceleration = dint(v)?;
        }
        attr::DECELERATION => {
            state.check_profile(v, true)?;
            state.pc.deceleration = dint(v)?;
        }
        attr::INCREMENTAL => state.pc.incremental = boolean(v)?,
        attr::LOAD_DATA => {
            if boolean(v)? {
                // Position mode moves at attribute 7, velocity mode at attribute 22 (its
                // sign the direction), section 7.
                let velocity = match state.drive.config.mode {
                    Mode::Velocity => state.pc.jog_velocity,
                    _ => state.pc.target_velocity,
                };
                match state.start_profile(velocity, velocity >= 0) {
                    Err(Refusal::NotHomed) => return Err(General::DeviceStateConflict.into()),
                    Err(Refusal::Invalid) => return Err(out_of_range()),
                    Err(Refusal::NotReady) | Ok(_) => {}
                }
            }
        }
        attr::ENABLE => {
            let on = boolean(v)?;
            if on != state.drive.enabled() || (on && state.drive.hard_stopped()) {
                state.drive.set_enable(on);
            }
        }
        attr::TORQUE => {
            let ma = dint(v)?;
            if ma.unsigned_abs() > MAX_TORQUE_MA.unsigned_abs() {
                return Err(out_of_range());
            }
            state.drive.set_torque(ma);
        }
        attr::LOAD_COMPLETE => state.load_complete = boolean(v)?,
        attr::HOME_MODE => state.drive.config.home_mode = params::home_mode(v)?,
        attr::HOME_MOVE => {
            if boolean(v)? {
                state.home()?;
            }
        }
        _ => return Err(General::AttributeNotSettable.into()),
    }
    Ok(())
}
