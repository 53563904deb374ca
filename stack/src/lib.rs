//! A `no_std`, heap-free, sans-IO EtherNet/IP adapter (target) stack.
//!
//! The stack never touches a socket or a clock: the runtime hands it received bytes and the
//! current [`Instant`], and it writes replies into buffers the runtime owns. Every capacity is a
//! compile-time constant in [`config`].
//!
//! - [`wire`]: zero-copy, length-checked codecs for every EtherNet/IP and CIP structure.
//! - [`cip`]: status codes, the request/reply model and the standard objects.
//! - [`encap`]: encapsulation sessions, TCP framing and command handling.
//! - [`device`]: the [`Device`] trait a device profile implements; [`guide`] walks through
//!   writing one.
//! - [`adapter`]: the [`Adapter`] the runtime drives.
//! - [`eds`]: the EDS file of any device.
//! - [`nv`]: non-volatile storage (A/B copies with sequence numbers and CRC) over any flash.
//! - [`virtual_scanner`]: a scanner in virtual time, for a device's own tests.
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

pub mod adapter;
pub mod cip;
pub mod config;
pub mod device;
pub mod eds;
pub mod encap;
pub mod guide;
pub mod io;
pub mod net;
pub mod nv;
pub mod originator;
pub mod rng;
pub mod time;
pub mod virtual_scanner;
pub mod wire;

pub use adapter::{Adapter, SocketId, TcpOutcome};
pub use device::{AssemblyInfo, AssemblyRole, Device, IdentityInfo};
pub use io::produce::IoDue;
pub use net::NetworkConfig;
pub use time::{Duration, Instant};
