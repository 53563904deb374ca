//! The LLDP agent through the adapter's API: the LLDPDUs it sends (start, interval, change,
//! shutdown), the LLDP Data Table (0x10A) filled from received LLDPDUs and aged by their TTL,
//! and the LLDP Management object's (0x109) attributes with their Set rules and storage.

use std::cell::RefCell;
use std::net::Ipv4Addr;

use enip_stack::adapter::MAX_LLDPDU;
use enip_stack::nv::{AbStore, NvStore, RamFlash, SharedStore, IMAGE_SIZE, MAX_WRITE_SIZE};
use enip_stack::wire::lldp::{CipIdentification, LldpduRepr, LocalSystem};
use enip_stack::wire::Writer;
use enip_stack::{Adapter, Device, Instant, NetworkConfig};

mod common;
use common::TestDevice;

const SECOND: u64 = 1_000_000;
const OUR_MAC: [u8; 6] = [2, 0, 0, 0, 0, 2];

fn adapter() -> Adapter<TestDevice> {
    let net = NetworkConfig::new_static(
        Ipv4Addr::new(198, 18, 0, 2),
        Ipv4Addr::new(255, 255, 255, 0),
        OUR_MAC,
    );
    Adapter::new(TestDevice::new(), net, 7)
}

/// Runs one request on `class`/`instance`/`attribute` (0: none) and returns the general
/// status and the reply data.
fn call<D: Device>(
    a: &mut Adapter<D>,
    now: u64,
    service: u8,
    class: u16,
    instance: u8,
    attribute: u8,
    data: &[u8],
) -> (u8, Vec<u8>) {
    let [c0, c1] = class.to_le_bytes();
    let mut req = vec![service, 0, 0x21, 0, c0, c1, 0x24, instance];
    if attribute != 0 {
        req.extend_from_slice(&[0x30, attribute]);
    }
    req[1] = ((req.len() - 2) / 2) as u8;
    req.extend_from_slice(data);
    let mut reply = [0u8; 512];
    let n = a.execute(&req, Instant(now), &mut reply);
    let extra = usize::from(reply[3]) * 2;
    (reply[2], reply[4 + extra..n].to_vec())
}

fn get<D: Device>(a: &mut Adapter<D>, now: u64, class: u16, inst: u8, attr: u8) -> (u8, Vec<u8>) {
    call(a, now, 0x0E, class, inst, attr, &[])
}

fn set<D: Device>(a: &mut Adapter<D>, now: u64, class: u16, attr: u8, v: &[u8]) -> u8 {
    call(a, now, 0x10, class, 1, attr, v).0
}

/// The LLDPDU due at `now`, parsed into (TTL, system name).
fn sent<D: Device>(a: &mut Adapter<D>, now: u64) -> Option<(u16, Vec<u8>, Vec<u8>)> {
    let mut out = [0u8; MAX_LLDPDU];
    let n = a.lldp_transmit(Instant(now), &mut out);
    if n == 0 {
        return None;
    }
    let pdu = LldpduRepr::parse(&out[..n]).expect("our LLDPDU parses");
    assert_eq!(pdu.neighbor_mac(), OUR_MAC);
    let id = pdu
        .cip_identification
        .map(|i| i.vendor_id.to_le_bytes().to_vec());
    Some((
        pdu.ttl,
        pdu.system_name.unwrap_or(&[]).to_vec(),
        id.unwrap_or_default(),
    ))
}

/// A neighbour's LLDPDU: chassis `mac`, port "eth0", TTL `ttl`.
fn neighbour(mac: [u8; 6], ttl: u16) -> Vec<u8> {
    let l = LocalSystem {
        mac,
        port_id: b"eth0",
        ttl,
        system_name: b"switch",
        system_description: b"",
        ip: Ipv4Addr::new(198, 18, 0, 1),
        if_index: 3,
        identity: CipIdentification {
            vendor_id: 1,
            device_type: 12,
            product_code: 99,
            major_revision: 3,
            minor_revision: 1,
            serial_number: 0x0102_0304,
        },
    };
    let mut buf = [0u8; 512];
    let mut w = Writer::new(&mut buf);
    l.emit(&mut w).unwrap();
    w.written().to_vec()
}

#[test]
fn sends_at_start_every_interval_and_on_a_host_name_change() {
    let mut a = adapter();
    assert_eq!(a.lldp_deadline(), Some(Instant(0)));
    let (ttl, name, vendor) = sent(&mut a, 0).unwrap();
    assert_eq!((ttl, name.len()), (120, 0));
    assert_eq!(vendor, TestDevice::new().identity().vendor_id.to_le_bytes());
    assert_eq!(a.lldp_deadline(), Some(Instant(30 * SECOND)));
    assert!(sent(&mut a, 29 * SECOND).is_none());
    // TCP/IP attribute 6: announced a second after the last LLDPDU.
    assert_eq!(set(&mut a, 10 * SECOND, 0xF5, 6, b"\x05\x00cell7\x00"), 0);
    assert_eq!(a.lldp_deadline(), Some(Instant(SECOND)));
    assert_eq!(sent(&mut a, 10 * SECOND).unwrap().1, b"cell7");
    assert_eq!(a.lldp_deadline(), Some(Instant(40 * SECOND)));
    assert!(sent(&mut a, 40 * SECOND).is_some());
}

