//! The encapsulation port's TCP (`enip_stack::tcp::TcpServer`) with a real adapter behind
//! it, fed a script of segments from several peers, time and sends; see
//! `enip_fuzz::tcp_script` for the format and the invariants.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    enip_fuzz::tcp_script::run_tcp_server(data);
});
