//! The drive parameters the Parameter object (class 0x0F) serves: instance = the parameter's
//! index in Appendix B, its size and type, scaling, and how a value is read and written.
//!
//! Scaling (Appendix B): positions in position units (EIP.POSUNIT), velocities and
//! accelerations in profile units (EIP.PROFUNIT), other fractional values x1000 (1.001 is
//! 1001). An 8-byte parameter at instance N has its lower 32 bits at N + 1 (4 bytes). A
//! "command" parameter (HOME.MOVE, DRV.CLRFAULTS, DRV.NVSAVE) executes on a write of one byte
//! (any value); reading it gives 0 and executes nothing.
//!
//! Instances 1-11 and 205 are Appendix B's (RSLogix guide, November 2018, p.74; HOME.MOVE 205
//! from the communication manual's own example); 797 EIP.PROFUNIT is the parameter
//! reference's; 796 EIP.POSUNIT is inferred (it precedes EIP.PROFUNIT in Modbus, 1590 and
//! 1592). The other parameters the simulation needs are not in any retrieved copy of
//! Appendix B, so they take project instances from 1001 up (see the profile's README).

use enip_stack::cip::{CipError, CipResult, General};

/// How a parameter's value is scaled on the network.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scale {
    /// An integer as it is.
    Integer,
    /// A fractional value x1000.
    Milli,
    /// Position units.
    Position,
    /// Profile units (velocity, acceleration).
    Profile,
}

/// Who may read and write a parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rule {
    /// Read and written.
    ReadWrite,
    /// Read only.
    ReadOnly,
    /// A command: executes on a write, reads 0.
    Command,
}

/// One parameter of the table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Param {
    /// Parameter object instance.
    pub instance: u16,
    /// AKD parameter name.
    pub name: &'static str,
    /// Data length in bytes (attribute 6).
    pub len: u8,
    /// Signed data type.
    pub signed: bool,
    /// Scaling.
    pub scale: Scale,
    /// Access.
    pub rule: Rule,
    /// Power-up value (network scaling, default units), for parameters that only store.
    pub default: i64,
}

const fn p(
    instance: u16,
    name: &'static str,
    len: u8,
    signed: bool,
    scale: Scale,
    rule: Rule,
    default: i64,
) -> Param {
    Param {
        instance,
        name,
        len,
        signed,
        scale,
        rule,
        default,
    }
}

use Rule::{Command, ReadOnly, ReadWrite};
use Scale::{Integer, Milli, Position, Profile};

/// Instance numbers the code acts on.
pub mod id {
    /// AIN.ZERO (command).
    pub const AIN_ZERO: u16 = 9;
    /// HOME.MOVE (command; the manual's example instance).
    pub const HOME_MOVE: u16 = 205;
    /// EIP.POSUNIT (inferred instance).
    pub const EIP_POSUNIT: u16 = 796;
    /// EIP.PROFUNIT.
    pub const EIP_PROFUNIT: u16 = 797;
    /// DRV.CLRFAULTS (command; project instance).
    pub const DRV_CLRFAULTS: u16 = 1001;
    /// DRV.NVSAVE (command; project instance).
    pub const DRV_NVSAVE: u16 = 1002;
    /// DRV.ACC (project instance).
    pub const DRV_ACC: u16 = 1004;
    /// DRV.DEC (project instance).
    pub const DRV_DEC: u16 = 1006;
    /// DRV.DECSTOP (project instance).
    pub const DRV_DECSTOP: u16 = 1008;
    /// DRV.MOTIONSTAT (project instance).
    pub const DRV_MOTIONSTAT: u16 = 1010;
    /// HOME.MODE (project instance).
    pub const HOME_MODE: u16 = 1012;
    /// HOME.P (project instance).
    pub const HOME_P: u16 = 1013;
    /// MT.TPOSWND (project instance).
    pub const MT_TPOSWND: u16 = 1015;
    /// PL.FB (project instance).
    pub const PL_FB: u16 = 1017;
    /// VL.FB (project instance).
    pub const VL_FB: u16 = 1019;
    /// IL.FB (project instance).
    pub const IL_FB: u16 = 1021;
    /// SWLS.EN (project instance).
    pub const SWLS_EN: u16 = 1022;
    /// SWLS.LIMIT0 (project instance).
    pub const SWLS_LIMIT0: u16 = 1023;
    /// SWLS.LIMIT1 (project instance).
    pub const SWLS_LIMIT1: u16 = 1025;
    /// MT.NUM: the motion task being edited (project instance).
    pub const MT_NUM: u16 = 1030;
    /// MT.P (project instance).
    pub const MT_P: u16 = 1031;
    /// MT.V (project instance).
    pub const MT_V: u16 = 1033;
    /// MT.ACC (project instance).
    pub const MT_ACC: u16 = 1035;
    /// MT.DEC (project instance).
    pub const MT_DEC: u16 = 1037;
    /// MT.CNTL (project instance).
    pub const MT_CNTL: u16 = 1039;
    /// MT.SET: store the edited task (command; project instance).
    pub const MT_SET: u16 = 1040;
    /// MT.LOAD: read task MT.NUM for editing (command; project instance).
    pub const MT_LOAD: u16 = 1041;
    /// EIP.CMDMAP: the command dynamic map's list (project instance; [`super::super::maps`]).
    pub const EIP_CMDMAP: u16 = 1042;
    /// EIP.RSPMAP: the response dynamic map's list (project instance).
    pub const EIP_RSPMAP: u16 = 1043;
}

