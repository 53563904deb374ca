//! Chooses the QEMU machine (cargo features `an385`, `an386`, `an500`, `an505`), links with
//! its memory map and bakes in the network settings, profile and Address Conflict Detection
//! and test-image choices.

include!("../build-support/board_build.rs");

/// The machines: feature, the target it builds for, and its memory map. The first is the
/// default, which gives way to any other.
const MACHINES: [(&str, &str, &str); 4] = [
    ("an386", "thumbv7em-none-eabihf", "memory.x"),
    ("an385", "thumbv7m-none-eabi", "memory.x"),
    ("an500", "thumbv7em-none-eabihf", "memory.x"),
    ("an505", "thumbv8m.main-none-eabihf", "memory-an505.x"),
];

fn main() {
    let memory_x = machine();
    link_with_own_memory_map(memory_x);
    network_settings("198.18.0.2/24");
    profile_from_features();
    acd_setting();
    test_faults_setting();
}

/// Sets the `mps2_machine` cfg to the chosen machine and returns its memory map; fails the
/// build on two non-default machines or a target the machine's core does not run.
fn machine() -> &'static str {
    let values: Vec<String> = MACHINES
        .iter()
        .map(|(m, _, _)| format!("\"{m}\""))
        .collect();
    println!(
        "cargo::rustc-check-cfg=cfg(mps2_machine, values({}))",
        values.join(", ")
    );
    let enabled = |m: &str| env::var_os(format!("CARGO_FEATURE_{}", m.to_uppercase())).is_some();
    let others: Vec<_> = MACHINES[1..]
        .iter()
        .filter(|(m, _, _)| enabled(m))
        .collect();
    let (name, target, memory_x) = match others.as_slice() {
        [] => MACHINES[0],
        [one] => **one,
        _ => panic!("enable one machine feature (an385, an386, an500, an505), not several"),
    };
    let building_for = env::var("TARGET").unwrap_or_default();
    assert!(
        building_for == target,
        "the {name} machine builds for --target {target}, not {building_for}"
    );
    println!("cargo::rustc-cfg=mps2_machine=\"{name}\"");
    memory_x
}
