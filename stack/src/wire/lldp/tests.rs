//! Tests of the LLDPDU codec: the adapter's own LLDPDU read back, and malformed LLDPDUs
//! refused without a panic.

use super::*;

const MAC: [u8; 6] = [0x02, 0x00, 0x5E, 0x10, 0x00, 0x02];

fn local(ttl: u16) -> LocalSystem<'static> {
    LocalSystem {
        mac: MAC,
        port_id: b"Port 1",
        ttl,
        system_name: b"press-4",
        system_description: b"Generic adapter",
        ip: Ipv4Addr::new(198, 18, 0, 2),
        if_index: 1,
        identity: CipIdentification {
            vendor_id: 0x1234,
            device_type: 0x2B,
            product_code: 7,
            major_revision: 2,
            minor_revision: 5,
            serial_number: 0xDEAD_BEEF,
        },
    }
}

fn emitted(l: &LocalSystem<'_>, shutdown: bool) -> heapless::Vec<u8, 512> {
    let mut buf = [0u8; 512];
    let mut w = Writer::new(&mut buf);
    if shutdown {
        l.emit_shutdown(&mut w).unwrap();
    } else {
        l.emit(&mut w).unwrap();
    }
    heapless::Vec::from_slice(w.written()).unwrap()
}

#[test]
fn own_lldpdu_round_trips() {
    let l = local(120);
    let bytes = emitted(&l, false);
    // Chassis ID: type 1, length 7, subtype MAC.
    assert_eq!(&bytes[..3], &[0x02, 0x07, CHASSIS_MAC]);
    let pdu = LldpduRepr::parse(&bytes).unwrap();
    assert_eq!(pdu.neighbor_mac(), MAC);
    assert_eq!((pdu.port_subtype, pdu.port_id), (5, &b"Port 1"[..]));
    // The MSAP identifier: both ID TLVs, headers included (2 + 7 and 2 + 7 bytes).
    assert_eq!(pdu.msap, &bytes[..18]);
    assert_eq!(pdu.ttl, 120);
    assert_eq!(pdu.system_name, Some(&b"press-4"[..]));
    assert_eq!(pdu.capabilities, Some((0x80, 0x80)));
    assert_eq!(&pdu.addresses[..], &[Ipv4Addr::new(198, 18, 0, 2)]);
    assert_eq!(pdu.cip_identification, Some(l.identity));
    assert_eq!(pdu.cip_mac, Some(MAC));
    // The CIP Identification TLV: OUI, subtype 1, then the identity little-endian.
    let odva = [
        0xFE, 16, 0x00, 0x21, 0x6C, 1, 0x34, 0x12, 0x2B, 0, 7, 0, 2, 5, 0xEF, 0xBE, 0xAD, 0xDE,
    ];
    assert!(bytes.windows(odva.len()).any(|w| w == odva));
    // Ends with the End TLV.
    assert_eq!(&bytes[bytes.len() - 2..], &[0, 0]);
}

#[test]
fn shutdown_lldpdu_has_ttl_zero_and_only_the_mandatory_tlvs() {
    let bytes = emitted(&local(120), true);
    let pdu = LldpduRepr::parse(&bytes).unwrap();
    assert_eq!(pdu.ttl, 0);
    assert_eq!(pdu.system_name, None);
    assert_eq!(bytes.len(), 9 + 9 + 4 + 2);
}

#[test]
fn empty_name_and_no_address_are_left_out() {
    let mut l = local(30);
    l.system_name = b"";
    l.ip = Ipv4Addr::UNSPECIFIED;
    let pdu_bytes = emitted(&l, false);
    let pdu = LldpduRepr::parse(&pdu_bytes).unwrap();
    assert_eq!((pdu.system_name, pdu.addresses.len()), (None, 0));
}

#[test]
fn padding_after_the_end_and_unknown_tlvs_are_accepted() {
    let mut bytes = emitted(&local(30), false);
    bytes.truncate(bytes.len() - 2);
    // An unknown TLV type 9 and a foreign organizational TLV, then End and padding.
    bytes.extend_from_slice(&[0x12, 0x01, 0xAA]).unwrap();
    bytes
        .extend_from_slice(&[0xFE, 0x05, 0x00, 0x80, 0xC2, 0x01, 0x00])
        .unwrap();
    bytes.extend_from_slice(&[0, 0, 0, 0, 0, 0]).unwrap();
    let pdu = LldpduRepr::parse(&bytes).unwrap();
    assert_eq!(pdu.ttl, 30);
}

