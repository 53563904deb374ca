//! The P parameters as requests see them: the stored ones ([`Store`]) and the computed CIP
//! status ones ([`CipStatus`], P37424-P37439), read and written by number, one at a time, in
//! blocks or through AND and OR masks. Classes 0x64 and 0x65, the tag services and the
//! assemblies take this, not the whole controller.

use enip_stack::cip::{CipError, CipResult, General};
use enip_stack::wire::Writer;

use super::params::{self, Kind, Slot, Store, Value};
use super::status::CipStatus;

/// The parameters and the CIP status behind the status parameters.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Memory {
    /// The stored parameters.
    pub store: Store,
    /// The CIP status behind P37424-P37439.
    pub status: CipStatus,
    /// A parameter was written since [`Memory::take_written`] was last asked.
    written: bool,
}

impl Memory {
    /// The parameters at power-up (Program1 has loaded the AOI I/O configuration, p.9).
    pub fn power_up() -> Self {
        Memory {
            store: Store::power_up(),
            status: CipStatus::default(),
            written: false,
        }
    }

    /// The value of parameter `p` in its native type, or `None` if it does not exist.
    pub fn get(&self, p: u32) -> Option<Value> {
        let slot = Slot::of(p)?;
        match slot {
            Slot::Status(i) => Some(Value::Long(
                self.status.param(i, self.store.groups_in_use()),
            )),
            _ => self.store.load(slot),
        }
    }

    /// Writes `value` to parameter `p`, converted to its type; `None` if it does not exist.
    /// Computed status parameters ignore the write (R7.2).
    pub fn set(&mut self, p: u32, value: Value) -> Option<()> {
        let slot = Slot::of(p)?;
        self.store.store(slot, value);
        self.written = true;
        Some(())
    }

    /// True if a parameter was written since the last call.
    pub fn take_written(&mut self) -> bool {
        core::mem::take(&mut self.written)
    }

    /// 0x05 unless every parameter of P(first)..P(first+n-1) exists.
    pub fn check(&self, first: u32, n: usize) -> CipResult {
        let all = (0..n as u32).all(|k| first.checked_add(k).and_then(params::kind).is_some());
        if all {
            Ok(())
        } else {
            Err(CipError::new(General::PathDestinationUnknown))
        }
    }

    /// Writes `n` values from P(first) as `kind` into the reply (0x05 if one is missing).
    pub fn read_block(&self, first: u32, n: usize, kind: Kind, w: &mut Writer<'_>) -> CipResult {
        self.check(first, n)?;
        for k in 0..n as u32 {
            let value = self
                .get(first.saturating_add(k))
                .ok_or(CipError::new(General::PathDestinationUnknown))?;
            put(w, value, kind)?;
        }
        Ok(())
    }

    /// Writes the 4-byte values of `data` (as `kind`) to P(first)..., all or nothing.
    pub fn write_block(&mut self, first: u32, data: &[u8], kind: Kind) -> CipResult {
        self.check(first, data.len() / 4)?;
        for (k, chunk) in data.chunks_exact(4).enumerate() {
            if let Ok(bytes) = <[u8; 4]>::try_from(chunk) {
                self.set(
                    first.saturating_add(k as u32),
                    Value::from_le_bytes(kind, bytes),
                );
            }
        }
        Ok(())
    }

    /// P = (P AND `and`) OR `or`, on the value as a long, stored back in P's type.
    pub fn and_or(&mut self, p: u32, and: i32, or: i32) -> CipResult {
        let old = self
            .get(p)
            .ok_or(CipError::new(General::PathDestinationUnknown))?;
        self.set(p, Value::Long((old.as_long() & and) | or));
        Ok(())
    }
}

/// Encodes `value` as `kind` into the reply.
pub fn put(w: &mut Writer<'_>, value: Value, kind: Kind) -> CipResult {
    w.bytes(&value.to_kind(kind).to_le_bytes())?;
    Ok(())
}
