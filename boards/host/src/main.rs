//! Placeholder: the Linux host board lands here.
fn main() {}
