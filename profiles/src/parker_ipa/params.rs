//! The simulated ACR controller's P parameters: which exist, their native type (long or
//! float), their storage (one static table, no heap) and the conversion between the types.
//!
//! Map (digest section 11, \[KB\] Parker "User Variables"):
//! - P0-P4095: floats that exist only once dimensioned (`DIM`); the simulated controller
//!   boots with [`DIMENSIONED_FLOATS`] of them (0: P10 does not exist, as in example 2, p.5).
//! - P4096-P4607: longs, the flags (the manual writes P4100 and masks P4111).
//! - P12288-P14335: axis parameters, axis `a` at 12288 + 256a; indexes 0-15 long (0
//!   current position, 2 actual position), 16-255 float (16 PGAIN, 27-31 monitor, 60-63
//!   jog VEL/ACC/DEC/JRK, 82-87 scaling) \[R\].
//! - P37424-P37439: the CIP status parameters (computed, [`super::status`]); P37434 is the
//!   number of I/O groups in use, read and written.
//! - P37440-P37503: the I/O group configuration, longs.
//! - P38912-P39167: user longs; P39168-P39423: user floats.
//!
//! Conversion (R9.4): float to long truncates toward zero, saturates at the int32 limits,
//! NaN becomes 0 (Rust's `as`); long to float is the nearest float32.

/// A parameter value in one of the two ACR types.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    /// A 32-bit long (DINT).
    Long(i32),
    /// A float (REAL on the wire).
    Float(f32),
}

impl Value {
    /// The value as a long: floats truncate toward zero, saturate, NaN is 0 (R9.4).
    pub fn as_long(self) -> i32 {
        match self {
            Value::Long(l) => l,
            Value::Float(f) => f as i32,
        }
    }
    /// The value as a float: longs become the nearest float32.
    pub fn as_float(self) -> f32 {
        match self {
            Value::Long(l) => l as f32,
            Value::Float(f) => f,
        }
    }
    /// The value converted to `kind`.
    pub fn to_kind(self, kind: Kind) -> Value {
        match kind {
            Kind::Long => Value::Long(self.as_long()),
            Kind::Float => Value::Float(self.as_float()),
        }
    }
    /// The four little-endian bytes of the value in its own type.
    pub fn to_le_bytes(self) -> [u8; 4] {
        match self {
            Value::Long(l) => l.to_le_bytes(),
            Value::Float(f) => f.to_le_bytes(),
        }
    }
    /// Decodes four little-endian bytes as `kind`.
    pub fn from_le_bytes(kind: Kind, bytes: [u8; 4]) -> Value {
        match kind {
            Kind::Long => Value::Long(i32::from_le_bytes(bytes)),
            Kind::Float => Value::Float(f32::from_le_bytes(bytes)),
        }
    }
}

/// The native type of a parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// 32-bit long.
    Long,
    /// Float.
    Float,
}

/// Floats P0.. dimensioned at power-up (the manual's example 2 needs P10 not to exist).
pub const DIMENSIONED_FLOATS: usize = 0;
/// First flag parameter.
pub const FLAGS_FIRST: u32 = 4096;
/// Number of flag parameters (P4096-P4607).
pub const FLAGS_COUNT: usize = 512;
/// Axis 0's first parameter.
pub const AXIS_FIRST: u32 = 12288;
/// Parameters per axis.
pub const AXIS_STRIDE: u32 = 256;
/// Axes of the simulated controller.
pub const AXES: usize = 8;
/// Axis parameter indexes below this are longs, the others floats \[R\].
pub const AXIS_LONGS: u32 = 16;
/// First CIP status parameter (Table 2, p.5).
pub const STATUS_FIRST: u32 = 37424;
/// Number of CIP status parameters (P37424-P37439).
pub const STATUS_COUNT: usize = 16;
/// First I/O group configuration parameter (p.8).
pub const CONFIG_FIRST: u32 = 37440;
/// Number of I/O group configuration parameters (16 groups x 4, P37440-P37503).
pub const CONFIG_COUNT: usize = 64;
/// First user long \[KB\].
pub const USER_LONGS_FIRST: u32 = 38912;
/// Number of user longs (P38912-P39167).
pub const USER_LONGS_COUNT: usize = 256;
/// First user float \[KB\].
pub const USER_FLOATS_FIRST: u32 = 39168;
/// Number of user floats (P39168-P39423).
pub const USER_FLOATS_COUNT: usize = 256;
/// Every existing parameter (class 0x64 attribute 3).
pub const COUNT: usize = DIMENSIONED_FLOATS
    + FLAGS_COUNT
    + AXES * AXIS_STRIDE as usize
    + STATUS_COUNT
    + CONFIG_COUNT
    + USER_LONGS_COUNT
    + USER_FLOATS_COUNT;