#[test]
fn management_attributes_and_set_rules() {
    let mut a = adapter();
    let m = 0x109;
    assert_eq!(get(&mut a, 0, m, 1, 1), (0, vec![2, 0, 3]));
    assert_eq!(get(&mut a, 0, m, 1, 2), (0, vec![30, 0]));
    assert_eq!(get(&mut a, 0, m, 1, 3), (0, vec![4]));
    assert_eq!(get(&mut a, 0, m, 1, 4), (0, vec![1, 0]));
    assert_eq!(get(&mut a, 0, m, 1, 5), (0, vec![0, 0, 0, 0]));
    let all = call(&mut a, 0, 0x01, m, 1, 0, &[]);
    assert_eq!(all, (0, vec![2, 0, 3, 30, 0, 4, 1, 0, 0, 0, 0, 0]));
    // Out of range 0x09, wrong size 0x13/0x15, read-only 0x0E; nothing changes.
    assert_eq!(set(&mut a, 0, m, 2, &[0, 0]), 0x09);
    assert_eq!(set(&mut a, 0, m, 2, &[0x11, 0x0E]), 0x09);
    assert_eq!(set(&mut a, 0, m, 3, &[0]), 0x09);
    assert_eq!(set(&mut a, 0, m, 3, &[101]), 0x09);
    assert_eq!(set(&mut a, 0, m, 1, &[3, 0, 3]), 0x09);
    assert_eq!(set(&mut a, 0, m, 1, &[2, 0, 7]), 0x09);
    assert_eq!(set(&mut a, 0, m, 2, &[5]), 0x13);
    assert_eq!(set(&mut a, 0, m, 3, &[5, 0]), 0x15);
    assert_eq!(set(&mut a, 0, m, 4, &[0, 0]), 0x0E);
    assert_eq!(set(&mut a, 0, m, 5, &[0, 0, 0, 0]), 0x0E);
    assert_eq!(get(&mut a, 0, m, 1, 2), (0, vec![30, 0]));
    // msgTxInterval 5 s, msgTxHold 2: TTL 10.
    sent(&mut a, 0).unwrap();
    assert_eq!(set(&mut a, 0, m, 2, &[5, 0]), 0);
    assert_eq!(set(&mut a, 0, m, 3, &[2]), 0);
    assert_eq!(sent(&mut a, SECOND).unwrap().0, 10);
    assert_eq!(a.lldp_deadline(), Some(Instant(6 * SECOND)));
    // Port bit off: one shutdown LLDPDU, then silence; received LLDPDUs are still taken in
    // (bit 0 governs reception).
    assert_eq!(set(&mut a, 2 * SECOND, m, 1, &[2, 0, 1]), 0);
    assert_eq!(sent(&mut a, 2 * SECOND).unwrap().0, 0);
    assert_eq!(a.lldp_deadline(), None);
    a.lldp_receive(&neighbour([2, 0, 0, 0, 0, 9], 60), Instant(3));
    assert_eq!(get(&mut a, 3, 0x10A, 0, 3), (0, vec![1, 0]));
    // Global bit off: received LLDPDUs are ignored.
    assert_eq!(set(&mut a, 3 * SECOND, m, 1, &[2, 0, 2]), 0);
    assert!(sent(&mut a, 3 * SECOND).is_none());
    a.lldp_receive(&neighbour([2, 0, 0, 0, 0, 8], 60), Instant(4));
    assert_eq!(get(&mut a, 4, 0x10A, 0, 3), (0, vec![1, 0]));
    assert_eq!(set(&mut a, 4 * SECOND, m, 1, &[2, 0, 3]), 0);
    assert_eq!(sent(&mut a, 4 * SECOND).unwrap().0, 10);
}

#[test]
fn settings_survive_a_restart_and_a_factory_reset_clears_them() {
    let store = store();
    let mut a = adapter();
    a.attach_store(leak(store)).unwrap();
    assert_eq!(set(&mut a, 0, 0x109, 2, &[7, 0]), 0);
    assert_eq!(set(&mut a, 0, 0x109, 3, &[9]), 0);
    // The same store under a new adapter: the settings are back.
    let mut b = adapter();
    b.attach_store(leak(store)).unwrap();
    assert_eq!(get(&mut b, 0, 0x109, 1, 2), (0, vec![7, 0]));
    assert_eq!(get(&mut b, 0, 0x109, 1, 3), (0, vec![9]));
    // Identity Reset type 1: factory defaults, also after the next start.
    assert_eq!(call(&mut b, 0, 0x05, 0x01, 1, 0, &[1]).0, 0);
    assert_eq!(get(&mut b, 0, 0x109, 1, 2), (0, vec![30, 0]));
    let mut c = adapter();
    c.attach_store(leak(store)).unwrap();
    assert_eq!(get(&mut c, 0, 0x109, 1, 3), (0, vec![4]));
}

