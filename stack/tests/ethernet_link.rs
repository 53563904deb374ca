//! The Ethernet Link object's counters, as the runtime hands them over, read and cleared
//! with Get_And_Clear; interface control (6) and admin state (9) Sets, each rule once.

mod common;

use common::*;
use enip_stack::objects::LinkCounters;
use enip_stack::wire::epath::{LogicalType, SegmentRepr};

fn path(attribute: u32) -> [SegmentRepr<'static>; 3] {
    [
        SegmentRepr::Logical(LogicalType::Class, 0xF6),
        SegmentRepr::Logical(LogicalType::Instance, 1),
        SegmentRepr::Logical(LogicalType::Attribute, attribute),
    ]
}

fn udints(data: &[u8]) -> Vec<u32> {
    data.chunks(4)
        .map(|c| u32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

/// An IPv4 frame of `len` bytes to `dst`.
fn frame(dst: [u8; 6], len: usize) -> Vec<u8> {
    let mut f = vec![0u8; len];
    f[..6].copy_from_slice(&dst);
    f[12..14].copy_from_slice(&[0x08, 0x00]);
    f
}

#[test]
fn counters_read_and_get_and_clear() {
    let mut h = Harness::new();
    let me = [2, 0, 0, 0, 0, 2];
    let mut counted = LinkCounters::new();
    counted.received(&frame(me, 100), &me);
    counted.received(&frame([0xFF; 6], 60), &me);
    counted.sent(&frame([2, 0, 0, 0, 0, 1], 200));
    counted.media.fcs_errors = 3; // as a board that reads its MAC's counters would report
    h.adapter.add_link_counters(&counted);
    h.adapter.add_link_counters(&counted);

    let (g, _, data) = status(&h.request(0x0E, &path(4), &[]));
    assert_eq!(g, 0);
    // In: 2 x (104 + 64) octets, 2 unicast, 2 broadcast; out: 2 x 204 octets, 2 unicast.
    assert_eq!(
        udints(&data),
        vec![336, 2, 2, 0, 0, 0, 408, 2, 0, 0, 0],
        "interface counters"
    );

    // Get_And_Clear answers the values, then they are zero; the media counters stay.
    let (g, _, data) = status(&h.request(0x4C, &path(4), &[]));
    assert_eq!((g, udints(&data)[0]), (0, 336));
    let (_, _, data) = status(&h.request(0x0E, &path(4), &[]));
    assert_eq!(udints(&data), vec![0; 11]);
    let (g, _, data) = status(&h.request(0x4C, &path(5), &[]));
    assert_eq!((g, udints(&data)[1]), (0, 6), "FCS errors");
    let (_, _, data) = status(&h.request(0x0E, &path(5), &[]));
    assert_eq!(udints(&data), vec![0; 12]);
}

#[test]
fn get_and_clear_statuses() {
    let mut h = Harness::new();
    for (attribute, general) in [(1, 0x2E), (6, 0x2E), (12, 0x14)] {
        let (g, _, _) = status(&h.request(0x4C, &path(attribute), &[]));
        assert_eq!(g, general, "Get_And_Clear of attribute {attribute}");
    }
}

#[test]
fn interface_control_sets() {
    let mut h = Harness::new();
    for (value, general, what) in [
        (
            [1u8, 0, 0, 0],
            0x00,
            "auto-negotiate, nothing forced: the interface's setting",
        ),
        ([1, 0, 100, 0], 0x0C, "auto-negotiate with a forced speed"),
        ([3, 0, 0, 0], 0x0C, "auto-negotiate with forced full duplex"),
        (
            [2, 0, 100, 0],
            0x09,
            "forced 100 full duplex: no driver can force",
        ),
        ([0, 0, 10, 0], 0x09, "forced 10 half duplex"),
        ([5, 0, 0, 0], 0x09, "a reserved control bit"),
    ] {
        let (g, _, _) = status(&h.request(0x10, &path(6), &value));
        assert_eq!(g, general, "{what}");
    }
    let (g, _, _) = status(&h.request(0x10, &path(6), &[1, 0, 0]));
    assert_eq!(g, 0x13, "three bytes");
    let (g, _, data) = status(&h.request(0x0E, &path(6), &[]));
    assert_eq!((g, data), (0, vec![1, 0, 0, 0]), "unchanged");
}

#[test]
fn admin_state_sets() {
    let mut h = Harness::new();
    for (value, general) in [(1u8, 0x00), (2, 0x09), (0, 0x09), (3, 0x09)] {
        let (g, _, _) = status(&h.request(0x10, &path(9), &[value]));
        assert_eq!(g, general, "admin state {value}");
    }
    let (_, _, data) = status(&h.request(0x0E, &path(9), &[]));
    assert_eq!(data, vec![1]);
    let (_, _, data) = status(&h.request(0x0E, &path(8), &[]));
    assert_eq!(data, vec![1], "interface state: enabled");
}
