//! `enip-nucleo-h563zi`: the board firmware running one of the shipped device profiles.
//!
//! Build-time settings: `ENIP_IP` (default 192.168.1.10/24) and `ENIP_GATEWAY` for the
//! static address, or the `dhcp` feature; the profile by a `profile-NAME` feature (default
//! `generic`). Everything else is [`enip_nucleo_h563zi::run`].
#![no_std]
#![no_main]

include!("../../shared/profile_main.rs");
profile_main!(enip_nucleo_h563zi, "enip-nucleo-h563zi");
