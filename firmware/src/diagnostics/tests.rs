//! The diagnostics class through the adapter's message router, in front of the generic
//! profile.

use core::net::{Ipv4Addr, SocketAddrV4};

use enip_profiles::Generic;
use enip_stack::config::MAX_ENCAP_FRAME;
use enip_stack::originator::{self, parse_reply};
use enip_stack::wire::encap::EncapRepr;
use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use enip_stack::{Adapter, NetworkConfig, SocketId};

use super::*;
use enip_stack::Instant;

fn measured() -> StackUse {
    StackUse {
        size: 4096,
        painted: 2048,
        deepest: 700,
    }
}

/// The adapter over the generic profile with the diagnostics in front, a session registered
/// on socket 0; returns it with the session handle.
fn adapter() -> (Adapter<Diagnosed<Generic>>, u32) {
    with_platform(Platform {
        stack: measured,
        provoke: None,
    })
}

/// [`adapter`] with the board's `platform`.
fn with_platform(platform: Platform) -> (Adapter<Diagnosed<Generic>>, u32) {
    let net = NetworkConfig::new_static(
        Ipv4Addr::new(198, 18, 0, 2),
        Ipv4Addr::new(255, 255, 255, 0),
        [2, 0, 0, 0, 0, 1],
    );
    let mut a = Adapter::new(Diagnosed::new(Generic::new(), platform), net, 7);
    let peer = SocketAddrV4::new(Ipv4Addr::new(198, 18, 0, 1), 50000);
    a.tcp_accept(SocketId(0), peer, Instant(0));
    let mut frame = [0u8; 64];
    let mut reply = [0u8; MAX_ENCAP_FRAME];
    let n = originator::register_session(&mut frame).unwrap();
    let out = a.tcp_receive(SocketId(0), &frame[..n], Instant(0), &mut reply);
    let session = EncapRepr::parse_header(&reply[..out.reply_len])
        .unwrap()
        .session_handle;
    (a, session)
}

/// Sends `service` to `class`/1/`attribute` in `session`; returns the general status and
/// the reply data (its first 4 bytes).
fn ask(
    rig: &mut (Adapter<Diagnosed<Generic>>, u32),
    service: u8,
    class: u32,
    attribute: u32,
) -> (u8, [u8; 4]) {
    ask_with(rig, service, class, attribute, &[])
}

/// [`ask`] with request data `data`.
fn ask_with(
    (a, session): &mut (Adapter<Diagnosed<Generic>>, u32),
    service: u8,
    class: u32,
    attribute: u32,
    data: &[u8],
) -> (u8, [u8; 4]) {
    let mut frame = [0u8; 128];
    let mut reply = [0u8; MAX_ENCAP_FRAME];
    let path = [
        SegmentRepr::Logical(LogicalType::Class, class),
        SegmentRepr::Logical(LogicalType::Instance, 1),
        SegmentRepr::Logical(LogicalType::Attribute, attribute),
    ];
    let n = originator::send_rr_data(&mut frame, *session, None, |w| {
        originator::request(w, service, &path, data)
    })
    .unwrap();
    let out = a.tcp_receive(SocketId(0), &frame[..n], Instant(0), &mut reply);
    let r = parse_reply(&reply[..out.reply_len])
        .unwrap()
        .response
        .unwrap();
    let mut data = [0u8; 4];
    let len = r.data.len().min(4);
    data[..len].copy_from_slice(&r.data[..len]);
    (r.general_status, data)
}

#[test]
fn the_stack_measurement_is_readable_over_cip() {
    let mut a = adapter();
    let get = GET_ATTRIBUTE_SINGLE;
    assert_eq!(ask(&mut a, get, CLASS, 1), (0, 4096u32.to_le_bytes()));
    assert_eq!(ask(&mut a, get, CLASS, 2), (0, 2048u32.to_le_bytes()));
    assert_eq!(ask(&mut a, get, CLASS, 3), (0, 700u32.to_le_bytes()));
    assert_eq!(
        ask(&mut a, get, CLASS, 4).0,
        General::AttributeNotSupported as u8
    );
    // Without a fault trigger (every image but the test ones), the service does not exist.
    assert_eq!(
        ask(&mut a, PROVOKE, CLASS, 1).0,
        General::ServiceNotSupported as u8
    );
    // The device behind still answers its own objects (Identity, product name).
    let (status, _) = ask(&mut a, get, 1, 7);
    assert_eq!(status, 0);
}

/// The fault kind the test trigger last received.
static PROVOKED: core::sync::atomic::AtomicU8 = core::sync::atomic::AtomicU8::new(0);

fn provoke(kind: u8) {
    PROVOKED.store(kind, core::sync::atomic::Ordering::Relaxed);
}

#[test]
fn a_test_image_faults_on_request_with_one_byte() {
    let mut a = with_platform(Platform {
        stack: measured,
        provoke: Some(provoke),
    });
    assert_eq!(ask_with(&mut a, PROVOKE, CLASS, 1, &[2]).0, 0);
    assert_eq!(PROVOKED.load(core::sync::atomic::Ordering::Relaxed), 2);
    for bad in [&[][..], &[1, 2]] {
        let status = ask_with(&mut a, PROVOKE, CLASS, 1, bad).0;
        assert_eq!(status, General::InvalidParameter as u8, "{bad:?}");
    }
    assert_eq!(PROVOKED.load(core::sync::atomic::Ordering::Relaxed), 2);
}
