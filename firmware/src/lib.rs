//! The EtherNet/IP adapter runtime on embassy-net, and the device profiles.
//!
//! A board builds an [`embassy_net::Stack`], wraps a [`enip_stack::Adapter`] over a device profile
//! with [`share`], and awaits [`run`] next to the stack's runner:
//!
//! - [`run`] serves the three encapsulation TCP sockets and the UDP socket on port 44818,
//!   Class 1 I/O, keeps the adapter's view of the interface current, and runs the device's
//!   own clock (`Device::poll`, e.g. a simulated drive's control tick);
//! - [`profiles`] holds the shipped device profiles (each behind its `profile-NAME` feature)
//!   and `Profile`, which picks one of them by name;
//! - [`Resources`] are the socket buffers, which the board places (usually in a `static`),
//!   and the embassy-net stack needs [`SOCKETS`] sockets (build its resources with
//!   [`stack_resources`], which refuses fewer);
//! - [`indicators`] shows the ODVA Module and Network Status on the board's LEDs.
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

mod clock;
mod device_tick;
pub mod indicators;
mod io;
mod netif;
pub mod profiles;
mod resources;
mod runtime;
mod shared;
mod tcp;
mod udp;

pub use netif::network_config;
#[cfg(feature = "_any-profile")]
pub use profiles::Profile;
pub use resources::{stack_resources, Resources, SOCKETS};
pub use runtime::run;
pub use shared::{share, with_adapter, SharedAdapter};
