//! The PositionServo variable table: every variable the manual names, with its native format,
//! access, EPM (non-volatile) storage, power-up default and the values a write may take, and
//! the RAM copy of all of them.
//!
//! The manual (P94ETH01D) refers to the PositionServo Programming Manual (PM94H201) for the
//! complete list; this table holds the variables the EtherNet/IP manual itself uses. Every
//! variable can be read and written as a 32-bit integer or a 32-bit REAL: the conversion is
//! automatic (7.2). Conversions here: an integer variable read as REAL is its value as a
//! float; a REAL variable read as integer is rounded to the nearest integer (saturating); a
//! REAL written to an integer variable is rounded the same way. Variables the manual types
//! `U32` (status words, DataLink control words, the multicast address) are unsigned.
//!
//! STATUS: section 5.5 calls STATUS #53 and EXSTATUS #54, table 18 calls them PID 54 and
//! PID 83. Table 18 is taken as authoritative: STATUS is 54 and EXSTATUS is 83; 53 reads the
//! same STATUS word, so a program written against either place works.

use enip_stack::cip::{CipError, CipResult, General};

/// A decoded DataLink control word.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Link {
    /// Bit 31: the link transfers data.
    pub enabled: bool,
    /// Bit 30: REAL (F32) rather than integer (U32).
    pub real: bool,
    /// Bits 15-0: the linked variable.
    pub id: u16,
}

impl Link {
    /// Bits 29-16, which must be zero.
    pub const RESERVED: u32 = 0x3FFF_0000;
    const ENABLE: u32 = 1 << 31;
    const REAL: u32 = 1 << 30;

    /// Decodes a control word (the reserved bits are ignored).
    pub const fn decode(control: u32) -> Self {
        Link {
            enabled: control & Self::ENABLE != 0,
            real: control & Self::REAL != 0,
            id: control as u16,
        }
    }

    /// The control word for this link.
    pub const fn encode(self) -> u32 {
        (if self.enabled { Self::ENABLE } else { 0 })
            | (if self.real { Self::REAL } else { 0 })
            | self.id as u32
    }
}

/// Variable IDs (the instance numbers of class 0x64).
pub mod id {
    /// VAR_ENABLE_SWITCH_TYPE: 0 inhibit only, 1 run (table 26).
    pub const ENABLE_SWITCH_TYPE: u16 = 29;
    /// VAR_CURRENTLIMIT: current limit in A (7.2).
    pub const CURRENT_LIMIT: u16 = 30;
    /// VAR_DRIVEMODE: 0 torque, 1 velocity, 2 position (tables 26, 27).
    pub const DRIVE_MODE: u16 = 34;
    /// VAR_REFERENCE: 0 external (analog input), 1 internal (tables 26, 27).
    pub const REFERENCE_SOURCE: u16 = 37;
    /// VAR_ENABLE: non-zero enables the drive, 0 disables it (7.2, table 20).
    pub const ENABLE: u16 = 52;
    /// STATUS as section 5.5 numbers it: the same word as [`STATUS`].
    pub const STATUS_ALIAS: u16 = 53;
    /// STATUS (table 18).
    pub const STATUS: u16 = 54;
    /// INPUTS: digital input states (table 15).
    pub const INPUTS: u16 = 65;
    /// VAR_ENABLEACCELDECEL: velocity mode accel/decel limits on (1) or off (0) (table 26).
    pub const ENABLE_ACCEL_DECEL: u16 = 75;
    /// VAR_ACCEL_LIMIT: acceleration limit in units/s² (table 26, 8.3).
    pub const ACCEL_LIMIT: u16 = 76;
    /// VAR_DECEL_LIMIT: deceleration limit in units/s² (table 26, 8.3).
    pub const DECEL_LIMIT: u16 = 77;
    /// EXSTATUS: extended status (table 18, 8.4).
    pub const EXSTATUS: u16 = 83;
    /// VAR_MOVEP: writing starts an absolute move to this position (8.2).
    pub const MOVEP: u16 = 92;
    /// VAR_MOVED: writing starts a relative move by this distance (7.2, 8.2).
    pub const MOVED: u16 = 93;
    /// V0, the first user variable (6.3).
    pub const V0: u16 = 100;
    /// V31, the last user variable (table 5).
    pub const V31: u16 = 131;
    /// REFERENCE: velocity in units/s (RPS) or current in A (table 20).
    pub const REFERENCE: u16 = 139;
    /// S-curve relative move (8.2).
    pub const MOVEDS: u16 = 177;
    /// S-curve absolute move (8.2).
    pub const MOVEPS: u16 = 178;
    /// VAR_PHCUR: phase current in A (5.4, table 19).
    pub const PHASE_CURRENT: u16 = 188;
    /// Registered position (table 19).
    pub const REGISTERED_POSITION: u16 = 213;
    /// Actual position in units (table 19).
    pub const ACTUAL_POSITION: u16 = 215;
    /// Position error in units (table 19).
    pub const POSITION_ERROR: u16 = 216;
    /// Actual velocity in units/s (table 19).
    pub const ACTUAL_VELOCITY: u16 = 260;
    /// LinkA_in, the first input DataLink control word (table 10).
    pub const LINK_A_IN: u16 = 261;
    /// LinkA_out, the first output DataLink control word (table 11).
    pub const LINK_A_OUT: u16 = 265;
    /// CIP heartbeat, written through assembly 109 (table 16).
    pub const CIP_HEARTBEAT: u16 = 272;
    /// Multicast TTL (2.2.1).
    pub const MULTICAST_TTL: u16 = 273;
    /// Multicast address, as a 32-bit number (2.2.1).
    pub const MULTICAST_ADDRESS: u16 = 275;
}

