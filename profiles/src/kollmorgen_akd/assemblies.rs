//! The three assemblies (manual p.10-11) and the byte layouts of the command (O->T) and
//! response (T->O) assemblies: the command as a view whose getters cannot panic; the
//! response is encoded from the drive's state every time the stack produces it
//! ([`super::response::encode`]).
//!
//! Every multi-byte field is least significant byte first (p.11, p.14).

use enip_stack::{AssemblyInfo, AssemblyRole};

use super::maps::SLOTS;

/// Configuration assembly: 0 bytes (p.11).
pub const CONFIG: u16 = 100;
/// Command assembly, O->T with the run/idle header: the instance is on a page break no
/// copy shows; 101 (\[R\] item 1), next to 100 and 102.
pub const COMMAND: u16 = 101;
/// Response assembly, T->O without header (p.10).
pub const RESPONSE: u16 = 102;
/// Both I/O assemblies are 64 bytes.
pub const SIZE: usize = 64;
/// Bytes of the dynamic map (36-63): a DINT per slot of the map lists.
pub const DYNAMIC_MAP_LEN: usize = 4 * SLOTS;
/// First byte of the dynamic map in both I/O assemblies.
pub const DYNAMIC_MAP_START: usize = 36;

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

    /// True for a command type this edition defines (the ones above).
    pub const fn is_defined(kind: u8) -> bool {
        matches!(
            kind,
            TARGET_POSITION
                | TARGET_VELOCITY
                | ACCELERATION
                | DECELERATION
                | TORQUE
                | POSITION_MOVE
                | JOG
                | SET_ATTRIBUTE
                | PARAMETER
        )
    }
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
    /// Custom map 1: the project's fixed map (see [`super::super::response::custom_map`]).
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
    pub fn dynamic_map(&self) -> [u8; DYNAMIC_MAP_LEN] {
        core::array::from_fn(|i| self.byte(i.saturating_add(DYNAMIC_MAP_START)))
    }
}
