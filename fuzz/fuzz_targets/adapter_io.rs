//! The Class 1 path: Forward_Open/Forward_Close over TCP, `io_receive` on UDP 2222,
//! `poll_io` production, input triggers and time; see `enip_fuzz::io_script`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    enip_fuzz::io_script::run_io(data, |_, _| {});
});
