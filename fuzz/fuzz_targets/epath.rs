//! EPATH segments: parse, re-emit, re-parse must give the same segments, and the re-emitted
//! (canonical) form must be a fixed point; `buffer_len` must match what `emit` writes.
#![no_main]

use enip_stack::wire::epath::{SegmentRepr, Segments};
use enip_stack::wire::Writer;
use libfuzzer_sys::fuzz_target;

/// Emits every segment of `path` that parses; returns the canonical bytes and the segments.
fn canonical(path: &[u8]) -> (Vec<u8>, Vec<SegmentRepr<'_>>) {
    let segments: Vec<SegmentRepr<'_>> = Segments::new(path).map_while(Result::ok).collect();
    let mut out = vec![0u8; path.len() * 2 + 16];
    let mut w = Writer::new(&mut out);
    for s in &segments {
        let before = w.len();
        s.emit(&mut w)
            .unwrap_or_else(|e| panic!("parsed segment {s:?} does not emit: {e:?}"));
        assert_eq!(w.len() - before, s.buffer_len(), "buffer_len of {s:?}");
    }
    let n = w.len();
    out.truncate(n);
    (out, segments)
}

fuzz_target!(|data: &[u8]| {
    let (bytes, first) = canonical(data);
    let reparsed: Vec<_> = Segments::new(&bytes).collect();
    assert!(
        reparsed.iter().all(Result::is_ok),
        "re-emitted path does not parse: {first:?} -> {bytes:02x?} -> {reparsed:?}"
    );
    let second: Vec<SegmentRepr<'_>> = reparsed.into_iter().map_while(Result::ok).collect();
    assert_eq!(first, second, "segments changed through emit: {bytes:02x?}");
    let (again, _) = canonical(&bytes);
    assert_eq!(bytes, again, "canonical form is not stable");
});
