//! `explicit_cycle N`: drives the sans-IO adapter with the generic profile through N
//! unconnected Get_Attribute_Single requests (Identity attribute 7, the product name) in
//! SendRRData frames on one registered session. Run under callgrind by `cargo xtask bench`
//! for the stack's instructions per explicit request (two runs of different N, so set-up
//! cancels out).

use std::hint::black_box;
use std::net::{Ipv4Addr, SocketAddrV4};

use enip_firmware::profiles::generic::Generic;
use enip_stack::config::MAX_ENCAP_FRAME;
use enip_stack::originator;
use enip_stack::wire::epath::{LogicalType, Segment};
use enip_stack::{Adapter, Instant, NetworkConfig, SocketId};

/// Get_Attribute_Single.
const GET_ATTRIBUTE_SINGLE: u8 = 0x0E;

fn main() {
    let requests: u64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(100_000);
    let net = NetworkConfig::new_static(
        Ipv4Addr::new(198, 18, 0, 2),
        Ipv4Addr::new(255, 255, 255, 0),
        [2, 0, 0, 0, 0, 2],
    );
    let mut adapter = Adapter::new(Generic::new(), net, 1);
    let scanner = SocketAddrV4::new(Ipv4Addr::new(198, 18, 0, 1), 50_000);
    adapter.tcp_accept(SocketId(0), scanner, Instant(0));
    let mut frame = vec![0u8; MAX_ENCAP_FRAME];
    let mut reply = vec![0u8; MAX_ENCAP_FRAME];
    let n = originator::register_session(&mut frame).expect("frame");
    let out = adapter.tcp_receive(SocketId(0), &frame[..n], Instant(0), &mut reply);
    assert_eq!(out.reply_len, 28, "RegisterSession answered");
    let session = u32::from_le_bytes(reply[4..8].try_into().expect("handle"));
    let path = [
        Segment::Logical(LogicalType::Class, 1),
        Segment::Logical(LogicalType::Instance, 1),
        Segment::Logical(LogicalType::Attribute, 7),
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
