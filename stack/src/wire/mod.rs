//! Zero-copy, length-checked codecs for EtherNet/IP and CIP wire structures.
//!
//! Each structure has a `Packet<T: AsRef<[u8]>>` view whose `new_checked` validates the length
//! once (so its getters cannot fail), and where useful a `Repr` that parses and emits. Nothing
//! here panics or indexes out of bounds on any input, and no emit writes past its buffer.

pub mod bytes;
pub mod cpf;
pub mod encap;
pub mod epath;
pub mod forward_open;
pub mod identity_item;
pub mod io_datagram;
pub mod message_router;
pub mod register_session;
pub mod rr_data;

/// Why a buffer could not be parsed or emitted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Error {
    /// The buffer is shorter than the structure (or than a length field says).
    Truncated,
    /// A field holds a value the structure does not allow.
    Malformed,
    /// The output buffer is too small.
    Exhausted,
}

/// Result of a codec operation.
pub type Result<T> = core::result::Result<T, Error>;

pub use bytes::{Reader, Writer};
