//! The non-volatile copy of the parameters DRV.NVSAVE stores and a power-up loads:
//! [`Parameters`], kept in [`NvCopy`], a record of the adapter's store ([`crate::storage`]).

use super::params::TABLE;
use crate::storage::{key, Record, Saved};

/// One value per parameter of [`TABLE`] (commands and read-only ones hold 0).
pub type Image = [i64; TABLE.len()];

/// Bytes of the saved record: every value, little-endian.
const RECORD_BYTES: usize = 8 * TABLE.len();

/// The values DRV.NVSAVE saved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Parameters(pub Image);

impl Record<RECORD_BYTES> for Parameters {
    const KEY: u16 = key::KOLLMORGEN_AKD_PARAMETERS;
    fn encode(&self) -> [u8; RECORD_BYTES] {
        let mut bytes = [0u8; RECORD_BYTES];
        for (raw, value) in bytes.chunks_exact_mut(8).zip(&self.0) {
            raw.copy_from_slice(&value.to_le_bytes());
        }
        bytes
    }
    fn decode(bytes: &[u8; RECORD_BYTES]) -> Self {
        let mut image: Image = [0; TABLE.len()];
        for (value, raw) in image.iter_mut().zip(bytes.chunks_exact(8)) {
            *value = raw.try_into().map_or(0, i64::from_le_bytes);
        }
        Parameters(image)
    }
}

/// The saved values in RAM and, given the adapter's store ([`NvCopy::in_store`]), in a
/// record there; a failed save refuses DRV.NVSAVE (0x02, resource unavailable).
pub type NvCopy = Saved<Parameters, RECORD_BYTES>;
