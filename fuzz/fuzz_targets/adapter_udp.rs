//! `Adapter::udp_receive` and `poll_udp` fed by a script of unicast, broadcast and multicast
//! datagrams and time steps; see `enip_fuzz::script` for the format and the invariants.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    enip_fuzz::script::run_udp(data, |_, _| {});
});