/// The default multicast address, 239.192.15.32 (2.2.1, table 5).
pub const DEFAULT_MULTICAST: u32 = 0xEFC0_0F20;

/// Native format of a variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Signed 32-bit integer.
    Int,
    /// Unsigned 32-bit word (bit fields, addresses).
    Word,
    /// 32-bit REAL.
    Real,
}

/// Whether the network may write a variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    /// Read and written.
    ReadWrite,
    /// Computed by the drive; writes fail with 0x0E.
    ReadOnly,
}

/// The values a write may take; anything else fails with 0x09 (invalid attribute value).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Check {
    /// Any value (REALs must be finite).
    Any,
    /// An integer in this inclusive range.
    Range(i32, i32),
    /// Zero or not: any non-zero value is stored as 1 ("Non 0 = enabled").
    Flag,
    /// A finite REAL above zero.
    Positive,
    /// A DataLink control word (table 12): reserved bits 16-29 zero, and when enabled the
    /// ID of a variable in this table.
    DataLink,
    /// A multicast address in 239.192.0.0/14, the range TCP/IP attribute 9 accepts.
    MulticastGroup,
}

/// One row of the table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Variable {
    /// Variable ID (class 0x64 instance).
    pub id: u16,
    /// Native format.
    pub format: Format,
    /// Network access.
    pub access: Access,
    /// True if the variable has an EPM (non-volatile) copy.
    pub epm: bool,
    /// Power-up value when the EPM holds none, as raw bits of the native format.
    pub default: u32,
    /// Accepted values.
    pub check: Check,
}

/// A value as it arrives: the 4 bytes of an integer, or a REAL.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    /// 32 bits of integer, read as signed or unsigned per the variable's format.
    Integer(u32),
    /// A REAL.
    Real(f32),
}

const fn var(id: u16, format: Format, access: Access, epm: bool, default: u32) -> Variable {
    Variable {
        id,
        format,
        access,
        epm,
        default,
        check: Check::Any,
    }
}

const fn checked(v: Variable, check: Check) -> Variable {
    Variable { check, ..v }
}

const fn real(v: f32) -> u32 {
    v.to_bits()
}

use Access::{ReadOnly as RO, ReadWrite as RW};
use Format::{Int, Real, Word};

/// Number of user variables, V0-V31.
const USER: usize = 32;
/// Number of DataLink control words, 4 in and 4 out.
const LINKS: usize = 8;

/// The variables below V0, in ID order.
const HEAD: [Variable; 14] = [
    checked(
        var(id::ENABLE_SWITCH_TYPE, Int, RW, true, 0),
        Check::Range(0, 1),
    ),
    checked(
        var(id::CURRENT_LIMIT, Real, RW, true, real(4.0)),
        Check::Positive,
    ),
    checked(var(id::DRIVE_MODE, Int, RW, true, 0), Check::Range(0, 2)),
    checked(
        var(id::REFERENCE_SOURCE, Int, RW, true, 0),
        Check::Range(0, 1),
    ),
    checked(var(id::ENABLE, Int, RW, false, 0), Check::Flag),
    var(id::STATUS_ALIAS, Word, RO, false, 0),
    var(id::STATUS, Word, RO, false, 0),
    var(id::INPUTS, Word, RO, false, 0),
    checked(var(id::ENABLE_ACCEL_DECEL, Int, RW, true, 0), Check::Flag),
    checked(
        var(id::ACCEL_LIMIT, Real, RW, true, real(100.0)),
        Check::Positive,
    ),
    checked(
        var(id::DECEL_LIMIT, Real, RW, true, real(100.0)),
        Check::Positive,
    ),
    var(id::EXSTATUS, Word, RO, false, 0),
    var(id::MOVEP, Real, RW, false, 0),
    var(id::MOVED, Real, RW, false, 0),
];

