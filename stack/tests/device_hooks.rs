//! Device hooks the stack consults: multicast TTL and configuration kept by the device
//! (TCP/IP attributes 8 and 9, Forward_Open, the runtime's group and TTL) and the refusal of
//! change-of-state connections.

mod common;

use std::net::Ipv4Addr;

use common::*;
use enip_stack::device::Multicast;
use enip_stack::device::MulticastConfig;
use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use enip_stack::wire::forward_open::NetworkParams;

fn tcpip(attribute: u32) -> [SegmentRepr<'static>; 3] {
    [
        SegmentRepr::Logical(LogicalType::Class, 0xF5),
        SegmentRepr::Logical(LogicalType::Instance, 1),
        SegmentRepr::Logical(LogicalType::Attribute, attribute),
    ]
}

fn device_keeps(h: &mut Harness, ttl: u8, start: [u8; 4]) {
    h.adapter.device_mut().multicast = Some(Multicast {
        ttl,
        config: MulticastConfig {
            alloc_control: 0,
            num_mcast: 1,
            start: Ipv4Addr::from(start),
        },
    });
}

#[test]
fn tcpip_attributes_8_and_9_read_and_write_the_device_values() {
    let mut h = Harness::new();
    device_keeps(&mut h, 1, [239, 192, 15, 32]);
    let (g, _, d) = status(&h.request(0x0E, &tcpip(8), &[]));
    assert_eq!((g, d), (0, vec![1]));
    let (g, _, d) = status(&h.request(0x0E, &tcpip(9), &[]));
    assert_eq!((g, d), (0, vec![0, 0, 1, 0, 32, 15, 192, 239]));

    assert_eq!(status(&h.request(0x10, &tcpip(8), &[5])).0, 0);
    assert_eq!(h.adapter.device().multicast.map(|m| m.ttl), Some(5));
    assert_eq!(h.adapter.multicast_ttl(), 5);
    // The stack validates first (TTL 0), then the device may refuse (two addresses).
    assert_eq!(status(&h.request(0x10, &tcpip(8), &[0])).0, 0x09);
    let two = [1, 0, 2, 0, 1, 2, 192, 239];
    assert_eq!(status(&h.request(0x10, &tcpip(9), &two)).0, 0x09);
    let one = [1, 0, 1, 0, 7, 2, 192, 239];
    assert_eq!(status(&h.request(0x10, &tcpip(9), &one)).0, 0);
    let m = h.adapter.device().multicast.unwrap();
    assert_eq!((m.ttl, m.config.start), (5, Ipv4Addr::new(239, 192, 2, 7)));
    // The stack's own values are untouched.
    assert_eq!(h.adapter.objects().tcpip.ttl, 1);
    assert_eq!(h.adapter.objects().tcpip.mcast.alloc_control, 0);
}

#[test]
fn forward_open_and_group_use_the_device_address() {
    let mut h = Harness::new();
    device_keeps(&mut h, 1, [239, 192, 15, 32]);
    let path = io_path(None, 110, 100, None);
    let mut owner = fo(1, &path, 5_000);
    owner.t_o_params = NetworkParams::from_u16(0x2800 | 34);
    let frame = h.forward_open(&owner);
    let reply = enip_stack::originator::parse_reply(&frame).unwrap();
    assert_eq!(reply.response.unwrap().general_status, 0);
    let group = reply.t_o_sockaddr.expect("T->O sockaddr item");
    assert_eq!(group.addr, Ipv4Addr::new(239, 192, 15, 32));
    assert_eq!(h.adapter.multicast_group(), Some(group.addr));
}

#[test]
fn change_of_state_is_refused_when_the_device_says_so() {
    let mut h = Harness::new();
    let path = io_path(None, 110, 100, None);
    let mut cos = fo(1, &path, 10_000);
    cos.transport = 0x11;
    h.adapter.device_mut().change_of_state = false;
    let (g, words, _) = status(&h.forward_open(&cos));
    assert_eq!((g, words.first().copied()), (0x01, Some(0x0103)));
    // Cyclic and application-triggered still open.
    let mut app = fo(2, &path, 10_000);
    app.transport = 0x21;
    assert_eq!(status(&h.forward_open(&app)).0, 0);
    h.adapter.device_mut().change_of_state = true;
    let other = io_path(None, 111, 101, None);
    let mut cos = fo(3, &other, 10_000);
    cos.transport = 0x11;
    assert_eq!(status(&h.forward_open(&cos)).0, 0);
}
