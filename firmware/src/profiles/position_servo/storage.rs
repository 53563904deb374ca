//! EPM persistence: the non-volatile copy of the variables that have one (7.2).
//!
//! [`EpmStorage`] is what the profile needs from non-volatile memory; [`RamEpm`] keeps the
//! copy in RAM (host and QEMU boards: it survives an Identity Reset, not a restart). A flash
//! implementation for the Nucleo board can come later behind the same trait.

use super::variables::{self, COUNT};

/// Why a value could not be stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StorageError {
    /// The variable has no EPM copy.
    NoCopy,
    /// The medium failed to write (flash implementations).
    Write,
}

/// Non-volatile storage of variable values (raw bits of the native format), by variable ID.
pub trait EpmStorage {
    /// The stored value of variable `id`, if any.
    fn load(&self, id: u16) -> Option<u32>;
    /// Stores the value of variable `id`.
    fn store(&mut self, id: u16, raw: u32) -> Result<(), StorageError>;
    /// Forgets every stored value (factory defaults).
    fn clear(&mut self);
}

/// An [`EpmStorage`] in RAM: a slot for every variable of the table that has an EPM copy.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RamEpm {
    values: [u32; COUNT],
    stored: [bool; COUNT],
}

impl RamEpm {
    /// An empty store: every variable powers up with its default.
    pub const fn new() -> Self {
        RamEpm {
            values: [0; COUNT],
            stored: [false; COUNT],
        }
    }
}

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

    fn store(&mut self, id: u16, raw: u32) -> Result<(), StorageError> {
        let i = match variables::find(id) {
            Some((i, v)) if v.epm => i,
            _ => return Err(StorageError::NoCopy),
        };
        match (self.values.get_mut(i), self.stored.get_mut(i)) {
            (Some(value), Some(stored)) => {
                *value = raw;
                *stored = true;
                Ok(())
            }
            _ => Err(StorageError::NoCopy),
        }
    }

    fn clear(&mut self) {
        self.stored = [false; COUNT];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profiles::position_servo::variables::id;

    #[test]
    fn stores_overwrites_and_clears() {
        let mut epm = RamEpm::new();
        assert_eq!(epm.load(id::V0), None);
        epm.store(id::V0, 1).unwrap();
        epm.store(id::V0 + 1, 2).unwrap();
        epm.store(id::V0, 3).unwrap();
        assert_eq!((epm.load(id::V0), epm.load(id::V0 + 1)), (Some(3), Some(2)));
        epm.clear();
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
