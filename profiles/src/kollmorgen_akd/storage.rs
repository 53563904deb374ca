//! The non-volatile copy of the parameters DRV.NVSAVE stores and a power-up loads: a small
//! trait, and [`RamNv`], kept in RAM and in a record of the adapter's store.

use enip_stack::nv::{key, SharedStore};

use super::params::TABLE;
use crate::nv_record::Record;

/// One value per parameter of [`TABLE`] (commands and read-only ones hold 0).
pub type Image = [i64; TABLE.len()];

/// The storage could not save (DRV.NVSAVE answers 0x02, resource unavailable).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NvError;

/// Where DRV.NVSAVE keeps the parameter values.
pub trait NvStorage {
    /// The saved values, if a save happened.
    fn load(&self) -> Option<Image>;
    /// Saves `image`; an error refuses DRV.NVSAVE.
    fn save(&mut self, image: &Image) -> Result<(), NvError>;
    /// Forgets the saved values (factory defaults).
    fn clear(&mut self) -> Result<(), NvError>;
}

/// Bytes of the saved record: every value, little-endian.
const RECORD_BYTES: usize = 8 * TABLE.len();
const _: () = assert!(
    RECORD_BYTES <= enip_stack::nv::PROFILE_RECORD_ROOM,
    "the saved parameters must fit in the store beside the TCP/IP settings"
);

/// The saved values in RAM and, given the adapter's store ([`RamNv::in_store`]), in a record
/// there: without one they survive an Identity Reset type 0, not a power cycle.
#[derive(Debug, Clone, Default)]
pub struct RamNv {
    image: Option<Image>,
    record: Option<Record>,
}

impl RamNv {
    /// Empty storage (factory defaults).
    pub const fn new() -> Self {
        RamNv {
            image: None,
            record: None,
        }
    }

    /// The values saved in `store` (none, or unreadable: factory defaults), saved there
    /// from now on.
    pub fn in_store(store: SharedStore) -> Self {
        let record = Record::new(store, key::KOLLMORGEN_AKD_PARAMETERS);
        let image = record.load::<RECORD_BYTES>().map(|bytes| {
            let mut image: Image = [0; TABLE.len()];
            for (value, raw) in image.iter_mut().zip(bytes.chunks_exact(8)) {
                *value = raw.try_into().map_or(0, i64::from_le_bytes);
            }
            image
        });
        RamNv {
            image,
            record: Some(record),
        }
    }
}

/// Two storages are equal when they hold the same values (where they are saved is not
/// compared).
impl PartialEq for RamNv {
    fn eq(&self, other: &Self) -> bool {
        self.image == other.image
    }
}

impl Eq for RamNv {}

impl NvStorage for RamNv {
    fn load(&self) -> Option<Image> {
        self.image
    }
    fn save(&mut self, image: &Image) -> Result<(), NvError> {
        if let Some(record) = self.record {
            let mut bytes = [0u8; RECORD_BYTES];
            for (raw, value) in bytes.chunks_exact_mut(8).zip(image) {
                raw.copy_from_slice(&value.to_le_bytes());
            }
            record.save(&bytes).map_err(|_| NvError)?;
        }
        self.image = Some(*image);
        Ok(())
    }
    fn clear(&mut self) -> Result<(), NvError> {
        if let Some(record) = self.record {
            record.clear().map_err(|_| NvError)?;
        }
        self.image = None;
        Ok(())
    }
}
