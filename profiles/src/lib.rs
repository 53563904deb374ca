//! The device profiles of enip-rs: each an [`enip_stack::Device`] behind its cargo feature,
//! and [`Profile`] to choose one of those compiled in by name at run time.
//!
//! | feature | type | device |
//! | --- | --- | --- |
//! | `generic` | [`Generic`] | the OpENer sample application's assemblies |
//! | `position-servo` | [`PositionServo`] | the Lenze (AC Tech) PositionServo drive |
//! | `parker-ipa` | [`ParkerIpa`] | the Parker IPA / ACR9000 controller |
//! | `ametek-pls` | [`AmetekPls`] | the AMETEK 7500 programmable limit switch |
//! | `kollmorgen-akd` | [`KollmorgenAkd`] | the Kollmorgen AKD servo drive |
//!
//! A firmware of its own device enables none of them and compiles none of them. A board
//! runs one with the runtime (`enip-firmware`): it powers the profile up from its
//! non-volatile store ([`PoweredUp`]), where the profile keeps its saved settings as one
//! record ([`storage`]).
//!
//! Every profile is laid out the same way, one file per part: `mod.rs` (the profile's type
//! and its `Device` impl), `identity.rs`, `assemblies.rs`, `params.rs` (the parameter
//! table), `classes` (vendor classes), `device` (the simulated device), `storage.rs` (what
//! it saves), `eds.rs` and `tests`; the crate's README has the whole scheme. The files of a
//! profile import each other one way (`cargo xtask modules` checks it).
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
// features; only the Ametek profile logs.
#[cfg_attr(feature = "ametek-pls", macro_use(info, warn))]
extern crate enip_stack;

#[cfg(feature = "ametek-pls")]
pub mod ametek_pls;
#[cfg(feature = "generic")]
pub mod generic;
#[cfg(feature = "kollmorgen-akd")]
pub mod kollmorgen_akd;
#[cfg(feature = "parker-ipa")]
pub mod parker_ipa;
#[cfg(feature = "position-servo")]
pub mod position_servo;

#[cfg(feature = "_any-profile")]
mod powered_up;
#[cfg(feature = "_any-profile")]
mod select;
#[cfg(feature = "_any-profile")]
pub mod storage;

#[cfg(feature = "ametek-pls")]
pub use ametek_pls::AmetekPls;
#[cfg(feature = "generic")]
pub use generic::Generic;
#[cfg(feature = "kollmorgen-akd")]
pub use kollmorgen_akd::KollmorgenAkd;
#[cfg(feature = "parker-ipa")]
pub use parker_ipa::ParkerIpa;
#[cfg(feature = "position-servo")]
pub use position_servo::PositionServo;
#[cfg(feature = "_any-profile")]
pub use powered_up::PoweredUp;
#[cfg(feature = "_any-profile")]
pub use select::Profile;