/// The table, by instance.
pub const TABLE: [Param; 36] = [
    p(1, "AIN.CUTOFF", 4, false, Milli, ReadWrite, 5_000_000),
    p(2, "AIN.DEADBAND", 4, false, Milli, ReadWrite, 0),
    p(3, "AIN.ISCALE", 4, false, Milli, ReadWrite, 1_000),
    p(4, "AIN.OFFSET", 2, true, Milli, ReadWrite, 0),
    p(5, "AIN.PSCALE", 8, true, Position, ReadWrite, 1),
    p(7, "AIN.VALUE", 4, false, Milli, ReadOnly, 0),
    p(8, "AIN.VSCALE", 4, false, Profile, ReadWrite, 1),
    p(id::AIN_ZERO, "AIN.ZERO", 1, false, Integer, Command, 0),
    p(10, "AOUT.ISCALE", 4, false, Milli, ReadWrite, 1_000),
    p(11, "AOUT.MODE", 2, false, Integer, ReadWrite, 0),
    p(id::HOME_MOVE, "HOME.MOVE", 1, false, Integer, Command, 0),
    p(
        id::EIP_POSUNIT,
        "EIP.POSUNIT",
        4,
        false,
        Integer,
        ReadWrite,
        0,
    ),
    p(
        id::EIP_PROFUNIT,
        "EIP.PROFUNIT",
        4,
        false,
        Integer,
        ReadWrite,
        0,
    ),
    p(
        id::DRV_CLRFAULTS,
        "DRV.CLRFAULTS",
        1,
        false,
        Integer,
        Command,
        0,
    ),
    p(id::DRV_NVSAVE, "DRV.NVSAVE", 1, false, Integer, Command, 0),
    p(id::DRV_ACC, "DRV.ACC", 8, false, Profile, ReadWrite, 0),
    p(id::DRV_DEC, "DRV.DEC", 8, false, Profile, ReadWrite, 0),
    p(
        id::DRV_DECSTOP,
        "DRV.DECSTOP",
        8,
        false,
        Profile,
        ReadWrite,
        0,
    ),
    p(
        id::DRV_MOTIONSTAT,
        "DRV.MOTIONSTAT",
        4,
        false,
        Integer,
        ReadOnly,
        0,
    ),
    p(id::HOME_MODE, "HOME.MODE", 2, true, Integer, ReadWrite, 0),
    p(id::HOME_P, "HOME.P", 8, true, Position, ReadWrite, 0),
    p(
        id::MT_TPOSWND,
        "MT.TPOSWND",
        8,
        false,
        Position,
        ReadWrite,
        0,
    ),
    p(id::PL_FB, "PL.FB", 8, true, Position, ReadOnly, 0),
    p(id::VL_FB, "VL.FB", 8, true, Profile, ReadOnly, 0),
    p(id::IL_FB, "IL.FB", 4, true, Milli, ReadOnly, 0),
    p(id::SWLS_EN, "SWLS.EN", 1, false, Integer, ReadWrite, 0),
    p(
        id::SWLS_LIMIT0,
        "SWLS.LIMIT0",
        8,
        true,
        Position,
        ReadWrite,
        0,
    ),
    p(
        id::SWLS_LIMIT1,
        "SWLS.LIMIT1",
        8,
        true,
        Position,
        ReadWrite,
        0,
    ),
    p(id::MT_NUM, "MT.NUM", 1, false, Integer, ReadWrite, 0),
    p(id::MT_P, "MT.P", 8, true, Position, ReadWrite, 0),
    p(id::MT_V, "MT.V", 8, false, Profile, ReadWrite, 0),
    p(id::MT_ACC, "MT.ACC", 8, false, Profile, ReadWrite, 0),
    p(id::MT_DEC, "MT.DEC", 8, false, Profile, ReadWrite, 0),
    p(id::MT_CNTL, "MT.CNTL", 4, false, Integer, ReadWrite, 0),
    p(id::MT_SET, "MT.SET", 1, false, Integer, Command, 0),
    p(id::MT_LOAD, "MT.LOAD", 1, false, Integer, Command, 0),
];