#[test]
fn malformed_lldpdus_are_refused() {
    let good = emitted(&local(30), false);
    // Every truncation inside the mandatory TLVs, or inside a later TLV, is refused.
    for cut in 0..good.len() - 2 {
        let r = LldpduRepr::parse(&good[..cut]);
        if cut < 22 {
            assert!(r.is_err(), "cut at {cut}");
        }
    }
    // Mandatory TLVs out of order: Port ID first.
    let mut swapped = [0u8; 64];
    swapped[..9].copy_from_slice(&good[9..18]);
    swapped[9..18].copy_from_slice(&good[..9]);
    swapped[18..22].copy_from_slice(&good[18..22]);
    assert_eq!(LldpduRepr::parse(&swapped[..24]), Err(Error::Malformed));
    // Chassis ID of length 1 (subtype only).
    assert_eq!(
        LldpduRepr::parse(&[0x02, 0x01, 4, 0x04, 0x02, 5, b'x', 0x06, 0x02, 0, 30, 0, 0]),
        Err(Error::Malformed)
    );
    // A second TTL TLV.
    let mut twice = heapless::Vec::<u8, 512>::from_slice(&good[..22]).unwrap();
    twice.extend_from_slice(&good[18..22]).unwrap();
    assert_eq!(LldpduRepr::parse(&twice), Err(Error::Malformed));
    // A TLV whose length runs past the data.
    let mut long = heapless::Vec::<u8, 512>::from_slice(&good[..22]).unwrap();
    long.extend_from_slice(&[0x0A, 0x40, b'a']).unwrap();
    assert_eq!(LldpduRepr::parse(&long), Err(Error::Truncated));
    assert!(LldpduRepr::parse(&[]).is_err());
}

#[test]
fn malformed_optional_tlvs_are_skipped() {
    let mut bytes = heapless::Vec::<u8, 512>::from_slice(&emitted(&local(30), true)).unwrap();
    bytes.truncate(bytes.len() - 2);
    // Capabilities of 3 bytes, a CIP Identification one byte short, a management address
    // whose address length runs past its TLV.
    bytes.extend_from_slice(&[0x0E, 0x03, 0, 0x80, 0]).unwrap();
    let mut short_id = heapless::Vec::<u8, 32>::from_slice(&[0xFE, 15, 0, 0x21, 0x6C, 1]).unwrap();
    short_id.extend_from_slice(&[0; 11]).unwrap();
    bytes.extend_from_slice(&short_id).unwrap();
    bytes.extend_from_slice(&[0x10, 0x03, 30, 1, 198]).unwrap();
    bytes.extend_from_slice(&[0, 0]).unwrap();
    let pdu = LldpduRepr::parse(&bytes).unwrap();
    assert_eq!(pdu.capabilities, None);
    assert_eq!(pdu.cip_identification, None);
    assert!(pdu.addresses.is_empty());
}

#[test]
fn arbitrary_bytes_never_panic() {
    // A cheap deterministic sweep; the fuzz target covers the rest.
    let good = emitted(&local(30), false);
    let mut x = 0x1234_5678u32;
    for _ in 0..2000 {
        let mut b = good.clone();
        for _ in 0..4 {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            let i = (x as usize) % b.len();
            b[i] = (x >> 8) as u8;
        }
        let _ = LldpduRepr::parse(&b);
    }
}

#[test]
fn neighbor_mac_prefers_the_cip_mac_then_the_chassis_then_the_port() {
    // Chassis ID of subtype 7 (locally assigned), Port ID of subtype 3 (MAC address).
    let port_mac = [0x02, 0, 0, 0, 0, 0x33];
    let mut bytes = heapless::Vec::<u8, 64>::new();
    bytes
        .extend_from_slice(&[0x02, 0x04, 7, b'b', b'o', b'x'])
        .unwrap();
    bytes.extend_from_slice(&[0x04, 0x07, PORT_MAC]).unwrap();
    bytes.extend_from_slice(&port_mac).unwrap();
    bytes.extend_from_slice(&[0x06, 0x02, 0, 30]).unwrap();
    let pdu = LldpduRepr::parse(&bytes).unwrap();
    assert_eq!(pdu.neighbor_mac(), port_mac);
    // Without a MAC anywhere: all zero.
    let mut no_mac = bytes.clone();
    no_mac[6 + 2] = PORT_INTERFACE_NAME;
    assert_eq!(LldpduRepr::parse(&no_mac).unwrap().neighbor_mac(), [0; 6]);
    // The CIP MAC Address TLV comes first, before a Chassis ID of the MAC subtype.
    let own = emitted(&local(30), false);
    let mut pdu = LldpduRepr::parse(&own).unwrap();
    pdu.cip_mac = Some([0x02, 0, 0, 0, 0, 0x44]);
    assert_eq!(pdu.neighbor_mac(), [0x02, 0, 0, 0, 0, 0x44]);
}
