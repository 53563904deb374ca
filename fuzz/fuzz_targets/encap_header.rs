//! Encapsulation header: `Packet::new_checked` + `EncapRepr::parse`, and emit reproduces the
//! header.
#![no_main]

use enip_stack::wire::encap::{EncapRepr, Packet, HEADER_LEN};
use enip_stack::wire::Writer;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let header = EncapRepr::parse_header(data);
    let Ok(p) = Packet::new_checked(data) else {
        return;
    };
    let repr = EncapRepr::parse(&p).expect("a checked packet parses");
    assert_eq!(Ok(repr), header);
    assert_eq!(p.data().len(), usize::from(repr.length));
    let mut out = [0u8; HEADER_LEN];
    repr.emit(&mut Writer::new(&mut out))
        .expect("the header fits in 24 bytes");
    assert_eq!(&out[..], &data[..HEADER_LEN]);
    assert!(repr
        .emit(&mut Writer::new(&mut out[..HEADER_LEN - 1]))
        .is_err());
});