/// Parameters that only store their value, in table order (their index in
/// [`State::stored`]).
const STORED_IDS: [u16; 8] = [1, 2, 3, 4, 5, 7, 8, 10];
/// How many parameters only store.
pub const STORED: usize = STORED_IDS.len() + 1;

/// Power-up values of the stored parameters (AOUT.MODE last).
pub fn stored_defaults() -> [i64; STORED] {
    let mut out = [0; STORED];
    for (slot, id) in out.iter_mut().zip(STORED_IDS.iter().chain([11].iter())) {
        *slot = find(*id).map_or(0, |(_, p)| p.default);
    }
    out
}

/// The index in [`STORED`] of parameter `id`, if it only holds a value.
pub fn stored_index(id: u16) -> Option<usize> {
    STORED_IDS.iter().chain([11].iter()).position(|&i| i == id)
}

/// What an instance addresses: a parameter, and whether it is the lower-32-bit view of an
/// 8-byte one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct View {
    /// The parameter.
    pub param: &'static Param,
    /// True for instance N + 1 of an 8-byte parameter N.
    pub low_word: bool,
}

impl View {
    /// Attribute 6: the data length the instance reads and writes.
    pub fn data_len(&self) -> u8 {
        if self.low_word {
            4
        } else {
            self.param.len
        }
    }
    /// Attribute 5: the data type code (0xC6 for commands).
    pub fn type_code(&self) -> u8 {
        match (self.data_len(), self.param.signed) {
            (1, true) => 0xC2,
            (1, false) => 0xC6,
            (2, true) => 0xC3,
            (2, false) => 0xC7,
            (4, true) => 0xC4,
            (4, false) => 0xC8,
            (_, true) => 0xC5,
            (_, false) => 0xC9,
        }
    }
}

fn find(id: u16) -> Option<(usize, &'static Param)> {
    TABLE.iter().enumerate().find(|(_, p)| p.instance == id)
}

/// The parameter instance `instance` addresses, if any.
pub fn view(instance: u32) -> Option<View> {
    let id = u16::try_from(instance).ok()?;
    if let Some((_, param)) = find(id) {
        return Some(View {
            param,
            low_word: false,
        });
    }
    let (_, param) = find(id.checked_sub(1)?)?;
    (param.len == 8).then_some(View {
        param,
        low_word: true,
    })
}

/// Every instance that exists, in order.
pub fn instances() -> impl Iterator<Item = u16> {
    TABLE.iter().flat_map(|p| {
        let low = (p.len == 8).then_some(p.instance.saturating_add(1));
        core::iter::once(p.instance).chain(low)
    })
}

/// HOME.MODE values the simulation implements: 0, "home using the current position".
pub fn home_mode(value: i64) -> CipResult<i16> {
    match value {
        0 => Ok(0),
        _ => Err(CipError::new(General::InvalidAttributeValue)),
    }
}
