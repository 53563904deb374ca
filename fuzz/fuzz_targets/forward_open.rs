//! Forward_Open / Large_Forward_Open / Forward_Close request data and their replies: parse,
//! emit, re-parse must give the same value, and `buffer_len` is what `emit` writes.
#![no_main]

use enip_stack::wire::forward_open::{
    FailureReplyRepr, ForwardCloseReplyRepr, ForwardCloseRepr, ForwardOpenReplyRepr,
    ForwardOpenRepr,
};
use enip_stack::wire::Writer;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let mut out = vec![0u8; data.len() + 16];
    for large in [false, true] {
        if let Ok(fo) = ForwardOpenRepr::parse(data, large) {
            let mut w = Writer::new(&mut out);
            fo.emit(&mut w).expect("a parsed Forward_Open emits");
            assert_eq!(w.len(), data.len(), "emitted length differs");
            let n = w.len();
            assert_eq!(fo.buffer_len(), n);
            assert_eq!(ForwardOpenRepr::parse(&out[..n], large), Ok(fo));
            let _ = (fo.transport_class(), fo.trigger());
        }
    }
    if let Ok(fc) = ForwardCloseRepr::parse(data) {
        let mut w = Writer::new(&mut out);
        fc.emit(&mut w).expect("a parsed Forward_Close emits");
        let n = w.len();
        assert_eq!(n, data.len());
        assert_eq!(fc.buffer_len(), n);
        assert_eq!(ForwardCloseRepr::parse(&out[..n]), Ok(fc));
    }
    if let Ok(r) = ForwardOpenReplyRepr::parse(data) {
        let mut w = Writer::new(&mut out);
        r.emit(&mut w).expect("a parsed reply emits");
        let n = w.len();
        assert_eq!(r.buffer_len(), n);
        assert_eq!(ForwardOpenReplyRepr::parse(&out[..n]), Ok(r));
    }
    if let Ok(r) = FailureReplyRepr::parse(data) {
        let mut w = Writer::new(&mut out);
        r.emit(&mut w).expect("a parsed failure reply emits");
        let n = w.len();
        assert_eq!(r.buffer_len(), n);
        assert_eq!(n, data.len());
        // The same bytes, but for the reserved last one, which emit zeroes.
        assert_eq!(out[..n - 1], data[..n - 1]);
        assert_eq!(FailureReplyRepr::parse(&out[..n]), Ok(r));
    }
    if let Ok(r) = ForwardCloseReplyRepr::parse(data) {
        let mut w = Writer::new(&mut out);
        r.emit(&mut w).expect("a parsed close reply emits");
        let n = w.len();
        assert_eq!(r.buffer_len(), n);
        assert_eq!(n, data.len());
        // The same bytes, but for the reserved one after the size, which emit zeroes.
        assert_eq!((&out[..9], &out[10..n]), (&data[..9], &data[10..]));
        assert_eq!(ForwardCloseReplyRepr::parse(&out[..n]), Ok(r));
    }
});