/// Where a parameter lives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Slot {
    /// A dimensioned float P0.. (index).
    Dimensioned(usize),
    /// A flag long (index from P4096).
    Flag(usize),
    /// An axis parameter (index from P12288).
    Axis(usize),
    /// A CIP status parameter (index from P37424).
    Status(usize),
    /// An I/O group configuration parameter (index from P37440).
    Config(usize),
    /// A user long (index from P38912).
    UserLong(usize),
    /// A user float (index from P39168).
    UserFloat(usize),
}

impl Slot {
    /// The slot of parameter `p`, or `None` if it does not exist.
    pub fn of(p: u32) -> Option<Slot> {
        let within = |first: u32, count: usize| {
            p.checked_sub(first)
                .map(|i| i as usize)
                .filter(|&i| i < count)
        };
        if let Some(i) = within(0, DIMENSIONED_FLOATS) {
            return Some(Slot::Dimensioned(i));
        }
        if let Some(i) = within(FLAGS_FIRST, FLAGS_COUNT) {
            return Some(Slot::Flag(i));
        }
        if let Some(i) = within(AXIS_FIRST, AXES.saturating_mul(AXIS_STRIDE as usize)) {
            return Some(Slot::Axis(i));
        }
        if let Some(i) = within(STATUS_FIRST, STATUS_COUNT) {
            return Some(Slot::Status(i));
        }
        if let Some(i) = within(CONFIG_FIRST, CONFIG_COUNT) {
            return Some(Slot::Config(i));
        }
        if let Some(i) = within(USER_LONGS_FIRST, USER_LONGS_COUNT) {
            return Some(Slot::UserLong(i));
        }
        within(USER_FLOATS_FIRST, USER_FLOATS_COUNT).map(Slot::UserFloat)
    }

    /// The native type of the parameter in this slot.
    pub fn kind(self) -> Kind {
        match self {
            Slot::Dimensioned(_) | Slot::UserFloat(_) => Kind::Float,
            Slot::Axis(i) if (i as u32 % AXIS_STRIDE) >= AXIS_LONGS => Kind::Float,
            _ => Kind::Long,
        }
    }
}

/// The native type of parameter `p`, or `None` if it does not exist.
pub fn kind(p: u32) -> Option<Kind> {
    Slot::of(p).map(Slot::kind)
}

/// Axis parameter index of the current position (group 0 of the AOI layout).
pub const CURRENT_POSITION: u32 = 0;
/// Axis parameter index of the actual position (group 0x30 index 2, p.27).
pub const ACTUAL_POSITION: u32 = 2;
/// Axis parameter index of the jog velocity (P12348 for axis 0, Fig. 4).
pub const JOG_VEL: u32 = 60;

/// The AOI configuration of `_ConfigureEIP` (p.9-10): start, count, direction, type per
/// group; Program1 loads it at every power cycle, so the simulated controller boots with it.
pub const AOI_GROUPS: [[i32; 4]; 16] = [
    [12288, 8, 0, 1], // Group0 Current Position
    [4120, 1, 0, 1],  // Group1 Primary Axis Flags
    [4360, 1, 0, 1],  // Group2 QuanAxisFlags
    [4600, 1, 0, 1],  // Group3 QuinAxisFlags
    [4096, 8, 0, 1],  // Group4 InputsOutputsMisc
    [4392, 1, 0, 1],  // Group5 Drive Status1 Flags
    [4408, 1, 0, 1],  // Group6 Drive Status2 Flags
    [12315, 5, 0, 2], // Group7 Monitor Parameters
    [12370, 6, 0, 2], // Group8 Scaling
    [4128, 8, 0, 1],  // Group9 Program Flags
    [38912, 8, 0, 1], // Group10 User DINTs
    [4156, 4, 1, 1],  // Group11 User Flags-Control Words
    [12348, 4, 1, 2], // Group12 Jog Profile Parameters
    [39000, 8, 1, 1], // Group13 User DINTs
    [39200, 8, 1, 2], // Group14 User Reals
    [39208, 8, 1, 2], // Group15 User Reals
];

