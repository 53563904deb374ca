//! `cip::Request::parse` and `Path::parse` on arbitrary bytes.
#![no_main]

use enip_stack::cip::{Path, Request};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    match Request::parse(data) {
        Ok(r) => {
            assert_eq!(Some(&r.service), data.first());
            assert_eq!(2 + r.raw_path.len() + r.data.len(), data.len());
            assert_eq!(Path::parse(r.raw_path), Ok(r.path));
            assert!(r.path.class.is_some() || r.path.symbol.is_some());
        }
        Err((service, e)) => {
            assert_eq!(service, data.first().copied().unwrap_or(0));
            assert_ne!(
                e.general,
                enip_stack::cip::General::Success,
                "an error with success status"
            );
        }
    }
    let _ = Path::parse(data).map(|p| p.instance_or_point());
});
