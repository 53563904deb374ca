//! What a conformance test reads from the standard objects: the class attributes (instance 0:
//! revision, max instance, number of instances, optional attribute list, optional service
//! list, highest class and instance attribute IDs) and each instance's Get_Attributes_All
//! reply, byte for byte in the order the CIP specification lists the attributes.

mod common;

use common::*;
use enip_stack::wire::epath::{LogicalType, SegmentRepr};

/// Get_Attributes_All (0x01) of `class`/`instance`: general status and data.
fn get_all(h: &mut Harness, class: u32, instance: u32) -> (u8, Vec<u8>) {
    let path = [
        SegmentRepr::Logical(LogicalType::Class, class),
        SegmentRepr::Logical(LogicalType::Instance, instance),
    ];
    let (g, _, data) = status(&h.request(0x01, &path, &[]));
    (g, data)
}

fn u16s(data: &[u8]) -> Vec<u16> {
    data.chunks(2)
        .map(|c| u16::from_le_bytes([c[0], c.get(1).copied().unwrap_or(0)]))
        .collect()
}

/// Class attributes 1-7 of `class` by Get_Attributes_All on instance 0: revision, max
/// instance, number of instances, optional attribute list, optional service list, highest
/// class attribute ID (7), highest instance attribute ID.
fn class_attributes(h: &mut Harness, class: u32) -> (u16, u16, u16, Vec<u16>, Vec<u16>, u16) {
    let (g, data) = get_all(h, class, 0);
    assert_eq!(g, 0, "class {class:#x} Get_Attributes_All");
    let words = u16s(&data);
    let (revision, max, count, optional_len) = (words[0], words[1], words[2], words[3]);
    let n = usize::from(optional_len);
    let optional = words[4..4 + n].to_vec();
    let services_len = usize::from(words[4 + n]);
    let services = words[5 + n..5 + n + services_len].to_vec();
    let rest = &words[5 + n + services_len..];
    assert_eq!(rest.len(), 2, "class {class:#x}: class and instance IDs");
    assert_eq!(rest[0], 7, "class {class:#x}: highest class attribute ID");
    // Each single Get gives the same value as Get_Attributes_All.
    for (id, value) in [(1, revision), (2, max), (3, count), (7, rest[1])] {
        let path = [
            SegmentRepr::Logical(LogicalType::Class, class),
            SegmentRepr::Logical(LogicalType::Instance, 0),
            SegmentRepr::Logical(LogicalType::Attribute, id),
        ];
        let (g, _, single) = status(&h.request(0x0E, &path, &[]));
        assert_eq!(
            (g, u16s(&single)),
            (0, vec![value]),
            "class {class:#x} attribute {id}"
        );
    }
    (revision, max, count, optional, services, rest[1])
}

/// Get_Attribute_List and Set_Attribute_List, which every class answers, then `more`.
fn lists_and(more: &[u16]) -> Vec<u16> {
    [&[0x03, 0x04][..], more].concat()
}

#[test]
fn class_attributes_of_every_standard_object() {
    let mut h = Harness::new();
    assert_eq!(
        class_attributes(&mut h, 0x01),
        (1, 1, 1, vec![8], lists_and(&[]), 8)
    );
    assert_eq!(
        class_attributes(&mut h, 0x02),
        (1, 1, 1, vec![1, 2], lists_and(&[0x0A]), 2)
    );
    // Assembly: the highest instance is 154, and 10 + 10 + 4 instances exist.
    assert_eq!(
        class_attributes(&mut h, 0x04),
        (2, 154, 24, vec![4], lists_and(&[]), 4)
    );
    assert_eq!(
        class_attributes(&mut h, 0x06),
        (1, 1, 1, (1..=8).collect(), lists_and(&[0x52, 0x5B]), 8)
    );
    assert_eq!(
        class_attributes(&mut h, 0xF5),
        (4, 1, 1, vec![8, 9, 10, 11, 13], lists_and(&[]), 13)
    );
    assert_eq!(
        class_attributes(&mut h, 0xF6),
        (4, 1, 1, (4..=11).collect(), lists_and(&[0x4C]), 11)
    );
    // Each optional service listed is answered (not 0x08) at instance 1.
    for (class, service) in [(0x02u32, 0x0Au8), (0x06, 0x5B), (0xF6, 0x4C)] {
        let path = [
            SegmentRepr::Logical(LogicalType::Class, class),
            SegmentRepr::Logical(LogicalType::Instance, 1),
        ];
        let (g, _, _) = status(&h.request(service, &path, &[]));
        assert_ne!(g, 0x08, "class {class:#x} service {service:#x}");
    }
}

