//! The TCP/IP object's settable, stored attributes (3, 5, 6, 8, 9, 13): the CIP rules of a Set,
//! status and capability bits, and the settings surviving a restart through an `NvStore`.

mod common;

use std::cell::RefCell;
use std::net::Ipv4Addr;
use std::rc::Rc;

use common::*;
use enip_stack::cip::tcpip::TcpIpState;
use enip_stack::cip::General;
use enip_stack::nv::{AbStore, NvError, NvStore, RamFlash, IMAGE_SIZE, MAX_WRITE_SIZE};
use enip_stack::wire::epath::{LogicalType, Segment};

type Flash = RamFlash<{ MAX_WRITE_SIZE + IMAGE_SIZE }>;

/// A store the test keeps a handle on while the adapter uses it; `fail` makes writes fail.
#[derive(Clone)]
struct Shared(Rc<RefCell<AbStore<Flash>>>, Rc<RefCell<bool>>);

impl NvStore for Shared {
    fn read(&mut self, key: u16, buf: &mut [u8]) -> Result<Option<usize>, NvError> {
        self.0.borrow_mut().read(key, buf)
    }
    fn write(&mut self, key: u16, value: &[u8]) -> Result<(), NvError> {
        if *self.1.borrow() {
            return Err(NvError::Flash);
        }
        self.0.borrow_mut().write(key, value)
    }
    fn remove(&mut self, key: u16) -> Result<(), NvError> {
        self.0.borrow_mut().remove(key)
    }
}

fn shared() -> Shared {
    Shared(
        Rc::new(RefCell::new(AbStore::mount(Flash::new()))),
        Rc::new(RefCell::new(false)),
    )
}

/// A harness whose adapter keeps its settings in `store`.
fn harness(store: &Shared) -> Harness {
    let mut h = Harness::new();
    h.adapter
        .attach_store(Box::leak(Box::new(store.clone())))
        .unwrap();
    h
}

fn tcpip(attribute: u32) -> [Segment<'static>; 3] {
    [
        Segment::Logical(LogicalType::Class, 0xF5),
        Segment::Logical(LogicalType::Instance, 1),
        Segment::Logical(LogicalType::Attribute, attribute),
    ]
}

/// An attribute 5 value.
fn interface(ip: [u8; 4], mask: [u8; 4], gw: [u8; 4], domain: &[u8]) -> Vec<u8> {
    let mut v = Vec::new();
    for a in [ip, mask, gw, [198, 18, 0, 53], [0; 4]] {
        v.extend(u32::from(Ipv4Addr::from(a)).to_le_bytes());
    }
    v.extend((domain.len() as u16).to_le_bytes());
    v.extend(domain);
    if domain.len() % 2 == 1 {
        v.push(0);
    }
    v
}

const MASK: [u8; 4] = [255, 255, 255, 0];

fn get(h: &mut Harness, attribute: u32) -> Vec<u8> {
    let (g, _, d) = status(&h.request(0x0E, &tcpip(attribute), &[]));
    assert_eq!(g, 0);
    d
}

fn set(h: &mut Harness, attribute: u32, value: &[u8]) -> u8 {
    status(&h.request(0x10, &tcpip(attribute), value)).0
}

#[test]
fn capability_and_status_tell_the_truth() {
    let store = shared();
    let mut h = harness(&store);
    // DHCP client, configuration settable, change requires reset.
    assert_eq!(get(&mut h, 2), 0x54u32.to_le_bytes());
    assert_eq!(get(&mut h, 1), 1u32.to_le_bytes());
    let value = interface([198, 18, 0, 9], MASK, [198, 18, 0, 1], b"plant.example");
    assert_eq!(value.len(), 20 + 2 + 14);
    assert_eq!(set(&mut h, 5, &value), 0);
    // Pending until the next reset; attribute 5 reads back what was set.
    assert_eq!(get(&mut h, 1), 0x21u32.to_le_bytes());
    assert_eq!(get(&mut h, 5), value);
    // The address in use does not change before the reset.
    assert_eq!(h.adapter.network().ip, ADAPTER_IP);
}

#[test]
fn settings_survive_a_restart() {
    let store = shared();
    let mut h = harness(&store);
    let value = interface([198, 18, 0, 9], MASK, [198, 18, 0, 1], b"");
    assert_eq!(set(&mut h, 5, &value), 0);
    assert_eq!(set(&mut h, 6, &[5, 0, b'p', b'r', b'e', b's', b's', 0]), 0);
    assert_eq!(set(&mut h, 13, &[30, 0]), 0);
    drop(h);
    let flash = store.0.borrow().flash().clone();
    let mut again = AbStore::mount(flash);
    let st = TcpIpState::stored(&mut again).unwrap().unwrap();
    let iface = st.static_interface().unwrap();
    assert_eq!(iface.ip, Ipv4Addr::new(198, 18, 0, 9));
    assert_eq!(iface.gateway, Ipv4Addr::new(198, 18, 0, 1));
    let mut h = harness(&store);
    assert_eq!(h.adapter.objects().tcpip.inactivity_timeout_s, 30);
    assert_eq!(&get(&mut h, 6)[..7], &[5, 0, b'p', b'r', b'e', b's', b's']);
    assert_eq!(get(&mut h, 1), 1u32.to_le_bytes());
    // Factory defaults (Identity Reset type 1) remove them.
    let identity = [
        Segment::Logical(LogicalType::Class, 1),
        Segment::Logical(LogicalType::Instance, 1),
    ];
    assert_eq!(status(&h.request(0x05, &identity, &[1])).0, 0);
    assert_eq!(TcpIpState::stored(&mut *store.0.borrow_mut()), Ok(None));
}

