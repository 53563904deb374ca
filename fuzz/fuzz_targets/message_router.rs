//! Message Router request and response framing: parse, emit, re-parse.
#![no_main]

use enip_stack::wire::message_router::{RequestPacket, RequestRepr, ResponseRepr};
use enip_stack::wire::Writer;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(p) = RequestPacket::new_checked(data) {
        assert_eq!(p.path().len(), 2 * usize::from(p.path_words()));
        assert_eq!(2 + p.path().len() + p.data().len(), data.len());
        let repr = RequestRepr::parse(&p);
        assert_eq!(repr.buffer_len(), data.len());
        let mut out = vec![0u8; repr.buffer_len()];
        repr.emit(&mut Writer::new(&mut out)).expect("fits");
        assert_eq!(&out[..], data);
        if !data.is_empty() {
            let mut short = vec![0u8; data.len() - 1];
            assert!(repr.emit(&mut Writer::new(&mut short)).is_err());
        }
    }
    if let Ok(r) = ResponseRepr::parse(data) {
        assert_eq!(r.buffer_len(), data.len());
        let _ = r.extended_status();
        let mut out = vec![0u8; r.buffer_len()];
        r.emit(&mut Writer::new(&mut out)).expect("fits");
        // The same bytes, but for the reserved one, which emit zeroes.
        assert_eq!((out[0], &out[2..]), (data[0], &data[2..]));
        assert_eq!(ResponseRepr::parse(&out), Ok(r));
    }
});
