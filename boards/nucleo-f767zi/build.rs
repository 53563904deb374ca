//! Links with the workspace's top-level `memory.x` (the STM32F767ZI map) and bakes in the
//! network settings and the profile.

include!("../build-support/board_build.rs");

fn main() {
    link_with_top_level_memory_map();
    network_settings("192.168.1.10/24");
    profile_from_features();
    // defmt's linker script, for the log frames.
    println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
}