#[test]
fn a_reset_the_device_refuses_keeps_the_stored_settings() {
    let store = shared();
    let mut h = harness(&store);
    assert_eq!(set(&mut h, 6, &[4, 0, b'k', b'e', b'e', b'p']), 0);
    h.adapter.device_mut().reset_refusal = Some(General::DeviceStateConflict.into());
    let identity = [
        Segment::Logical(LogicalType::Class, 1),
        Segment::Logical(LogicalType::Instance, 1),
    ];
    assert_eq!(status(&h.request(0x05, &identity, &[1])).0, 0x10);
    let st = TcpIpState::stored(&mut *store.0.borrow_mut()).unwrap();
    assert!(st.is_some(), "the stored settings survive a refused Reset");
    assert_eq!(&get(&mut h, 6)[..6], &[4, 0, b'k', b'e', b'e', b'p']);
    // Accepted, the same Reset restores the factory settings.
    h.adapter.device_mut().reset_refusal = None;
    assert_eq!(status(&h.request(0x05, &identity, &[1])).0, 0);
    assert_eq!(TcpIpState::stored(&mut *store.0.borrow_mut()), Ok(None));
}

#[test]
fn ttl_and_multicast_config_survive_a_restart() {
    let store = shared();
    let mut h = harness(&store);
    let mcast = [1, 0, 4, 0, 0, 3, 192, 239];
    assert_eq!(set(&mut h, 8, &[7]), 0);
    assert_eq!(set(&mut h, 9, &mcast), 0);
    drop(h);
    let mut h = harness(&store);
    assert_eq!(get(&mut h, 8), vec![7]);
    assert_eq!(get(&mut h, 9), mcast.to_vec());
    // A refused store undoes the Set.
    *store.1.borrow_mut() = true;
    assert_eq!(set(&mut h, 8, &[9]), 0x19);
    assert_eq!(get(&mut h, 8), vec![7]);
}

#[test]
fn attribute_5_rules() {
    let store = shared();
    let mut h = harness(&store);
    let ok = interface([198, 18, 0, 9], MASK, [0; 4], b"a");
    for (ip, mask, gw) in [
        ([0, 0, 0, 0], MASK, [0; 4]),
        ([127, 0, 0, 1], MASK, [0; 4]),
        ([239, 1, 2, 3], MASK, [0; 4]),
        ([198, 18, 0, 255], MASK, [0; 4]),
        ([198, 18, 0, 9], [255, 0, 255, 0], [0; 4]),
        ([198, 18, 0, 9], MASK, [198, 18, 7, 1]),
    ] {
        assert_eq!(
            set(&mut h, 5, &interface(ip, mask, gw, b"")),
            0x09,
            "{ip:?}"
        );
    }
    assert_eq!(
        set(&mut h, 5, &interface([198, 18, 0, 9], MASK, [0; 4], b"a b")),
        0x09
    );
    // Value lengths: 20 bytes and a padded STRING of at most 48 characters.
    assert_eq!(set(&mut h, 5, &ok[..20]), 0x13);
    assert_eq!(set(&mut h, 5, &ok[..23]), 0x13);
    assert_eq!(set(&mut h, 5, &[ok.as_slice(), &[0]].concat()), 0x15);
    let long = interface([198, 18, 0, 9], MASK, [0; 4], &[b'a'; 49]);
    assert_eq!(set(&mut h, 5, &long), 0x09);
    assert_eq!(get(&mut h, 1), 1u32.to_le_bytes());
    // Under DHCP the address is not settable: object state conflict.
    assert_eq!(set(&mut h, 3, &2u32.to_le_bytes()), 0);
    assert_eq!(set(&mut h, 5, &ok), 0x0C);
    assert_eq!(set(&mut h, 3, &0u32.to_le_bytes()), 0);
    assert_eq!(set(&mut h, 5, &ok), 0);
    // In Set_Attribute_List attribute 5 is followed by the next entry.
    let mut list = vec![2, 0, 5, 0];
    list.extend(interface([198, 18, 0, 10], MASK, [0; 4], b"abc"));
    list.extend([13, 0, 60, 0]);
    let (g, _, d) = status(&h.request(0x04, &tcpip(1)[..2], &list));
    assert_eq!((g, d), (0, vec![2, 0, 5, 0, 0, 0, 13, 0, 0, 0]));
    assert_eq!(h.adapter.objects().tcpip.inactivity_timeout_s, 60);
}

#[test]
fn a_failed_store_is_0x19_and_changes_nothing() {
    let store = shared();
    let mut h = harness(&store);
    *store.1.borrow_mut() = true;
    let value = interface([198, 18, 0, 9], MASK, [0; 4], b"");
    assert_eq!(set(&mut h, 5, &value), 0x19);
    assert_eq!(set(&mut h, 13, &[30, 0]), 0x19);
    assert_eq!(h.adapter.objects().tcpip.inactivity_timeout_s, 120);
    assert_eq!(get(&mut h, 1), 1u32.to_le_bytes());
    // Attribute 8 is stored as well.
    assert_eq!(set(&mut h, 8, &[4]), 0x19);
    assert_eq!(get(&mut h, 8), vec![1]);
}

#[test]
fn without_a_store_settings_last_until_power_off() {
    let mut h = Harness::new();
    let value = interface([198, 18, 0, 9], MASK, [0; 4], b"");
    assert_eq!(set(&mut h, 5, &value), 0);
    assert_eq!(get(&mut h, 5), value);
}
