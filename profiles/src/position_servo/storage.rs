//! EPM persistence: the non-volatile copy of the variables that have one (7.2).
//!
//! [`Epm`] is the copy; [`EpmCopy`] keeps it in RAM and, given the adapter's store
//! ([`EpmCopy::in_store`]), saves it there as one record ([`crate::storage`]), so it
//! survives a restart and a power cut during a save.

use enip_stack::cip::{CipResult, General};

use super::params::{self, COUNT};
use crate::storage::{key, Record, Saved};

/// Bytes of the saved record: a stored flag (0 or 1) per variable, then every value.
const RECORD_BYTES: usize = COUNT * 5;

/// The EPM copy: a slot for every variable of the table (raw bits of its native format),
/// and whether it holds a value.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Epm {
    values: [u32; COUNT],
    stored: [bool; COUNT],
}

impl Epm {
    /// An empty copy: every variable powers up with its default.
    pub const fn new() -> Self {
        Epm {
            values: [0; COUNT],
            stored: [false; COUNT],
        }
    }

    /// The stored value of variable `id`, if any.
    pub fn get(&self, id: u16) -> Option<u32> {
        let (i, _) = params::find(id)?;
        match self.stored.get(i) {
            Some(true) => self.values.get(i).copied(),
            _ => None,
        }
    }

    /// Stores the value of variable `id`; false if it has no EPM copy.
    fn set(&mut self, id: u16, raw: u32) -> bool {
        let i = match params::find(id) {
            Some((i, v)) if v.epm => i,
            _ => return false,
        };
        match (self.values.get_mut(i), self.stored.get_mut(i)) {
            (Some(value), Some(stored)) => {
                *value = raw;
                *stored = true;
                true
            }
            _ => false,
        }
    }
}

impl Default for Epm {
    fn default() -> Self {
        Self::new()
    }
}

impl Record<RECORD_BYTES> for Epm {
    const KEY: u16 = key::POSITION_SERVO_EPM;
    fn encode(&self) -> [u8; RECORD_BYTES] {
        let mut bytes = [0u8; RECORD_BYTES];
        let (flags, values) = bytes.split_at_mut(COUNT);
        for (flag, &stored) in flags.iter_mut().zip(&self.stored) {
            *flag = u8::from(stored);
        }
        for (raw, value) in values.chunks_exact_mut(4).zip(&self.values) {
            raw.copy_from_slice(&value.to_le_bytes());
        }
        bytes
    }
    fn decode(bytes: &[u8; RECORD_BYTES]) -> Self {
        let mut epm = Epm::new();
        let (flags, values) = bytes.split_at(COUNT);
        for (slot, &flag) in epm.stored.iter_mut().zip(flags) {
            *slot = flag == 1;
        }
        for (slot, raw) in epm.values.iter_mut().zip(values.chunks_exact(4)) {
            *slot = raw.try_into().map_or(0, u32::from_le_bytes);
        }
        epm
    }
}

/// The EPM copy in RAM and, given the adapter's store, in a record there.
pub type EpmCopy = Saved<Epm, RECORD_BYTES>;

impl EpmCopy {
    /// The stored value of variable `id`, if any.
    pub fn value(&self, id: u16) -> Option<u32> {
        self.load()?.get(id)
    }

    /// Stores the value of variable `id`, saving the whole copy with it; if the store
    /// refuses (0x19), nothing changes. A variable without an EPM copy: 0x02.
    pub fn store(&mut self, id: u16, raw: u32) -> CipResult {
        let mut epm = self.load().cloned().unwrap_or_default();
        if !epm.set(id, raw) {
            return Err(General::ResourceUnavailable.into());
        }
        self.save(epm)
            .map_err(|_| General::StoreOperationFailure.into())
    }
}

#[cfg(test)]
mod tests {
    use super::params::id;
    use super::*;

    #[test]
    fn stores_overwrites_and_clears() {
        let mut epm = EpmCopy::new();
        assert_eq!(epm.value(id::V0), None);
        epm.store(id::V0, 1).unwrap();
        epm.store(id::V0 + 1, 2).unwrap();
        epm.store(id::V0, 3).unwrap();
        assert_eq!(
            (epm.value(id::V0), epm.value(id::V0 + 1)),
            (Some(3), Some(2))
        );
        epm.clear().unwrap();
        assert_eq!(epm.value(id::V0), None);
    }

    #[test]
    fn holds_every_epm_variable_and_refuses_the_others() {
        let mut epm = EpmCopy::new();
        for v in params::TABLE.iter().filter(|v| v.epm) {
            epm.store(v.id, u32::from(v.id)).unwrap();
        }
        for v in params::TABLE.iter().filter(|v| v.epm) {
            assert_eq!(epm.value(v.id), Some(u32::from(v.id)));
        }
        let no_copy = Err(General::ResourceUnavailable.into());
        assert_eq!(epm.store(id::ENABLE, 1), no_copy);
        assert_eq!(epm.store(999, 1), no_copy);
    }
}
