//! Links with cortex-m-rt's `link.x` (which includes `memory.x`: the linker finds the
//! STM32F767ZI map at the workspace root; a project of its own keeps a copy next to its
//! `Cargo.toml`) and defmt's `defmt.x`.

fn main() {
    println!("cargo:rustc-link-arg-bins=--nmagic");
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
    println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
}
