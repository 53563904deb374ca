//! The EtherNet/IP adapter runtime on embassy-net.
//!
//! A board builds an [`embassy_net::Stack`] over a [`link::NetDriver`], shares an
//! [`enip_stack::Adapter`] over a device profile in an [`AdapterCell`], spawns the link task
//! with its Ethernet driver, and awaits [`run`] next to the stack's runner:
//!
//! - [`run`] serves the UDP socket on port 44818, keeps the adapter's view of the interface
//!   current, runs the device's own clock (`Device::poll`, e.g. a simulated drive's control
//!   tick), and performs the Identity Resets requested;
//! - [`link`] is Class 1 I/O and the encapsulation TCP at the Ethernet frame level: the
//!   board's driver belongs to the link task ([`link::run`]), which hands O->T datagrams to
//!   the adapter and sends T->O data straight from it, serves TCP port 44818 with the
//!   stack's own TCP ([`enip_stack::tcp`]: a request and its reply in one wake-up), and
//!   passes every other frame to embassy-net through a [`link::NetDriver`];
//! - [`Resources`] are the UDP socket's buffers, which the board places (usually in a
//!   `static`), and the embassy-net stack needs [`SOCKETS`] sockets (build its resources
//!   with [`stack_resources`], which refuses fewer);
//! - [`indicators`] shows the ODVA Module and Network Status on the board's LEDs;
//! - [`admission`] holds Class 1 connections to the RPI the board can sustain ([`RpiFloor`]);
//! - [`diagnostics`] puts the board's own object (its call stack's high-water mark) in front of
//!   the device profile, and [`watchdog`] feeds a hardware watchdog while the link task runs.
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

// The stack's logging macros (its `fmt` module), decided by this crate's `log` and `defmt`
// features.
#[macro_use(info, warn, error)]
extern crate enip_stack;

pub mod admission;
mod clock;
mod device_tick;
pub mod diagnostics;
pub mod indicators;
pub mod link;
mod multicast;
mod netif;
mod resources;
mod runtime;
mod shared;
mod udp;
pub mod watchdog;

pub use admission::RpiFloor;
pub use diagnostics::Diagnosed;
pub use netif::network_config;
pub use resources::{stack_resources, Resources, SOCKETS};
pub use runtime::run;
pub use shared::{share, with_adapter, AdapterCell, SharedAdapter};
