//! A `no_std`, heap-free, sans-IO EtherNet/IP adapter (target) stack.
//!
//! The stack never touches a socket or a clock: the runtime hands it received bytes and the
//! current [`Instant`], and it writes replies into buffers the runtime owns. Every capacity is a
//! compile-time constant in [`config`].
//!
//! The modules form a one-way graph; read bottom-up, each uses only those above it in this
//! list (`cargo xtask modules` checks it):
//!
//! - [`time`], [`rng`], [`net`], [`config`] (every capacity), [`nv`] (non-volatile storage:
//!   A/B copies with sequence numbers and CRC over any flash): small leaves.
//! - [`acd`]: Address Conflict Detection (RFC 5227): ARP probes and announcements, the
//!   state machine of one address, what the TCP/IP object reports of it.
//! - [`wire`]: zero-copy, length-checked codecs for every EtherNet/IP and CIP structure.
//! - [`cip`]: the vocabulary: status codes, class IDs, services, object definitions,
//!   requests and their context.
//! - [`device`]: the [`Device`] trait a device profile implements and the types it speaks in
//!   (connection kinds, events, admission, multicast settings); [`guide`] walks through
//!   writing one.
//! - [`io`]: connections: the connection table, Forward_Open validation, production and
//!   consumption of Class 1 data, Class 3 state.
//! - [`objects`]: the standard objects and the Message Router's dispatch to them (the
//!   Connection Manager among them, which is why they sit above the connections).
//! - `encap`: encapsulation sessions, TCP framing and the delayed ListIdentity replies.
//! - [`adapter`]: the [`Adapter`] the runtime drives, with the encapsulation commands beside it.
//! - [`tcp`]: the encapsulation port's TCP for a runtime that owns the Ethernet driver,
//!   feeding each connection's byte stream to the adapter.
//! - [`eds`] (the EDS file of any device), [`originator`] (the scanner side of the codecs, for
//!   tests and tools) and [`virtual_scanner`] (a scanner in virtual time, for a device's own
//!   tests) use the layers below them.
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]
// No panic on any input, made mechanical: no unwrap, expect, panic, unchecked indexing or
// arithmetic that can overflow outside the tests.
#![cfg_attr(
    not(test),
    deny(
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::indexing_slicing,
        clippy::arithmetic_side_effects
    )
)]

#[macro_use]
mod fmt;

pub mod acd;
pub mod adapter;
pub mod cip;
pub mod config;
pub mod device;
pub mod eds;
pub(crate) mod encap;
pub mod guide;
pub mod io;
pub mod net;
pub mod nv;
pub mod objects;
pub mod originator;
pub mod rng;
pub mod tcp;
pub mod time;
pub mod virtual_scanner;
pub mod wire;

pub use adapter::{Adapter, SocketId, TcpOutcome};
pub use device::{AssemblyInfo, AssemblyRole, Device, IdentityInfo};
pub use io::IoDue;
pub use net::NetworkConfig;
pub use time::{Duration, Instant};
