//! Non-volatile storage of the program (§2.9: "save the current settings to NVRAM"):
//! [`Program`], the image the module saves, kept in [`Nvram`], a record of the adapter's
//! store ([`crate::storage`]).

use super::params::{CONFIG_BYTES, GROUPS};
use crate::storage::{key, Record, Saved};

/// Bytes of the saved image: attributes 1-35 and 38, then the 8 group offsets.
pub const IMAGE_BYTES: usize = CONFIG_BYTES + 2 * GROUPS;

/// The saved image of one program: attributes 1-35 and 38, then the group offsets, every
/// word little-endian.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Program(pub [u8; IMAGE_BYTES]);

impl Record<IMAGE_BYTES> for Program {
    const KEY: u16 = key::AMETEK_PLS_PROGRAM;
    fn encode(&self) -> [u8; IMAGE_BYTES] {
        self.0
    }
    fn decode(bytes: &[u8; IMAGE_BYTES]) -> Self {
        Program(*bytes)
    }
}

/// The NVRAM: the program saved, if one was, in RAM and, given the adapter's store
/// ([`Saved::in_store`]), in a record there, so the program survives a restart.
pub type Nvram = Saved<Program, IMAGE_BYTES>;
