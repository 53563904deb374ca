//! Links with the mps2-an386 memory map and bakes in the network settings, profile and
//! Address Conflict Detection and test-image choices.

include!("../build-support/board_build.rs");

fn main() {
    link_with_own_memory_map("memory.x");
    network_settings("198.18.0.2/24");
    profile_from_features();
    acd_setting();
    test_faults_setting();
}