/// The stored parameters (everything but the computed status parameters), as raw 32-bit
/// images of their native type.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Store {
    dimensioned: [u32; DIMENSIONED_FLOATS],
    flags: [u32; FLAGS_COUNT],
    axes: [u32; AXES * AXIS_STRIDE as usize],
    config: [u32; CONFIG_COUNT],
    groups_in_use: u32,
    user_longs: [u32; USER_LONGS_COUNT],
    user_floats: [u32; USER_FLOATS_COUNT],
}

/// Axis 0's quaternary axis flags (axis `a` at P4360 + a, Fig. 7).
pub const QUATERNARY_FLAGS_FIRST: u32 = 4360;

/// Quaternary axis flags P4360-P4362 as Fig. 7 (p.26) shows them.
const QUATERNARY_FLAGS: [(u32, i32); 3] = [(4360, 1630535712), (4361, 1630535712), (4362, 5242880)];

impl Store {
    /// The power-up values: zeros, the flags of Fig. 7, and the AOI I/O configuration that
    /// Program1 "loads on each power cycle" (p.9).
    pub fn power_up() -> Self {
        let mut s = Store {
            dimensioned: [0; DIMENSIONED_FLOATS],
            flags: [0; FLAGS_COUNT],
            axes: [0; AXES * AXIS_STRIDE as usize],
            config: [0; CONFIG_COUNT],
            groups_in_use: 0,
            user_longs: [0; USER_LONGS_COUNT],
            user_floats: [0; USER_FLOATS_COUNT],
        };
        for (p, v) in QUATERNARY_FLAGS {
            if let Some(slot) = Slot::of(p) {
                s.store(slot, Value::Long(v));
            }
        }
        for (g, entry) in AOI_GROUPS.iter().enumerate() {
            for (k, v) in entry.iter().enumerate() {
                if let Some(c) = s.config.get_mut(g.saturating_mul(4).saturating_add(k)) {
                    *c = *v as u32;
                }
            }
        }
        s.groups_in_use = AOI_GROUPS.len() as u32;
        s
    }

    fn cell(&self, slot: Slot) -> Option<u32> {
        match slot {
            Slot::Dimensioned(i) => self.dimensioned.get(i).copied(),
            Slot::Flag(i) => self.flags.get(i).copied(),
            Slot::Axis(i) => self.axes.get(i).copied(),
            Slot::Status(i) if i == GROUPS_IN_USE_INDEX => Some(self.groups_in_use),
            Slot::Status(_) => None,
            Slot::Config(i) => self.config.get(i).copied(),
            Slot::UserLong(i) => self.user_longs.get(i).copied(),
            Slot::UserFloat(i) => self.user_floats.get(i).copied(),
        }
    }

    fn cell_mut(&mut self, slot: Slot) -> Option<&mut u32> {
        match slot {
            Slot::Dimensioned(i) => self.dimensioned.get_mut(i),
            Slot::Flag(i) => self.flags.get_mut(i),
            Slot::Axis(i) => self.axes.get_mut(i),
            Slot::Status(i) if i == GROUPS_IN_USE_INDEX => Some(&mut self.groups_in_use),
            Slot::Status(_) => None,
            Slot::Config(i) => self.config.get_mut(i),
            Slot::UserLong(i) => self.user_longs.get_mut(i),
            Slot::UserFloat(i) => self.user_floats.get_mut(i),
        }
    }

    /// The stored value of `slot` in its native type (`None` for the computed status
    /// parameters).
    pub fn load(&self, slot: Slot) -> Option<Value> {
        let raw = self.cell(slot)?;
        Some(match slot.kind() {
            Kind::Long => Value::Long(raw as i32),
            Kind::Float => Value::Float(f32::from_bits(raw)),
        })
    }

    /// Stores `value` in `slot`, converted to the slot's type; a computed status parameter
    /// ignores the write (R7.2: overwritten at the next update).
    pub fn store(&mut self, slot: Slot, value: Value) {
        let raw = match value.to_kind(slot.kind()) {
            Value::Long(l) => l as u32,
            Value::Float(f) => f.to_bits(),
        };
        if let Some(cell) = self.cell_mut(slot) {
            *cell = raw;
        }
    }

    /// P37434, the number of I/O groups in use.
    pub fn groups_in_use(&self) -> i32 {
        self.groups_in_use as i32
    }

    /// The 64 I/O configuration longs P37440-P37503.
    pub fn config(&self) -> [i32; CONFIG_COUNT] {
        self.config.map(|v| v as i32)
    }
}

/// Index of P37434 (groups in use) among the status parameters.
pub const GROUPS_IN_USE_INDEX: usize = 10;
