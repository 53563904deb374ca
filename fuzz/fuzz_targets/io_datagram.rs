//! The Class 1 datagram on UDP 2222: `Packet::new_checked`, and `IoDatagramRepr` parses and
//! re-emits the front of a checked datagram (its header and sequence count).
#![no_main]

use enip_stack::wire::io_datagram::{IoDatagramRepr, Packet, HEADER_LEN, SEQUENCE_LEN};
use enip_stack::wire::Writer;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(p) = Packet::new_checked(data) else {
        return;
    };
    let connected = p.connected_data();
    assert_eq!(HEADER_LEN + connected.len(), data.len());
    let Ok(repr) = IoDatagramRepr::parse(&p) else {
        assert!(connected.len() < SEQUENCE_LEN);
        return;
    };
    assert_eq!(usize::from(repr.connected_len), connected.len());
    let n = repr.buffer_len();
    let mut out = vec![0u8; n];
    repr.emit(&mut Writer::new(&mut out))
        .expect("a checked datagram's front emits");
    assert_eq!(&out[..], &data[..n]);
    assert!(repr.emit(&mut Writer::new(&mut out[..n - 1])).is_err());
});
