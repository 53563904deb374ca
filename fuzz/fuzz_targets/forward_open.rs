//! Forward_Open / Large_Forward_Open / Forward_Close request data and the Forward_Open reply:
//! parse, emit, re-parse must give the same value.
#![no_main]

use enip_stack::wire::forward_open::{ForwardClose, ForwardOpen, ForwardOpenReply};
use enip_stack::wire::Writer;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let mut out = vec![0u8; data.len() + 16];
    for large in [false, true] {
        if let Ok(fo) = ForwardOpen::parse(data, large) {
            let mut w = Writer::new(&mut out);
            fo.emit(&mut w).expect("a parsed Forward_Open emits");
            assert_eq!(w.len(), data.len(), "emitted length differs");
            let n = w.len();
            assert_eq!(ForwardOpen::parse(&out[..n], large), Ok(fo));
            let _ = (fo.transport_class(), fo.trigger());
        }
    }
    if let Ok(fc) = ForwardClose::parse(data) {
        let mut w = Writer::new(&mut out);
        fc.emit(&mut w).expect("a parsed Forward_Close emits");
        let n = w.len();
        assert_eq!(n, data.len());
        assert_eq!(ForwardClose::parse(&out[..n]), Ok(fc));
    }
    if let Ok(r) = ForwardOpenReply::parse(data) {
        let mut w = Writer::new(&mut out);
        r.emit(&mut w).expect("a parsed reply emits");
        let n = w.len();
        assert_eq!(ForwardOpenReply::parse(&out[..n]), Ok(r));
    }
});
