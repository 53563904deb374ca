//! `Adapter::tcp_receive` fed by a script of accepts, closes and data chunks on 4 sockets (one
//! outside the adapter's range); see `enip_fuzz::script` for the format and the invariants.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    enip_fuzz::script::run_tcp(data, |_, _| {});
});