/// The variables between V31 and the DataLinks, in ID order.
const MIDDLE: [Variable; 8] = [
    var(id::REFERENCE, Real, RW, false, 0),
    var(id::MOVEDS, Real, RW, false, 0),
    var(id::MOVEPS, Real, RW, false, 0),
    var(id::PHASE_CURRENT, Real, RO, false, 0),
    var(id::REGISTERED_POSITION, Real, RO, false, 0),
    var(id::ACTUAL_POSITION, Real, RO, false, 0),
    var(id::POSITION_ERROR, Real, RO, false, 0),
    var(id::ACTUAL_VELOCITY, Real, RO, false, 0),
];

/// The variables after the DataLinks, in ID order.
const TAIL: [Variable; 3] = [
    var(id::CIP_HEARTBEAT, Word, RW, false, 0),
    checked(
        var(id::MULTICAST_TTL, Int, RW, true, 1),
        Check::Range(1, 255),
    ),
    checked(
        var(id::MULTICAST_ADDRESS, Word, RW, true, DEFAULT_MULTICAST),
        Check::MulticastGroup,
    ),
];

/// Number of variables in [`TABLE`].
pub const COUNT: usize = HEAD.len() + USER + MIDDLE.len() + LINKS + TAIL.len();

/// The variable table, sorted by ID.
pub const TABLE: [Variable; COUNT] = build();

// Only evaluated for the `const` TABLE, so an out-of-range index or an overflow is a compile
// error, not a panic.
#[allow(clippy::indexing_slicing, clippy::arithmetic_side_effects)]
const fn build() -> [Variable; COUNT] {
    let mut t = [var(0, Int, RO, false, 0); COUNT];
    let mut i = 0;
    let mut n = 0;
    while i < HEAD.len() {
        t[n] = HEAD[i];
        n += 1;
        i += 1;
    }
    // V0-V31: REAL user variables with EPM copies (table 5).
    i = 0;
    while i < USER {
        t[n] = var(id::V0 + i as u16, Real, RW, true, 0);
        n += 1;
        i += 1;
    }
    i = 0;
    while i < MIDDLE.len() {
        t[n] = MIDDLE[i];
        n += 1;
        i += 1;
    }
    // DataLinks: enabled, REAL, linked to V0-V3 (in) and V4-V7 (out) by default (table 5).
    i = 0;
    while i < LINKS {
        let control = Link {
            enabled: true,
            real: true,
            id: id::V0 + i as u16,
        }
        .encode();
        t[n] = checked(
            var(id::LINK_A_IN + i as u16, Word, RW, true, control),
            Check::DataLink,
        );
        n += 1;
        i += 1;
    }
    i = 0;
    while i < TAIL.len() {
        t[n] = TAIL[i];
        n += 1;
        i += 1;
    }
    t
}

/// The index and row of variable `id`.
pub fn find(id: u16) -> Option<(usize, &'static Variable)> {
    let i = TABLE.binary_search_by_key(&id, |v| v.id).ok()?;
    TABLE.get(i).map(|v| (i, v))
}

/// Rounds to the nearest integer, halves away from zero, saturating at the `i64` range.
fn round(f: f32) -> i64 {
    let f = f64::from(f);
    if f >= 0.0 {
        (f + 0.5) as i64
    } else {
        (f - 0.5) as i64
    }
}

fn invalid() -> CipError {
    CipError::new(General::InvalidAttributeValue)
}

impl Variable {
    /// The value as attribute 0 gives it: 32 bits of integer.
    pub fn int_bits(&self, raw: u32) -> u32 {
        match self.format {
            Format::Int | Format::Word => raw,
            Format::Real => {
                round(f32::from_bits(raw)).clamp(i32::MIN.into(), i32::MAX.into()) as i32 as u32
            }
        }
    }

