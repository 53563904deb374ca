//! The assembly instances (5.5, tables 14-21) as word layouts; sizes follow from them.
//!
//! Inputs carry no header (5.2.2); outputs carry the 4-byte run/idle header (5.2.3), which
//! the stack strips. 103 is the empty configuration assembly. The manual names no heartbeat
//! connection points for input-only and listen-only connections; they are
//! [`INPUT_ONLY_HEARTBEAT`] and [`LISTEN_ONLY_HEARTBEAT`] here, outside the manual's range
//! so no assembly of the manual changes meaning.

use enip_stack::cip::{CipError, CipResult, General};
use enip_stack::{AssemblyInfo, AssemblyRole};

use super::datalinks::{self, LINKS};
use super::device::Servo;
use super::params::{self, id, Value, Variables};

/// 103: dummy assembly required for implicit configuration; no data.
pub const CONFIG: u16 = 103;
/// 104: status and I/O (input).
pub const STATUS_IO: u16 = 104;
/// 105: universal monitor (input).
pub const MONITOR: u16 = 105;
/// 106: basic control (output).
pub const BASIC_CONTROL: u16 = 106;
/// 108: extended control (output).
pub const EXTENDED_CONTROL: u16 = 108;
/// 109: "keep alive" (output): the CIP heartbeat.
pub const KEEP_ALIVE: u16 = 109;
/// O->T point of input-only connections (no data; not in the manual).
pub const INPUT_ONLY_HEARTBEAT: u16 = 198;
/// O->T point of listen-only connections (no data; not in the manual).
pub const LISTEN_ONLY_HEARTBEAT: u16 = 199;

/// How one 32-bit word of an assembly is encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Word {
    /// STATUS2 (tables 17, 18).
    Status2,
    /// A variable as U32.
    U32(u16),
    /// A variable as F32.
    F32(u16),
    /// A DataLink: the variable its control word (this variable ID) points at.
    Link(u16),
}

/// Table 15.
pub const STATUS_IO_WORDS: [Word; 2] = [Word::Status2, Word::U32(id::INPUTS)];
/// Table 19.
pub const MONITOR_WORDS: [Word; 9] = [
    Word::F32(id::ACTUAL_VELOCITY),
    Word::F32(id::ACTUAL_POSITION),
    Word::F32(id::POSITION_ERROR),
    Word::F32(id::PHASE_CURRENT),
    Word::F32(id::REGISTERED_POSITION),
    Word::Link(datalinks::input(0)),
    Word::Link(datalinks::input(1)),
    Word::Link(datalinks::input(2)),
    Word::Link(datalinks::input(3)),
];
/// Table 20.
pub const BASIC_CONTROL_WORDS: [Word; 2] = [Word::F32(id::ENABLE), Word::F32(id::REFERENCE)];
/// Table 21.
pub const EXTENDED_CONTROL_WORDS: [Word; 2 + LINKS] = [
    Word::F32(id::ENABLE),
    Word::F32(id::REFERENCE),
    Word::Link(datalinks::output(0)),
    Word::Link(datalinks::output(1)),
    Word::Link(datalinks::output(2)),
    Word::Link(datalinks::output(3)),
];
/// Table 16.
pub const KEEP_ALIVE_WORDS: [Word; 1] = [Word::U32(id::CIP_HEARTBEAT)];

/// An assembly instance: what the stack sees, and its layout.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Assembly {
    /// Instance, role, size and header.
    pub info: AssemblyInfo,
    /// Its words.
    pub words: &'static [Word],
}

const fn assembly(instance: u16, role: AssemblyRole, words: &'static [Word]) -> Assembly {
    Assembly {
        info: AssemblyInfo {
            instance,
            role,
            size: words.len().saturating_mul(4) as u16,
            run_idle_header: matches!(role, AssemblyRole::Output),
        },
        words,
    }
}

/// Every assembly instance (table 14 and the two heartbeat points).
pub const ASSEMBLIES: [Assembly; 8] = [
    assembly(CONFIG, AssemblyRole::Config, &[]),
    assembly(STATUS_IO, AssemblyRole::Input, &STATUS_IO_WORDS),
    assembly(MONITOR, AssemblyRole::Input, &MONITOR_WORDS),
    assembly(BASIC_CONTROL, AssemblyRole::Output, &BASIC_CONTROL_WORDS),
    assembly(
        EXTENDED_CONTROL,
        AssemblyRole::Output,
        &EXTENDED_CONTROL_WORDS,
    ),
    assembly(KEEP_ALIVE, AssemblyRole::Output, &KEEP_ALIVE_WORDS),
    assembly(INPUT_ONLY_HEARTBEAT, AssemblyRole::InputOnlyHeartbeat, &[]),
    assembly(
        LISTEN_ONLY_HEARTBEAT,
        AssemblyRole::ListenOnlyHeartbeat,
        &[],
    ),
];

