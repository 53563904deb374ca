//! `explicit_cycle N`: drives the sans-IO adapter with the generic profile through N
//! unconnected Get_Attribute_Single requests (Identity attribute 7, the product name) in
//! SendRRData frames on one registered session. Run under callgrind by `cargo xtask bench`
//! for the stack's instructions per explicit request (two runs of different N, so set-up
//! cancels out).

use std::hint::black_box;

use enip_profiles::generic::Generic;
use enip_stack::config::MAX_ENCAP_FRAME;
use enip_stack::originator;
use enip_stack::virtual_scanner::VirtualScanner;
use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use enip_stack::{Instant, SocketId};

/// Get_Attribute_Single.
const GET_ATTRIBUTE_SINGLE: u8 = 0x0E;

fn main() {
    let requests: u64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(100_000);
    let mut scanner = VirtualScanner::new(Generic::new());
    let session = scanner.session();
    assert_ne!(session, 0, "RegisterSession answered");
    let adapter = scanner.adapter_mut();
    let mut frame = vec![0u8; MAX_ENCAP_FRAME];
    let mut reply = vec![0u8; MAX_ENCAP_FRAME];
    let path = [
        SegmentRepr::Logical(LogicalType::Class, 1),
        SegmentRepr::Logical(LogicalType::Instance, 1),
        SegmentRepr::Logical(LogicalType::Attribute, 7),
    ];
    // The request is built once, so the count is the adapter's work, not the originator's.
    let n = originator::send_rr_data(&mut frame, session, None, |w| {
        originator::request(w, GET_ATTRIBUTE_SINGLE, &path, &[])
    })
    .expect("frame");
    let mut answered = 0u64;
    for k in 1..=requests {
        let out = adapter.tcp_receive(
            SocketId(0),
            black_box(&frame[..n]),
            Instant(k * 1_000),
            &mut reply,
        );
        black_box(&reply[..out.reply_len]);
        answered += u64::from(out.reply_len > 0 && !out.close);
    }
    let r = originator::parse_reply(&reply).expect("reply");
    assert_eq!(r.response.map(|m| m.general_status), Some(0), "success");
    assert_eq!(answered, requests, "every request answered");
    println!("{{\"requests\":{requests},\"answered\":{answered}}}");
}
