//! Device profiles, each behind its cargo feature `profile-NAME`, and [`Profile`] to choose
//! one of those compiled in by name at run time.
//!
//! A firmware of its own device enables none of them and compiles none of them.

#[cfg(feature = "profile-ametek-pls")]
pub mod ametek_pls;
#[cfg(feature = "profile-generic")]
pub mod generic;
#[cfg(feature = "profile-kollmorgen-akd")]
pub mod kollmorgen_akd;
#[cfg(feature = "profile-parker-ipa")]
pub mod parker_ipa;
#[cfg(feature = "profile-position-servo")]
pub mod position_servo;

#[cfg(feature = "_any-profile")]
pub mod nv_record;
#[cfg(feature = "_any-profile")]
mod powered_up;
#[cfg(feature = "_any-profile")]
mod select;

#[cfg(feature = "profile-ametek-pls")]
pub use ametek_pls::AmetekPls;
#[cfg(feature = "profile-generic")]
pub use generic::Generic;
#[cfg(feature = "profile-kollmorgen-akd")]
pub use kollmorgen_akd::KollmorgenAkd;
#[cfg(feature = "profile-parker-ipa")]
pub use parker_ipa::ParkerIpa;
#[cfg(feature = "profile-position-servo")]
pub use position_servo::PositionServo;
#[cfg(feature = "_any-profile")]
pub use powered_up::PoweredUp;
#[cfg(feature = "_any-profile")]
pub use select::Profile;
