//! The firmware link task's look at every received Ethernet frame (`link::fuzzing::inspect`,
//! feature `fuzzing`) for an adapter at 198.18.0.2: an O->T datagram's payload range lies
//! inside the frame of an IPv4 frame, a sender comes with the frame's source MAC address,
//! and an ARP sender is the one the stack's own ARP reader (Address Conflict Detection)
//! finds in the same frame. Then the input, read as 10-byte (IPv4 address, MAC) pairs, is
//! learned by the link task's neighbour table, checked against a model: the last MAC of
//! each host, the least recently learned one giving way when the table is full.
#![no_main]

use std::net::Ipv4Addr;

use enip_firmware::link::fuzzing::{inspect, NeighborTable, NEIGHBORS};
use enip_stack::acd::Arp;
use libfuzzer_sys::fuzz_target;

const ME: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 2);

fuzz_target!(|data: &[u8]| {
    let (sender, o_t) = inspect(data, ME);
    if let Some((_, range)) = &o_t {
        assert!(
            range.start <= range.end && range.end <= data.len(),
            "{range:?}"
        );
        assert_eq!(data.get(12..14), Some(&[0x08, 0x00][..]), "O->T not IPv4");
    }
    if let Some((ip, mac)) = sender {
        assert_eq!(
            data.get(6..12),
            Some(&mac[..]),
            "sender MAC not the frame's"
        );
        if data.get(12..14) == Some(&[0x08, 0x06][..]) {
            let arp = Arp::from_frame(data).expect("the stack reads the same ARP");
            assert_eq!(
                (arp.sender_ip, arp.sender_mac, arp.target_ip),
                (ip, mac, ME)
            );
        }
    }

    let mut table = NeighborTable::default();
    // Model: (ip, mac, learned at), at most NEIGHBORS entries.
    let mut model: Vec<(Ipv4Addr, [u8; 6], usize)> = Vec::new();
    for (step, pair) in data.chunks_exact(10).enumerate() {
        let ip = Ipv4Addr::new(pair[0], pair[1], pair[2], pair[3]);
        let mac: [u8; 6] = pair[4..].try_into().expect("6 bytes");
        table.learn(ip, mac);
        if let Some(e) = model.iter_mut().find(|e| e.0 == ip) {
            *e = (ip, mac, step);
        } else if model.len() < NEIGHBORS {
            model.push((ip, mac, step));
        } else if let Some(oldest) = model.iter_mut().min_by_key(|e| e.2) {
            *oldest = (ip, mac, step);
        }
        for (ip, mac, _) in &model {
            assert_eq!(table.get(*ip), Some(*mac), "{ip}");
        }
    }
});