    /// The value as attribute 2 gives it: a REAL.
    pub fn real(&self, raw: u32) -> f32 {
        match self.format {
            Format::Int => raw as i32 as f32,
            Format::Word => raw as f32,
            Format::Real => f32::from_bits(raw),
        }
    }

    /// Refuses a write of a read-only variable, or of the EPM copy of a variable without
    /// one, with 0x0E (attribute not settable).
    pub fn writable(&self, epm: bool) -> CipResult {
        if self.access == Access::ReadOnly || (epm && !self.epm) {
            Err(General::AttributeNotSettable.into())
        } else {
            Ok(())
        }
    }

    /// Converts `value` to the native format and checks it: the raw bits to store.
    pub fn encode(&self, value: Value) -> CipResult<u32> {
        let raw = match (self.format, value) {
            (Format::Int | Format::Word, Value::Integer(bits)) => bits,
            (Format::Real, Value::Integer(bits)) => (bits as i32 as f32).to_bits(),
            (_, Value::Real(f)) if !f.is_finite() => return Err(invalid()),
            (_, Value::Real(f)) if self.check == Check::Flag => u32::from(f != 0.0),
            (Format::Int, Value::Real(f)) => {
                round(f).clamp(i32::MIN.into(), i32::MAX.into()) as i32 as u32
            }
            (Format::Word, Value::Real(f)) => round(f).clamp(0, u32::MAX.into()) as u32,
            (Format::Real, Value::Real(f)) => f.to_bits(),
        };
        self.check(raw)
    }

    /// Applies [`Variable::check`] to native bits `raw`.
    fn check(&self, raw: u32) -> CipResult<u32> {
        let ok = match self.check {
            Check::Any => self.format != Format::Real || f32::from_bits(raw).is_finite(),
            Check::Range(lo, hi) => (lo..=hi).contains(&(raw as i32)),
            Check::Flag => return Ok(u32::from(raw != 0)),
            Check::Positive => {
                let f = f32::from_bits(raw);
                f.is_finite() && f > 0.0
            }
            Check::DataLink => {
                let link = Link::decode(raw);
                raw & Link::RESERVED == 0 && (!link.enabled || find(link.id).is_some())
            }
            Check::MulticastGroup => raw & 0xFFFC_0000 == 0xEFC0_0000,
        };
        if ok {
            Ok(raw)
        } else {
            Err(invalid())
        }
    }
}

/// The RAM copy of every variable, as raw bits of its native format, and whether any
/// changed since [`Variables::take_changed`] was last asked.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Variables {
    ram: [u32; COUNT],
    changed: bool,
}

impl Variables {
    /// The values at power-up: the EPM copy (`epm` of a variable's ID) where it holds one,
    /// else the default.
    pub fn power_up(epm: impl Fn(u16) -> Option<u32>) -> Self {
        let mut ram = [0; COUNT];
        for (slot, v) in ram.iter_mut().zip(TABLE.iter()) {
            *slot = if v.epm { epm(v.id) } else { None }.unwrap_or(v.default);
        }
        Variables { ram, changed: true }
    }

    /// True if a value changed since the last call.
    pub fn take_changed(&mut self) -> bool {
        core::mem::take(&mut self.changed)
    }

    /// Raw bits of variable `id` (0 if unknown).
    pub fn raw(&self, id: u16) -> u32 {
        find(id)
            .and_then(|(i, _)| self.ram.get(i).copied())
            .unwrap_or(0)
    }

    /// Variable `id` as a REAL (0 if unknown).
    pub fn real(&self, id: u16) -> f32 {
        find(id).map_or(0.0, |(_, v)| v.real(self.raw(id)))
    }

    /// Stores raw bits for variable `id` (ignored if unknown); no checks.
    pub fn set(&mut self, id: u16, raw: u32) {
        if let Some(slot) = find(id).and_then(|(i, _)| self.ram.get_mut(i)) {
            self.changed |= *slot != raw;
            *slot = raw;
        }
    }

