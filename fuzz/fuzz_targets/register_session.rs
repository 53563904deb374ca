//! RegisterSession data: parse, then emit reproduces the bytes.
#![no_main]

use enip_stack::wire::register_session::{Packet, RegisterSessionRepr, LEN};
use enip_stack::wire::Writer;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(p) = Packet::new_checked(data) else {
        return;
    };
    let repr = RegisterSessionRepr::parse(&p);
    let mut out = [0u8; LEN];
    repr.emit(&mut Writer::new(&mut out)).expect("fits");
    assert_eq!(&out[..], data);
    assert_eq!(repr.buffer_len(), LEN);
});
