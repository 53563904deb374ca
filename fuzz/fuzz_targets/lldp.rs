//! LLDP: the input as an LLDPDU, parsed, then taken in twice by an adapter (the test device),
//! whose LLDP Data Table is read attribute by attribute and whose own LLDPDU must parse.
//! The input is a neighbour exactly when it parses with a TTL outlasting the reads.
#![no_main]

use enip_fuzz::{frames, script, TestDevice};
use enip_stack::adapter::MAX_LLDPDU;
use enip_stack::wire::lldp::LldpduRepr;
use enip_stack::Instant;
use libfuzzer_sys::fuzz_target;

/// Seconds, as the adapter's clock counts.
fn at(seconds: u64) -> Instant {
    Instant::from_micros(seconds * 1_000_000)
}

fuzz_target!(|data: &[u8]| {
    let parsed = LldpduRepr::parse(data);
    let mut adapter = script::adapter(TestDevice::new());
    adapter.lldp_receive(data, at(1));
    adapter.lldp_receive(data, at(2));
    let mut reply = [0u8; 600];
    for instance in 1..=8u16 {
        for attribute in 1..=9u16 {
            let req = frames::get_attribute_single(0x10A, instance, attribute);
            let n = adapter.execute(&req, at(3), &mut reply);
            assert!(n >= 4, "a reply to every read");
        }
    }
    let req = frames::get_attribute_single(0x10A, 1, 2);
    let n = adapter.execute(&req, at(3), &mut reply);
    let listed = n >= 4 && reply[2] == 0;
    let expected = parsed.as_ref().is_ok_and(|p| p.ttl >= 2);
    assert_eq!(listed, expected, "{parsed:?}");
    let mut out = [0u8; MAX_LLDPDU];
    let n = adapter.lldp_transmit(at(3), &mut out);
    assert!(
        n > 0 && LldpduRepr::parse(&out[..n]).is_ok(),
        "our own LLDPDU"
    );
});
