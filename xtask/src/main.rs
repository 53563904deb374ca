//! Placeholder: `cargo xtask` lands here.
fn main() {}
