//! Links with the board's link script: enip-nucleo-h743zi's build script writes `board-link.x`
//! (the STM32H743ZI map followed by cortex-m-rt's `link.x`) and puts it on the search path of
//! the crates that depend on it; and defmt's `defmt.x`.

fn main() {
    println!("cargo:rustc-link-arg-bins=--nmagic");
    println!("cargo:rustc-link-arg-bins=-Tboard-link.x");
    println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
}
