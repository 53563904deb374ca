//! Links with the board's own `memory.x` (the STM32H743ZI map; the workspace's top-level one
//! is the F767's) and bakes in the network settings and the profile.

include!("../build-support/board_build.rs");

fn main() {
    link_with_own_memory_map_and_device("memory.x");
    network_settings("192.168.1.10/24");
    profile_from_features();
    // defmt's linker script, for the log frames.
    println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
}
