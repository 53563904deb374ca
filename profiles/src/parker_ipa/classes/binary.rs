//! Class 0x65 service 0x34, Write Binary Command(s): the ACR binary host commands that
//! Table 7 marks compatible and whose formats the *ACR Programmer's Guide* ("Binary Host
//! Interface") gives, executed on the simulated parameters:
//!
//! - Set Long `00 89 iL iH v0..v3`: P(i) = the long v (converted to P's type);
//! - Set IEEE `00 8B iL iH f0..f3`: P(i) = the float f (converted);
//! - Parameter Mask `00 95 iL iH n0..n3 o0..o3`: P(i) = (P AND NOT n) OR o, on a long
//!   parameter only;
//! - SET `1C bL bH` and CLR `1D bL bH`: bit b of the flags (P4096 + b / 32, bit b % 32).
//!
//! Indexes and values are sent low byte first. One request may carry several commands back
//! to back. Every command is checked before any runs: a command Table 7 marks incompatible,
//! Binary Move, FOV and ROV (compatible, not simulated) and unknown headers get Table 8's
//! 0x08 (case 1, not implemented); a packet that ends inside a command 0x13; a parameter or
//! flag that does not exist, or a mask on a float, 0x20. A refused request changes nothing.

use enip_stack::cip::{CipError, CipResult, General};

use super::super::memory::Memory;
use super::super::params::{self, Kind, Value, FLAGS_COUNT, FLAGS_FIRST};

/// Header of the parameter access packets (byte 1 is the packet ID).
const PARAMETER_ACCESS: u8 = 0x00;
/// Packet ID: Set Long.
const SET_LONG: u8 = 0x89;
/// Packet ID: Set IEEE.
const SET_IEEE: u8 = 0x8B;
/// Packet ID: Parameter Mask.
const PARAMETER_MASK: u8 = 0x95;
/// Header: SET a bit.
const SET_BIT: u8 = 0x1C;
/// Header: CLR a bit.
const CLR_BIT: u8 = 0x1D;
/// Bits in the flag parameters.
const FLAG_BITS: u32 = FLAGS_COUNT as u32 * 32;

/// One binary command, decoded.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Command {
    /// P(index) = value.
    Set(u32, Value),
    /// P(index) = (P AND NOT nand) OR or.
    Mask(u32, i32, i32),
    /// Flag bit (index) set (true) or cleared.
    Bit(u32, bool),
}

fn err(g: General) -> CipError {
    CipError::new(g)
}

fn word(b: [u8; 2]) -> u32 {
    u32::from(u16::from_le_bytes(b))
}

/// Decodes the command at the start of `data`; returns it and the rest.
fn next(data: &[u8]) -> CipResult<(Command, &[u8])> {
    let short = || err(General::NotEnoughData);
    match data {
        [PARAMETER_ACCESS, id, rest @ ..] => {
            let size = match *id {
                SET_LONG | SET_IEEE => 6,
                PARAMETER_MASK => 10,
                _ => return Err(General::ServiceNotSupported.into()),
            };
            let (body, rest) = rest.split_at_checked(size).ok_or_else(short)?;
            let long = |at: usize| -> [u8; 4] {
                let mut b = [0; 4];
                b.iter_mut()
                    .zip(body.iter().skip(at))
                    .for_each(|(d, s)| *d = *s);
                b
            };
            let index = match body {
                [l, h, ..] => word([*l, *h]),
                _ => return Err(short()),
            };
            let command = match *id {
                SET_LONG => Command::Set(index, Value::Long(i32::from_le_bytes(long(2)))),
                SET_IEEE => Command::Set(index, Value::Float(f32::from_le_bytes(long(2)))),
                _ => Command::Mask(
                    index,
                    i32::from_le_bytes(long(2)),
                    i32::from_le_bytes(long(6)),
                ),
            };
            Ok((command, rest))
        }
        [header @ (SET_BIT | CLR_BIT), rest @ ..] => match rest {
            [l, h, rest @ ..] => Ok((Command::Bit(word([*l, *h]), *header == SET_BIT), rest)),
            _ => Err(short()),
        },
        _ => Err(General::ServiceNotSupported.into()),
    }
}

/// 0x20 unless `command` can run on the simulated parameters.
fn check(command: Command) -> CipResult {
    let ok = match command {
        Command::Set(p, _) => params::kind(p).is_some(),
        Command::Mask(p, _, _) => params::kind(p) == Some(Kind::Long),
        Command::Bit(b, _) => b < FLAG_BITS,
    };
    if ok {
        Ok(())
    } else {
        Err(err(General::InvalidParameter))
    }
}

/// Runs `command` (already checked).
fn apply(memory: &mut Memory, command: Command) {
    match command {
        Command::Set(p, value) => {
            memory.set(p, value);
        }
        Command::Mask(p, nand, or) => {
            let _ = memory.and_or(p, !nand, or);
        }
        Command::Bit(b, on) => {
            let p = FLAGS_FIRST.saturating_add(b / 32);
            let mask = 1i32 << (b % 32);
            let _ = if on {
                memory.and_or(p, -1, mask)
            } else {
                memory.and_or(p, !mask, 0)
            };
        }
    }
}

/// Checks every command of `data`, then runs them in order; nothing runs if one is refused.
pub fn execute(memory: &mut Memory, data: &[u8]) -> CipResult {
    if data.is_empty() {
        return Err(err(General::NotEnoughData));
    }
    let mut rest = data;
    while !rest.is_empty() {
        let (command, tail) = next(rest)?;
        check(command)?;
        rest = tail;
    }
    let mut rest = data;
    while let Ok((command, tail)) = next(rest) {
        apply(memory, command);
        rest = tail;
    }
    Ok(())
}
