//! The ametek-pls profile's own parsers: requests to its classes and symbolic paths through
//! `Adapter::execute`, its assemblies through `Device::write_assembly`, and its own time;
//! see `enip_fuzz::profile` for the script format and the invariants.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    enip_fuzz::profile::run("ametek-pls", data);
});