/// [`ASSEMBLIES`] as the stack lists them.
pub const INFOS: [AssemblyInfo; ASSEMBLIES.len()] = {
    let mut out = [ASSEMBLIES[0].info; ASSEMBLIES.len()];
    let mut i = 0;
    while i < ASSEMBLIES.len() {
        // Const context, so no iterators; `i < ASSEMBLIES.len()`, the length of both arrays.
        #[allow(clippy::indexing_slicing)]
        {
            out[i] = ASSEMBLIES[i].info;
        }
        i += 1;
    }
    out
};

fn find(instance: u16) -> CipResult<&'static Assembly> {
    ASSEMBLIES
        .iter()
        .find(|a| a.info.instance == instance)
        .ok_or(CipError::new(General::PathDestinationUnknown))
}

/// STATUS2 (table 18) from STATUS (54) and EXSTATUS (83).
pub fn status2(status: u32, exstatus: u32) -> u32 {
    const MAP: [(u32, u32); 13] = [
        (0, 0),
        (1, 3),
        (2, 5),
        (3, 7),
        (4, 8),
        (5, 13),
        (6, 19),
        (7, 22),
        (8, 24),
        (9, 25),
        (10, 27),
        (11, 28),
        (12, 29),
    ];
    let from_status = MAP
        .iter()
        .filter(|&&(_, bit)| status & (1 << bit) != 0)
        .fold(0, |acc, &(to, _)| acc | 1 << to);
    let homing = [(13, 21), (14, 22)]
        .iter()
        .filter(|&&(_, bit)| exstatus & (1u32 << bit) != 0)
        .fold(0, |acc, &(to, _)| acc | 1u32 << to);
    from_status | homing
}

fn encode(vars: &Variables, word: Word) -> [u8; 4] {
    let var = |vid| params::find(vid).map(|(_, v)| (v, vars.raw(vid)));
    match word {
        Word::Status2 => status2(vars.raw(id::STATUS), vars.raw(id::EXSTATUS)).to_le_bytes(),
        Word::U32(vid) => var(vid).map_or(0, |(v, raw)| v.int_bits(raw)).to_le_bytes(),
        Word::F32(vid) => var(vid).map_or(0.0, |(v, raw)| v.real(raw)).to_le_bytes(),
        Word::Link(control) => datalinks::read(vars, control),
    }
}

/// Copies assembly `instance` into `out`; returns the length.
pub fn read(vars: &Variables, instance: u16, out: &mut [u8]) -> CipResult<usize> {
    let a = find(instance)?;
    let mut n = 0usize;
    for (chunk, word) in out.chunks_exact_mut(4).zip(a.words) {
        chunk.copy_from_slice(&encode(vars, *word));
        n = n.saturating_add(4);
    }
    Ok(n)
}

/// Applies output data for assembly `instance` (exactly its size), word by word; a word its
/// variable refuses changes nothing.
pub fn write(servo: &mut Servo, instance: u16, data: &[u8]) -> CipResult {
    let a = find(instance)?;
    match data.len().cmp(&usize::from(a.info.size)) {
        core::cmp::Ordering::Less => return Err(General::NotEnoughData.into()),
        core::cmp::Ordering::Greater => return Err(General::TooMuchData.into()),
        core::cmp::Ordering::Equal => {}
    }
    if !a.info.role.settable() {
        return Err(General::AttributeNotSettable.into());
    }
    for (chunk, word) in data.chunks_exact(4).zip(a.words) {
        let Ok(bytes) = <[u8; 4]>::try_from(chunk) else {
            continue;
        };
        // A refused word leaves its variable as it was, like refused O->T data.
        let _ = match *word {
            Word::U32(vid) => servo.write(vid, Value::Integer(u32::from_le_bytes(bytes)), None),
            Word::F32(vid) => servo.write(vid, Value::Real(f32::from_le_bytes(bytes)), None),
            Word::Link(control) => {
                datalinks::write(servo, control, bytes);
                Ok(())
            }
            Word::Status2 => Ok(()),
        };
    }
    Ok(())
}
