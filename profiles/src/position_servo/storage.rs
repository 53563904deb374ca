//! EPM persistence: the non-volatile copy of the variables that have one (7.2).
//!
//! [`EpmStorage`] is what the profile needs from non-volatile memory; [`RamEpm`] keeps the
//! copy in RAM and, given the adapter's store ([`RamEpm::in_store`]), saves it there as one
//! record, so it survives a restart and a power cut during a save.

use enip_stack::nv::{key, SharedStore};

use super::variables::{self, COUNT};
use crate::nv_record::Record;

/// Why a value could not be stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StorageError {
    /// The variable has no EPM copy.
    NoCopy,
    /// The medium failed to write.
    Write,
}

/// Non-volatile storage of variable values (raw bits of the native format), by variable ID.
pub trait EpmStorage {
    /// The stored value of variable `id`, if any.
    fn load(&self, id: u16) -> Option<u32>;
    /// Stores the value of variable `id`.
    fn store(&mut self, id: u16, raw: u32) -> Result<(), StorageError>;
    /// Forgets every stored value (factory defaults).
    fn clear(&mut self) -> Result<(), StorageError>;
}

/// Bytes of the saved record: a stored flag (0 or 1) per variable, then every value.
const RECORD_BYTES: usize = COUNT * 5;
const _: () = assert!(
    RECORD_BYTES <= enip_stack::nv::PROFILE_RECORD_ROOM,
    "the EPM must fit in the store beside the TCP/IP settings"
);

/// An [`EpmStorage`] in RAM, a slot for every variable of the table that has an EPM copy,
/// saved to a store record when it has one.
#[derive(Debug, Clone)]
pub struct RamEpm {
    values: [u32; COUNT],
    stored: [bool; COUNT],
    record: Option<Record>,
}

impl RamEpm {
    /// An empty store: every variable powers up with its default.
    pub const fn new() -> Self {
        RamEpm {
            values: [0; COUNT],
            stored: [false; COUNT],
            record: None,
        }
    }

    /// The copy saved in `store` (none, or unreadable: empty), saved there from now on.
    pub fn in_store(store: SharedStore) -> Self {
        let record = Record::new(store, key::POSITION_SERVO_EPM);
        let mut epm = RamEpm::new();
        if let Some(bytes) = record.load::<RECORD_BYTES>() {
            let (flags, values) = bytes.split_at(COUNT);
            for (slot, &flag) in epm.stored.iter_mut().zip(flags) {
                *slot = flag == 1;
            }
            for (slot, raw) in epm.values.iter_mut().zip(values.chunks_exact(4)) {
                *slot = raw.try_into().map_or(0, u32::from_le_bytes);
            }
        }
        epm.record = Some(record);
        epm
    }

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
}

/// Two copies are equal when they hold the same values (where they are saved is not
/// compared).
impl PartialEq for RamEpm {
    fn eq(&self, other: &Self) -> bool {
        (self.values, self.stored) == (other.values, other.stored)
    }
}

impl Eq for RamEpm {}

impl Default for RamEpm {
    fn default() -> Self {
        Self::new()
    }
}

impl EpmStorage for RamEpm {
    fn load(&self, id: u16) -> Option<u32> {
        let (i, _) = variables::find(id)?;
        match self.stored.get(i) {
            Some(true) => self.values.get(i).copied(),
            _ => None,
        }
    }

    /// Saves the whole copy with the new value; if the store refuses, nothing changes.
    fn store(&mut self, id: u16, raw: u32) -> Result<(), StorageError> {
        let i = match variables::find(id) {
            Some((i, v)) if v.epm => i,
            _ => return Err(StorageError::NoCopy),
        };
        let before = (self.values, self.stored);
        match (self.values.get_mut(i), self.stored.get_mut(i)) {
            (Some(value), Some(stored)) => {
                *value = raw;
                *stored = true;
            }
            _ => return Err(StorageError::NoCopy),
        }
        if let Some(record) = self.record {
            if record.save(&self.encode()).is_err() {
                (self.values, self.stored) = before;
                return Err(StorageError::Write);
            }
        }
        Ok(())
    }

    fn clear(&mut self) -> Result<(), StorageError> {
        if let Some(record) = self.record {
            record.clear().map_err(|_| StorageError::Write)?;
        }
        self.stored = [false; COUNT];
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::position_servo::variables::id;

    #[test]
    fn stores_overwrites_and_clears() {
        let mut epm = RamEpm::new();
        assert_eq!(epm.load(id::V0), None);
        epm.store(id::V0, 1).unwrap();
        epm.store(id::V0 + 1, 2).unwrap();
        epm.store(id::V0, 3).unwrap();
        assert_eq!((epm.load(id::V0), epm.load(id::V0 + 1)), (Some(3), Some(2)));
        epm.clear().unwrap();
        assert_eq!(epm.load(id::V0), None);
    }

    #[test]
    fn holds_every_epm_variable_and_refuses_the_others() {
        let mut epm = RamEpm::new();
        for v in variables::TABLE.iter().filter(|v| v.epm) {
            epm.store(v.id, u32::from(v.id)).unwrap();
        }
        for v in variables::TABLE.iter().filter(|v| v.epm) {
            assert_eq!(epm.load(v.id), Some(u32::from(v.id)));
        }
        assert_eq!(epm.store(id::ENABLE, 1), Err(StorageError::NoCopy));
        assert_eq!(epm.store(999, 1), Err(StorageError::NoCopy));
    }
}
