//! ListIdentity identity item and ListServices item: parse, emit, re-parse.
#![no_main]

use enip_stack::wire::identity_item::{IdentityRepr, ServiceRepr};
use enip_stack::wire::Writer;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(id) = IdentityRepr::parse(data) {
        assert_eq!(id.buffer_len(), data.len());
        let mut out = vec![0u8; id.buffer_len()];
        let mut w = Writer::new(&mut out);
        id.emit(&mut w).expect("fits");
        assert_eq!(w.len(), data.len());
        assert_eq!(IdentityRepr::parse(&out), Ok(id));
    }
    if let Ok(s) = ServiceRepr::parse(data) {
        let mut out = [0u8; 20];
        s.emit(&mut Writer::new(&mut out)).expect("fits");
        assert_eq!(&out[..], data);
    }
});
