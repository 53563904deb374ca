//! Links with the board's own memory map (`memory.x`: the RP2040's boot stage 2, the 2 MiB
//! QSPI flash less the store's last 8 KiB, 264 KiB of RAM) and bakes in the network settings
//! and the profile.

include!("../build-support/board_build.rs");

fn main() {
    link_with_own_memory_map_and_device("memory.x");
    network_settings("192.168.1.10/24");
    profile_from_features();
    // embassy-rp's `.boot2` placement, and defmt's linker script for the log frames.
    println!("cargo:rustc-link-arg-bins=-Tlink-rp.x");
    println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
}
