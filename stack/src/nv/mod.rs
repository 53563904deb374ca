//! Non-volatile storage: the one abstraction for everything that must survive a power cycle.
//!
//! [`NvStore`] keeps small numbered records (the TCP/IP object's settings, a profile's saved
//! configuration); writing one replaces it as a whole or not at all. [`AbStore`] implements it
//! over any [`Flash`] with two sectors used in turn (A/B): a write programs a complete new
//! copy (sequence number and CRC) into the other sector and commits it last, so a power cut at
//! any point leaves the previous complete copy readable, and erases alternate between the two.
//! [`NorFlashSectors`] puts it on any `embedded-storage` `NorFlash` driver (the NUCLEO's
//! on-chip flash), [`RamFlash`] is the flash of the host and QEMU builds, [`CutFlash`] one
//! whose power a test cuts at any step. [`SharedStore`] lets the adapter and the device profile keep their
//! records in the same store.

mod ab;
mod crc;
mod cut_flash;
mod flash;
mod records;
mod shared;

#[cfg(feature = "cip-security")]
pub use ab::SECURITY_RECORD_ROOM;
pub use ab::{
    AbStore, ACD_RECORD_ROOM, BASE_IMAGE_SIZE, IMAGE_SIZE, LLDP_RECORD_ROOM, PROFILE_RECORD_ROOM,
    QOS_RECORD_ROOM, STACK_RECORD_ROOM, TCP_IP_RECORD_ROOM,
};
pub use crc::crc32;
pub use cut_flash::{CutFlash, CUT_SECTOR};
pub use flash::{Flash, FlashError, NorFlashSectors, RamFlash, MAX_WRITE_SIZE};
pub use shared::SharedStore;

/// Why a store operation failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum NvError {
    /// The flash refused a read, erase or program.
    Flash,
    /// The records do not fit in one copy ([`IMAGE_SIZE`]).
    NoSpace,
    /// The caller's buffer is smaller than the record.
    BufferTooSmall,
    /// Another owner's operation on a [`SharedStore`] is still running.
    Busy,
}

impl core::fmt::Display for NvError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            NvError::Flash => "the flash refused a read, erase or program",
            NvError::NoSpace => "the records do not fit in one copy",
            NvError::BufferTooSmall => "the buffer is smaller than the record",
            NvError::Busy => "another owner's store operation is still running",
        })
    }
}

impl core::error::Error for NvError {}

impl From<FlashError> for NvError {
    fn from(_: FlashError) -> Self {
        NvError::Flash
    }
}

/// Record keys: who owns which record. The stack's are below 0x100; the device uses
/// [`key::PROFILE_BASE`] and up (the shipped profiles' keys are theirs, in `enip-profiles`).
pub mod key {
    /// The TCP/IP Interface object's settings (attributes 3, 5, 6, 8, 9 and 13).
    pub const TCP_IP: u16 = 0x0001;
    /// The LLDP Management object's settings (attributes 1-3).
    pub const LLDP: u16 = 0x0002;
    /// The QoS object's settings (attributes 1-8).
    pub const QOS: u16 = 0x0003;
    /// Address Conflict Detection: TCP/IP attributes 10 and 11.
    pub const ACD: u16 = 0x0004;
    /// CIP Security settings (feature `cip-security`): the security objects' states, the
    /// TLS settings in use and the certificate instances.
    pub const SECURITY: u16 = 0x0005;
    /// First key of the device's records.
    pub const PROFILE_BASE: u16 = 0x0100;
}

/// Small numbered records that survive a power cycle; each write or removal is atomic, and so
/// is a batch of them between [`NvStore::begin`] and [`NvStore::commit`].
pub trait NvStore {
    /// Copies record `key` into `buf`; its length, or `None` if there is no such record.
    fn read(&mut self, key: u16, buf: &mut [u8]) -> Result<Option<usize>, NvError>;
    /// Stores `value` as record `key`, replacing any previous value, all or nothing.
    fn write(&mut self, key: u16, value: &[u8]) -> Result<(), NvError>;
    /// Removes record `key` (nothing if there is none).
    fn remove(&mut self, key: u16) -> Result<(), NvError>;
    /// Starts a batch: the writes and removals until [`Self::commit`] show in reads at once
    /// but reach the flash together, all or nothing (the Identity object's factory reset
    /// removes the device's records and the TCP/IP settings as one).
    fn begin(&mut self) -> Result<(), NvError>;
    /// Saves the batch's changes as one (nothing if there are none) and ends it; on failure
    /// the records are those from before the batch.
    fn commit(&mut self) -> Result<(), NvError>;
    /// Ends the batch, dropping its changes.
    fn abandon(&mut self);
}

/// Record `key` of `store` read into a buffer of `N` bytes and decoded: `None` if there is
/// none, or if it does not decode (logged as `what`'s settings, whose defaults then hold). A
/// record longer than `N` bytes (another layout's) does not decode: it is not an error.
pub(crate) fn read_decoded<const N: usize, T>(
    store: &mut dyn NvStore,
    key: u16,
    what: &str,
    decode: impl FnOnce(&[u8]) -> Option<T>,
) -> Result<Option<T>, NvError> {
    let mut buf = [0u8; N];
    let decoded = match store.read(key, &mut buf) {
        Ok(None) => return Ok(None),
        Ok(Some(len)) => buf.get(..len).and_then(decode),
        Err(NvError::BufferTooSmall) => None,
        Err(e) => return Err(e),
    };
    if decoded.is_none() {
        warn!("stored {} settings unreadable; factory defaults hold", what);
    }
    Ok(decoded)
}

#[cfg(test)]
mod power_cut;
