//! The Class 1 datagram on UDP 2222: `Packet::new_checked`, and `emit_header` reproduces a
//! checked datagram's header.
#![no_main]

use enip_stack::wire::io_datagram::{emit_header, Packet, HEADER_LEN};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(p) = Packet::new_checked(data) else {
        return;
    };
    let connected = p.connected_data();
    assert_eq!(HEADER_LEN + connected.len(), data.len());
    let mut out = data.to_vec();
    emit_header(
        &mut out,
        p.connection_id(),
        p.encap_sequence(),
        connected.len(),
    )
    .expect("a checked datagram's header emits");
    assert_eq!(out, data);
    assert!(emit_header(&mut out[..data.len() - 1], 0, 0, connected.len()).is_err());
});