/// A store that outlives the adapters of a test (each restart is a new adapter).
fn store() -> &'static RefCell<dyn NvStore> {
    Box::leak(Box::new(RefCell::new(AbStore::mount(RamFlash::<
        { MAX_WRITE_SIZE + IMAGE_SIZE },
    >::new()))))
}

/// A handle on `cell` for one adapter.
fn leak(cell: &'static RefCell<dyn NvStore>) -> &'static mut dyn NvStore {
    Box::leak(Box::new(SharedStore::new(cell)))
}

#[test]
fn data_table_lists_neighbours_ages_them_and_keeps_eight() {
    let mut a = adapter();
    let t = 0x10A;
    let mac = [0x02, 0x42, 0xC6, 0x12, 0x00, 0x01];
    a.lldp_receive(&neighbour(mac, 4), Instant(5 * SECOND));
    assert_eq!(get(&mut a, 5 * SECOND, t, 0, 3), (0, vec![1, 0]));
    assert_eq!(get(&mut a, 5 * SECOND, t, 1, 1), (0, vec![1, 0]));
    assert_eq!(get(&mut a, 5 * SECOND, t, 1, 2), (0, mac.to_vec()));
    assert_eq!(get(&mut a, 5 * SECOND, t, 1, 3), (0, b"\x04eth0".to_vec()));
    assert_eq!(get(&mut a, 5 * SECOND, t, 1, 4), (0, vec![4, 0]));
    assert_eq!(
        get(&mut a, 5 * SECOND, t, 1, 5),
        (0, vec![0x80, 0, 0x80, 0])
    );
    assert_eq!(
        get(&mut a, 5 * SECOND, t, 1, 6),
        (0, vec![1, 1, 0, 18, 198])
    );
    let id = vec![1, 0, 12, 0, 99, 0, 3, 1, 4, 3, 2, 1];
    assert_eq!(get(&mut a, 5 * SECOND, t, 1, 7), (0, id));
    assert_eq!(get(&mut a, 5 * SECOND, t, 1, 9), (0, vec![5, 0, 0, 0]));
    assert_eq!(get(&mut a, 5 * SECOND, 0x109, 1, 5), (0, vec![5, 0, 0, 0]));
    // The same LLDPDU again refreshes the TTL without a change.
    a.lldp_receive(&neighbour(mac, 4), Instant(8 * SECOND));
    assert_eq!(get(&mut a, 11 * SECOND, t, 1, 9), (0, vec![5, 0, 0, 0]));
    // Aged out at 8 + 4 s; the Last Change is that moment.
    assert_eq!(get(&mut a, 12 * SECOND, t, 1, 2).0, 0x16);
    assert_eq!(
        get(&mut a, 13 * SECOND, 0x109, 1, 5),
        (0, vec![12, 0, 0, 0])
    );
    // Eight neighbours are kept, a ninth is dropped; TTL 0 removes one at once.
    for i in 0..9u8 {
        let m = [2, 0, 0, 0, 1, i];
        a.lldp_receive(&neighbour(m, 60), Instant(20 * SECOND));
    }
    assert_eq!(get(&mut a, 20 * SECOND, t, 0, 3), (0, vec![8, 0]));
    assert_eq!(
        get(&mut a, 20 * SECOND, t, 8, 2),
        (0, vec![2, 0, 0, 0, 1, 7])
    );
    let gone = [2, 0, 0, 0, 1, 3];
    a.lldp_receive(&neighbour(gone, 0), Instant(21 * SECOND));
    assert_eq!(get(&mut a, 21 * SECOND, t, 4, 2).0, 0x16);
    assert_eq!(get(&mut a, 21 * SECOND, t, 0, 3), (0, vec![7, 0]));
    // Malformed LLDPDUs change nothing.
    a.lldp_receive(&[0x02, 0x07, 4, 1, 2], Instant(22 * SECOND));
    assert_eq!(get(&mut a, 22 * SECOND, t, 0, 3), (0, vec![7, 0]));
    assert_eq!(a.objects().lldp.discarded, 1);
}

#[test]
fn shutdown_lldpdu_on_demand_only_while_lldp_transmits() {
    let mut a = adapter();
    let mut out = [0u8; MAX_LLDPDU];
    let n = a.lldp_shutdown(&mut out);
    let pdu = LldpduRepr::parse(&out[..n]).expect("the shutdown LLDPDU parses");
    assert_eq!((pdu.ttl, pdu.neighbor_mac()), (0, OUR_MAC));
    assert_eq!(pdu.system_name, None);
    // It leaves the schedule alone: the first LLDPDU is still due at start.
    assert_eq!(a.lldp_deadline(), Some(Instant(0)));
    assert_eq!(set(&mut a, 0, 0x109, 1, &[2, 0, 2]), 0);
    assert_eq!(a.lldp_shutdown(&mut out), 0);
}