#[test]
fn identity_get_attributes_all() {
    let mut h = Harness::new();
    let (g, data) = get_all(&mut h, 0x01, 1);
    assert_eq!(g, 0);
    let mut want = Vec::new();
    want.extend_from_slice(&IDENTITY.vendor_id.to_le_bytes());
    want.extend_from_slice(&IDENTITY.device_type.to_le_bytes());
    want.extend_from_slice(&IDENTITY.product_code.to_le_bytes());
    want.extend_from_slice(&[IDENTITY.revision.0, IDENTITY.revision.1]);
    want.extend_from_slice(&data[8..10]); // status: the device's bits, checked elsewhere
    want.extend_from_slice(&IDENTITY.serial_number.to_le_bytes());
    want.push(IDENTITY.product_name.len() as u8);
    want.extend_from_slice(IDENTITY.product_name.as_bytes());
    assert_eq!(data, want);
}

#[test]
fn message_router_get_attributes_all() {
    let mut h = Harness::new();
    let (g, data) = get_all(&mut h, 0x02, 1);
    assert_eq!(g, 0);
    // Object list (count, class IDs), then Number Available (the connection capacity).
    assert_eq!(
        u16s(&data),
        vec![
            9,
            0x01,
            0x02,
            0x04,
            0x06,
            0xF5,
            0xF6,
            0x48,
            0x109,
            0x10A,
            CONNECTIONS as u16
        ]
    );
}

#[test]
fn connection_manager_get_attributes_all() {
    let mut h = Harness::new();
    let (g, data) = get_all(&mut h, 0x06, 1);
    assert_eq!(g, 0);
    // Attributes 1-8, a UINT each: nothing opened, closed or timed out yet.
    assert_eq!(u16s(&data), vec![0; 8]);
}

#[test]
fn assembly_has_no_get_attributes_all() {
    let mut h = Harness::new();
    assert_eq!(get_all(&mut h, 0x04, 100).0, 0x08);
}

#[test]
fn tcp_ip_get_attributes_all() {
    let mut h = Harness::new();
    let (g, data) = get_all(&mut h, 0xF5, 1);
    assert_eq!(g, 0);
    let mut want = Vec::new();
    want.extend_from_slice(&1u32.to_le_bytes()); // 1 status: configured
    want.extend_from_slice(&0x50u32.to_le_bytes()); // 2 settable, change needs reset (no DHCP client)
    want.extend_from_slice(&0u32.to_le_bytes()); // 3 static
    want.extend_from_slice(&[2, 0, 0x20, 0xF6, 0x24, 0x01]); // 4 path to Ethernet Link 1
                                                             // 5: address, mask, gateway, name servers (UDINTs), domain name
    want.extend_from_slice(&u32::from_be_bytes([198, 18, 0, 2]).to_le_bytes());
    want.extend_from_slice(&0xFFFF_FF00u32.to_le_bytes());
    want.extend_from_slice(&[0; 12]);
    want.extend_from_slice(&[0, 0]);
    want.extend_from_slice(&[0, 0]); // 6 host name (empty)
    want.extend_from_slice(&[0; 6]); // 7 safety network number
    want.push(1); // 8 TTL
    want.extend_from_slice(&[0, 0, 1, 0]); // 9 mcast: default algorithm, one address
    want.extend_from_slice(&u32::from_be_bytes([239, 192, 1, 32]).to_le_bytes());
    want.push(1); // 10 SelectAcd (on by default; the runtime reports whether it runs)
    want.extend_from_slice(&[0; 35]); // 11 LastConflictDetected
    want.push(0); // 12 QuickConnect
    want.extend_from_slice(&120u16.to_le_bytes()); // 13 inactivity timeout
    assert_eq!(data, want);
}

#[test]
fn ethernet_link_get_attributes_all() {
    let mut h = Harness::new();
    let (g, data) = get_all(&mut h, 0xF6, 1);
    assert_eq!(g, 0);
    let mut want = Vec::new();
    want.extend_from_slice(&100u32.to_le_bytes()); // 1 speed
    want.extend_from_slice(&0x0Fu32.to_le_bytes()); // 2 link up, full duplex, negotiated
    want.extend_from_slice(&[2, 0, 0, 0, 0, 2]); // 3 MAC
    want.extend_from_slice(&[0; 44]); // 4 interface counters
    want.extend_from_slice(&[0; 48]); // 5 media counters
    want.extend_from_slice(&[1, 0, 0, 0]); // 6 auto-negotiate, no forced speed
    want.extend_from_slice(&[2, 1, 1]); // 7 twisted pair, 8 enabled, 9 admin enabled
    want.extend_from_slice(&[6, b'P', b'o', b'r', b't', b' ', b'1']); // 10 label
    want.extend_from_slice(&2u32.to_le_bytes()); // 11 capability: auto-negotiate,
    want.push(4); //   and the speed/duplex pairs
    for (speed, duplex) in [(10u16, 0u8), (10, 1), (100, 0), (100, 1)] {
        want.extend_from_slice(&speed.to_le_bytes());
        want.push(duplex);
    }
    assert_eq!(data, want);
}
