//! Links with the board's `board-link.x` (its memory map and cortex-m-rt's `link.x`, written
//! by the board crate's build script, on the link search path; a project of its own, outside
//! this workspace, keeps the board's `memory.x` next to its `Cargo.toml` and links with
//! `link.x` instead), embassy-rp's `link-rp.x` (the boot stage 2) and defmt's `defmt.x`.

fn main() {
    println!("cargo:rustc-link-arg-bins=--nmagic");
    println!("cargo:rustc-link-arg-bins=-Tboard-link.x");
    println!("cargo:rustc-link-arg-bins=-Tlink-rp.x");
    println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
}
