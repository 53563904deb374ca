//! Non-volatile storage of the program (§2.9: "save the current settings to NVRAM"):
//! [`Nvram`] is what the profile needs from it; [`RamNvram`] keeps the image in RAM and in a
//! record of the adapter's store.

use enip_stack::nv::{key, SharedStore};

use super::config::{CONFIG_BYTES, GROUPS};
use crate::nv_record::Record;

/// Bytes of the saved image: attributes 1-35 and 38, then the 8 group offsets.
pub const IMAGE_BYTES: usize = CONFIG_BYTES + 2 * GROUPS;
const _: () = assert!(
    IMAGE_BYTES <= enip_stack::nv::PROFILE_RECORD_ROOM,
    "the program must fit in the store beside the TCP/IP settings"
);

/// Why the image could not be stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StoreError;

/// Non-volatile storage of one program image.
pub trait Nvram {
    /// The saved image, if one was saved.
    fn load(&self) -> Option<&[u8; IMAGE_BYTES]>;
    /// Saves `image`.
    fn store(&mut self, image: &[u8; IMAGE_BYTES]) -> Result<(), StoreError>;
    /// Forgets the saved image (factory defaults).
    fn clear(&mut self) -> Result<(), StoreError>;
}

/// An [`Nvram`] in RAM and, given the adapter's store ([`RamNvram::in_store`]), in a record
/// there, so the program survives a restart.
#[derive(Debug, Clone)]
pub struct RamNvram {
    image: [u8; IMAGE_BYTES],
    saved: bool,
    record: Option<Record>,
}

impl RamNvram {
    /// An empty store: the module powers up with its defaults.
    pub const fn new() -> Self {
        RamNvram {
            image: [0; IMAGE_BYTES],
            saved: false,
            record: None,
        }
    }

    /// The program saved in `store` (none, or unreadable: the defaults), saved there from
    /// now on.
    pub fn in_store(store: SharedStore) -> Self {
        let record = Record::new(store, key::AMETEK_PLS_PROGRAM);
        let mut nv = RamNvram::new();
        if let Some(image) = record.load::<IMAGE_BYTES>() {
            nv.image = image;
            nv.saved = true;
        }
        nv.record = Some(record);
        nv
    }
}

/// Two stores are equal when they hold the same image (where it is saved is not compared).
impl PartialEq for RamNvram {
    fn eq(&self, other: &Self) -> bool {
        self.load() == other.load()
    }
}

impl Eq for RamNvram {}

impl Default for RamNvram {
    fn default() -> Self {
        Self::new()
    }
}

impl Nvram for RamNvram {
    fn load(&self) -> Option<&[u8; IMAGE_BYTES]> {
        self.saved.then_some(&self.image)
    }

    fn store(&mut self, image: &[u8; IMAGE_BYTES]) -> Result<(), StoreError> {
        if let Some(record) = self.record {
            record.save(image).map_err(|_| StoreError)?;
        }
        self.image = *image;
        self.saved = true;
        Ok(())
    }

    fn clear(&mut self) -> Result<(), StoreError> {
        if let Some(record) = self.record {
            record.clear().map_err(|_| StoreError)?;
        }
        self.saved = false;
        Ok(())
    }
}
