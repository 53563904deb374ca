//! The Class 1 connection points (p.11, "Adding IPA to RSLogix"): input 101 (produced,
//! T->O), output 102 (consumed, O->T, with the 32-bit run/idle header of the Logix generic
//! module, R3.3) and configuration 3 (no data, R3.7).
//!
//! Sizes: the assemblies are 400 bytes each way (p.11's "size 100" DINTs, Table 4's 3200
//! bits); a connection may carry from the configured groups' size up to 400 (R5.6,
//! `ParkerIpa::accepts_connection_size`). The groups fill the data from byte 0 in ascending
//! group order; produced bytes after them are zero, consumed bytes after them are ignored
//! (R5.4, R5.6).

use enip_stack::cip::CipResult;
use enip_stack::{AssemblyInfo, AssemblyRole};

use super::ioconfig::{Direction, Layout, MAX_LONGS};
use super::memory::Memory;
use super::params::Value;

/// Input assembly (IPA sends to PLC).
pub const INPUT: u16 = 101;
/// Output assembly (IPA reads from PLC).
pub const OUTPUT: u16 = 102;
/// Configuration assembly (no data).
pub const CONFIG: u16 = 3;
/// Data bytes each way: 100 DINTs (p.11, Table 4).
pub const DATA_SIZE: u16 = (MAX_LONGS * 4) as u16;

/// The connection points.
pub const INFOS: [AssemblyInfo; 3] = [
    AssemblyInfo {
        instance: INPUT,
        role: AssemblyRole::Input,
        size: DATA_SIZE,
        run_idle_header: false,
    },
    AssemblyInfo {
        instance: OUTPUT,
        role: AssemblyRole::Output,
        size: DATA_SIZE,
        run_idle_header: true,
    },
    AssemblyInfo {
        instance: CONFIG,
        role: AssemblyRole::Config,
        size: 0,
        run_idle_header: false,
    },
];

/// Writes the parameters of `layout` going `direction` into `out` (4 bytes each, in the
/// group's wire type), zero after them; returns `out.len()`. Straight into the buffer the
/// stack lends (the T->O datagram itself when producing).
pub fn image(memory: &Memory, layout: &Layout, direction: Direction, out: &mut [u8]) -> usize {
    out.fill(0);
    for ((p, wire), chunk) in layout.parameters(direction).zip(out.chunks_exact_mut(4)) {
        let value = memory.get(p).unwrap_or(Value::Long(0));
        chunk.copy_from_slice(&value.to_kind(wire).to_le_bytes());
    }
    out.len()
}

/// Applies consumed data: each 4-byte field, read in its group's wire type, goes to its
/// parameter converted to the parameter's type.
pub fn consume(memory: &mut Memory, layout: &Layout, data: &[u8]) -> CipResult {
    for ((p, wire), chunk) in layout
        .parameters(Direction::Consume)
        .zip(data.chunks_exact(4))
    {
        if let Ok(bytes) = <[u8; 4]>::try_from(chunk) {
            memory.set(p, Value::from_le_bytes(wire, bytes));
        }
    }
    Ok(())
}
