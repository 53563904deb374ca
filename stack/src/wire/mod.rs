//! Zero-copy, length-checked codecs for EtherNet/IP and CIP wire structures.
//!
//! One naming and one emission convention, after smoltcp's `wire`:
//! - a structure read in place has a view, `Packet<T: AsRef<[u8]>>` (`RequestPacket<T>` where
//!   a module holds several structures), whose `new_checked` validates the length once, so
//!   its getters cannot fail;
//! - every structure has an owned `XxxRepr` (`EncapRepr`, `ItemRepr`, `ForwardOpenRepr`,
//!   `SegmentRepr`, ...) with `parse` (from its checked view where it has one, else from its
//!   bytes or a [`Reader`]), `buffer_len` (the bytes `emit` writes) and
//!   `emit(&self, w: &mut Writer<'_>) -> Result<()>`;
//! - groups of fields inside a structure ([`forward_open::Triad`],
//!   [`forward_open::NetworkParams`], [`epath::ElectronicKey`]) are plain values with the same
//!   verbs where they have a wire form.
//!
//! Nothing here panics or indexes out of bounds on any input, and no emit writes past the
//! [`Writer`]'s buffer.

pub mod bytes;
pub mod cpf;
pub mod encap;
pub mod epath;
pub mod forward_open;
pub mod identity_item;
pub mod io_datagram;
pub mod lldp;
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

impl core::fmt::Display for Error {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Error::Truncated => "truncated: shorter than the structure or its length field",
            Error::Malformed => "malformed: a field holds a value the structure does not allow",
            Error::Exhausted => "output buffer too small",
        })
    }
}

impl core::error::Error for Error {}

/// Result of a codec operation.
pub type Result<T> = core::result::Result<T, Error>;

pub use bytes::{Reader, Writer};