    /// Stores a REAL for variable `id` in its native format; no checks.
    pub fn set_real(&mut self, id: u16, f: f32) {
        if let Some((_, v)) = find(id) {
            self.set(id, v.encode(Value::Real(f)).unwrap_or(0));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::storage::EpmCopy;
    use super::*;

    #[test]
    fn table_is_sorted_and_names_every_variable_of_the_manual() {
        assert!(TABLE.windows(2).all(|w| w[0].id < w[1].id));
        let named = [
            29, 30, 34, 37, 52, 53, 54, 65, 75, 76, 77, 83, 92, 93, 139, 177, 178, 188, 213, 215,
            216, 260, 272, 273, 275,
        ];
        for id in named.into_iter().chain(100..=131).chain(261..=268) {
            assert!(find(id).is_some(), "variable {id} missing");
        }
        assert_eq!(TABLE.len(), named.len() + 32 + 8);
    }

    #[test]
    fn integer_and_real_conversions() {
        let (_, v0) = find(id::V0).unwrap();
        let raw = v0.encode(Value::Real(2.5)).unwrap();
        assert_eq!(v0.real(raw), 2.5);
        assert_eq!(v0.int_bits(raw), 3);
        assert_eq!(
            v0.int_bits(v0.encode(Value::Real(-2.5)).unwrap()) as i32,
            -3
        );
        assert_eq!(v0.int_bits(v0.encode(Value::Real(1.4999)).unwrap()), 1);
        let raw = v0.encode(Value::Integer(-7i32 as u32)).unwrap();
        assert_eq!(v0.real(raw), -7.0);
        assert_eq!(
            v0.int_bits(v0.encode(Value::Real(1e20)).unwrap()),
            i32::MAX as u32
        );

        let (_, mode) = find(id::DRIVE_MODE).unwrap();
        assert_eq!(mode.encode(Value::Real(1.6)), Ok(2));
        assert_eq!(mode.real(2), 2.0);
        let (_, status) = find(id::STATUS).unwrap();
        assert_eq!(status.real(0x8000_0000), 2_147_483_648.0);
    }

    #[test]
    fn checks_reject_bad_values() {
        let bad = Err(invalid());
        let (_, mode) = find(id::DRIVE_MODE).unwrap();
        assert_eq!(mode.encode(Value::Integer(3)), bad);
        assert_eq!(mode.encode(Value::Integer(-1i32 as u32)), bad);
        let (_, accel) = find(id::ACCEL_LIMIT).unwrap();
        assert_eq!(accel.encode(Value::Real(0.0)), bad);
        assert_eq!(accel.encode(Value::Real(f32::NAN)), bad);
        assert_eq!(accel.encode(Value::Integer(1000)), Ok(1000.0f32.to_bits()));
        let (_, enable) = find(id::ENABLE).unwrap();
        assert_eq!(enable.encode(Value::Real(0.25)), Ok(1));
        assert_eq!(enable.encode(Value::Integer(7)), Ok(1));
        assert_eq!(enable.encode(Value::Real(0.0)), Ok(0));
        let (_, ttl) = find(id::MULTICAST_TTL).unwrap();
        assert_eq!(ttl.encode(Value::Integer(0)), bad);
        assert_eq!(ttl.encode(Value::Integer(255)), Ok(255));
        let (_, mcast) = find(id::MULTICAST_ADDRESS).unwrap();
        assert_eq!(mcast.encode(Value::Integer(0xE000_0001)), bad);
        assert_eq!(mcast.encode(Value::Integer(0xEFC1_0203)), Ok(0xEFC1_0203));
        let (_, link) = find(id::LINK_A_IN).unwrap();
        assert_eq!(link.encode(Value::Integer(0xC000_00BC)), Ok(0xC000_00BC));
        assert_eq!(
            link.encode(Value::Integer(0xC001_00BC)),
            bad,
            "reserved bit"
        );
        assert_eq!(
            link.encode(Value::Integer(0x8000_0063)),
            bad,
            "unknown variable 99"
        );
        assert_eq!(
            link.encode(Value::Integer(0x0000_0063)),
            Ok(0x63),
            "disabled"
        );
    }

    #[test]
    fn power_up_takes_the_epm_copy_else_the_default() {
        let mut epm = EpmCopy::new();
        epm.store(id::V0, 5.5f32.to_bits()).unwrap();
        let vars = Variables::power_up(|id| epm.value(id));
        assert_eq!(vars.real(id::V0), 5.5);
        assert_eq!(vars.raw(id::ENABLE), 0);
        assert_eq!(vars.raw(id::MULTICAST_ADDRESS), DEFAULT_MULTICAST);
        assert_eq!(vars.raw(id::LINK_A_IN), 0xC000_0064);
        assert_eq!(vars.raw(id::LINK_A_OUT + 3), 0xC000_006B);
        assert_eq!(vars.real(id::ACCEL_LIMIT), 100.0);
    }
}
