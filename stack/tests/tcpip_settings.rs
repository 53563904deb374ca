//! The TCP/IP object's settable, stored attributes (3, 5, 6, 8, 9, 10, 11, 13): the CIP rules
//! of a Set, status and capability bits, and the settings surviving a restart through an
//! `NvStore`.

mod common;

use std::cell::RefCell;
use std::net::Ipv4Addr;
use std::rc::Rc;

use common::*;
use enip_stack::cip::General;
use enip_stack::nv::{
    key, AbStore, CutFlash, Flash, NvError, NvStore, RamFlash, IMAGE_SIZE, MAX_WRITE_SIZE,
};
use enip_stack::objects::TcpIpState;
use enip_stack::wire::epath::{LogicalType, SegmentRepr};

/// The flash of most tests: one copy's room per sector, in RAM.
type SmallFlash = RamFlash<{ MAX_WRITE_SIZE + IMAGE_SIZE }>;

/// A store the test keeps a handle on while the adapter uses it; `fail` makes writes fail.
struct Shared<F: Flash = SmallFlash>(Rc<RefCell<AbStore<F>>>, Rc<RefCell<bool>>);

impl<F: Flash> Clone for Shared<F> {
    fn clone(&self) -> Self {
        Shared(self.0.clone(), self.1.clone())
    }
}

impl<F: Flash> NvStore for Shared<F> {
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
    fn begin(&mut self) -> Result<(), NvError> {
        self.0.borrow_mut().begin()
    }
    fn commit(&mut self) -> Result<(), NvError> {
        self.0.borrow_mut().commit()
    }
    fn abandon(&mut self) {
        self.0.borrow_mut().abandon()
    }
}

fn shared() -> Shared {
    shared_on(SmallFlash::new())
}

fn shared_on<F: Flash>(flash: F) -> Shared<F> {
    Shared(
        Rc::new(RefCell::new(AbStore::mount(flash))),
        Rc::new(RefCell::new(false)),
    )
}

/// A harness whose adapter keeps its settings in `store`.
fn harness<F: Flash + 'static>(store: &Shared<F>) -> Harness {
    let mut h = Harness::new();
    h.adapter
        .attach_store(Box::leak(Box::new(store.clone())))
        .unwrap();
    h
}

/// Identity instance 1, for its Reset service.
const IDENTITY_INSTANCE: [SegmentRepr<'static>; 2] = [
    SegmentRepr::Logical(LogicalType::Class, 1),
    SegmentRepr::Logical(LogicalType::Instance, 1),
];

fn tcpip(attribute: u32) -> [SegmentRepr<'static>; 3] {
    [
        SegmentRepr::Logical(LogicalType::Class, 0xF5),
        SegmentRepr::Logical(LogicalType::Instance, 1),
        SegmentRepr::Logical(LogicalType::Attribute, attribute),
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
    // Configuration settable, change requires reset; a DHCP client once the runtime says it
    // has one.
    assert_eq!(get(&mut h, 2), 0x50u32.to_le_bytes());
    h.adapter.set_dhcp_client(true);
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
    assert_eq!(status(&h.request(0x05, &IDENTITY_INSTANCE, &[1])).0, 0);
    assert_eq!(TcpIpState::stored(&mut *store.0.borrow_mut()), Ok(None));
}

#[test]
fn a_reset_the_device_refuses_keeps_the_stored_settings() {
    let store = shared();
    let mut h = harness(&store);
    assert_eq!(set(&mut h, 6, &[4, 0, b'k', b'e', b'e', b'p']), 0);
    h.adapter.device_mut().reset_refusal = Some(General::DeviceStateConflict.into());
    assert_eq!(status(&h.request(0x05, &IDENTITY_INSTANCE, &[1])).0, 0x10);
    let st = TcpIpState::stored(&mut *store.0.borrow_mut()).unwrap();
    assert!(st.is_some(), "the stored settings survive a refused Reset");
    assert_eq!(&get(&mut h, 6)[..6], &[4, 0, b'k', b'e', b'e', b'p']);
    // Accepted, the same Reset restores the factory settings.
    h.adapter.device_mut().reset_refusal = None;
    assert_eq!(status(&h.request(0x05, &IDENTITY_INSTANCE, &[1])).0, 0);
    assert_eq!(TcpIpState::stored(&mut *store.0.borrow_mut()), Ok(None));
}

/// A harness whose device keeps its own settings in `store` (record `PROFILE_BASE`) beside
/// the adapter's TCP/IP settings.
fn harness_with_device_settings<F: Flash + 'static>(store: &Shared<F>) -> Harness {
    let mut h = harness(store);
    h.adapter.device_mut().settings = Some(Box::new(store.clone()));
    h
}

/// Saves device settings and a host name (TCP/IP attribute 6) through `h`.
fn save_both(h: &mut Harness, store: &Shared<impl Flash>) {
    store
        .0
        .borrow_mut()
        .write(key::PROFILE_BASE, b"tuned")
        .unwrap();
    assert_eq!(set(h, 6, &[4, 0, b'k', b'e', b'e', b'p']), 0);
}

/// What a restart finds on the flash of `store`: the device's settings, the TCP/IP settings.
fn after_restart(store: &Shared<CutFlash>) -> (bool, bool) {
    let mut flash = store.0.borrow().flash().clone();
    flash.restore();
    let mut again = AbStore::mount(flash);
    let device = again
        .read(key::PROFILE_BASE, &mut [0; 16])
        .unwrap()
        .is_some();
    (device, TcpIpState::stored(&mut again).unwrap().is_some())
}

#[test]
fn a_factory_reset_removes_every_setting_in_one_save() {
    let store = shared_on(CutFlash::new());
    let mut h = harness_with_device_settings(&store);
    save_both(&mut h, &store);
    assert_eq!(after_restart(&store), (true, true));
    let before = store.0.borrow().sequence();
    assert_eq!(status(&h.request(0x05, &IDENTITY_INSTANCE, &[1])).0, 0);
    assert_eq!(store.0.borrow().sequence(), before + 1, "one save");
    assert_eq!(after_restart(&store), (false, false));
    // A device that removes its settings and then refuses the Reset loses none of them,
    // in RAM or on the flash.
    save_both(&mut h, &store);
    h.adapter.device_mut().reset_refusal = Some(General::DeviceStateConflict.into());
    let before = store.0.borrow().sequence();
    assert_eq!(status(&h.request(0x05, &IDENTITY_INSTANCE, &[1])).0, 0x10);
    assert_eq!(store.0.borrow().sequence(), before, "nothing saved");
    assert_eq!(after_restart(&store), (true, true));
    let kept = store.0.borrow_mut().read(key::PROFILE_BASE, &mut [0; 16]);
    assert_eq!(kept, Ok(Some(5)));
    assert_eq!(&get(&mut h, 6)[..6], &[4, 0, b'k', b'e', b'e', b'p']);
}

#[test]
fn every_power_cut_during_a_factory_reset_keeps_every_setting_or_none() {
    let prepared = shared_on(CutFlash::new());
    save_both(&mut harness_with_device_settings(&prepared), &prepared);
    let mut before = prepared.0.borrow().flash().clone();
    before.restore();
    let mut cut = 0;
    loop {
        let mut flash = before.clone();
        flash.cut_after(cut);
        let store = shared_on(flash);
        let mut h = harness_with_device_settings(&store);
        let answer = status(&h.request(0x05, &IDENTITY_INSTANCE, &[1])).0;
        let seen = after_restart(&store);
        if answer == 0 {
            assert_eq!(seen, (false, false), "no cut after {cut} steps");
            break;
        }
        assert_eq!(answer, 0x19, "cut after {cut}");
        // Never the device at factory defaults with the old address, or the reverse.
        assert_eq!(seen, (true, true), "cut after {cut}");
        cut += 1;
        assert!(cut < 1000, "the Reset never completes");
    }
    // One save of the empty copy: the erase, 12 bytes of body (3 units), the commit word.
    assert_eq!(cut, 5, "steps of the Reset");
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
fn ttl_and_multicast_config_apply_at_the_next_start_and_status_bit_4_says_so() {
    let store = shared();
    let mut h = harness(&store);
    let status = |h: &mut Harness| u32::from_le_bytes(get(h, 1).try_into().unwrap());
    assert_eq!(status(&mut h) & 0x10, 0);
    assert_eq!(set(&mut h, 8, &[7]), 0);
    let mcast = [1, 0, 4, 0, 0, 3, 192, 239];
    assert_eq!(set(&mut h, 9, &mcast), 0);
    // Read back as set, Mcast Pending on, the values in use those of the start.
    assert_eq!((get(&mut h, 8), get(&mut h, 9)), (vec![7], mcast.to_vec()));
    assert_eq!(status(&mut h) & 0x10, 0x10);
    assert_eq!(h.adapter.multicast_ttl(), 1);
    let in_use = h
        .adapter
        .objects()
        .tcpip
        .multicast_in_use(h.adapter.device(), h.adapter.network());
    assert_eq!(in_use, (Ipv4Addr::new(239, 192, 1, 32), 1));
    // A refused Set leaves the bit as it was.
    drop(h);
    let mut h = harness(&store);
    assert_eq!(status(&mut h) & 0x10, 0);
    assert_eq!(set(&mut h, 8, &[0]), 0x09);
    assert_eq!(status(&mut h) & 0x10, 0);
    // After the restart: in use, nothing pending.
    assert_eq!(h.adapter.multicast_ttl(), 7);
    let in_use = h
        .adapter
        .objects()
        .tcpip
        .multicast_in_use(h.adapter.device(), h.adapter.network());
    assert_eq!(in_use, (Ipv4Addr::new(239, 192, 3, 0), 7));
}

#[test]
fn safety_network_number_and_quick_connect_are_not_supported_alone() {
    let mut h = harness(&shared());
    for attribute in [7, 12] {
        let (g, _, _) = status(&h.request(0x0E, &tcpip(attribute), &[]));
        assert_eq!(g, 0x14, "Get {attribute}");
        assert_eq!(set(&mut h, attribute, &[0]), 0x14, "Set {attribute}");
    }
    // In a list: 0x14 for 7, the value of 13 beside it.
    let mut path = tcpip(1).to_vec();
    path.pop();
    let (g, _, d) = status(&h.request(0x03, &path, &[2, 0, 7, 0, 13, 0]));
    assert_eq!(
        (g, d),
        (0x0A, vec![2, 0, 7, 0, 0x14, 0, 13, 0, 0, 0, 120, 0])
    );
}

#[test]
fn host_and_domain_names_are_rfc_1123_labels() {
    let mut h = harness(&shared());
    let string = |name: &[u8]| {
        let mut v = (name.len() as u16).to_le_bytes().to_vec();
        v.extend(name);
        if name.len() % 2 == 1 {
            v.push(0);
        }
        v
    };
    for bad in [&b"-abc"[..], b"abc-", b"abc.def", b"a_b", &[b'a'; 64]] {
        assert_eq!(set(&mut h, 6, &string(bad)), 0x09, "host name {bad:?}");
    }
    for good in [&b""[..], b"a", b"press-7", b"7", &[b'a'; 63]] {
        assert_eq!(set(&mut h, 6, &string(good)), 0, "host name {good:?}");
        assert_eq!(get(&mut h, 6), string(good));
    }
    for bad in [
        &b"."[..],
        b"..",
        b".abc",
        b"abc.",
        b"a..b",
        b"-a.b",
        b"a.b-",
    ] {
        let value = interface([198, 18, 0, 9], MASK, [0; 4], bad);
        assert_eq!(set(&mut h, 5, &value), 0x09, "domain {bad:?}");
    }
    for good in [&b""[..], b"plant", b"line-2.plant.example"] {
        let value = interface([198, 18, 0, 9], MASK, [0; 4], good);
        assert_eq!(set(&mut h, 5, &value), 0, "domain {good:?}");
    }
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
    // DHCP without a DHCP client, DNS Enable without a DNS client, another method: 0x09.
    for control in [2u32, 0x10, 0x12, 1, 3] {
        assert_eq!(set(&mut h, 3, &control.to_le_bytes()), 0x09, "{control:#x}");
    }
    // Under DHCP the address is not settable: object state conflict.
    h.adapter.set_dhcp_client(true);
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

#[test]
fn acd_attributes_report_the_runtime_and_survive_a_restart() {
    use enip_stack::acd::{Activity, Arp, ArpFrame, LastConflict, ARP_FRAME_LEN};
    let store = shared();
    let mut h = harness(&store);
    // Not capable until the runtime that runs detection says so (a kernel's sockets never).
    assert_eq!(get(&mut h, 2), 0x50u32.to_le_bytes());
    h.adapter.set_acd_capable();
    assert_eq!(get(&mut h, 2), 0xD0u32.to_le_bytes());
    // SelectAcd defaults on; only 0 and 1 are taken; attribute 11 starts all zero.
    assert_eq!(get(&mut h, 10), [1]);
    assert_eq!(set(&mut h, 10, &[2]), General::InvalidAttributeValue as u8);
    assert_eq!(set(&mut h, 10, &[0]), 0);
    assert!(!h.adapter.acd_selected());
    assert_eq!(get(&mut h, 11), [0; 35]);
    // A conflict: status bits 6 and 7, attribute 11 with the remote MAC and the PDU.
    let other = [2, 0x11, 0x22, 0x33, 0x44, 0x55];
    let mut frame = [0u8; ARP_FRAME_LEN];
    ArpFrame::Announcement.write(other, ADAPTER_IP, &mut frame);
    let arp = Arp::from_frame(&frame).unwrap();
    h.adapter
        .record_acd_conflict(LastConflict::of(Activity::Probe, &arp));
    h.adapter.set_acd_status(true, true);
    assert_eq!(get(&mut h, 1), 0xC1u32.to_le_bytes());
    let last = get(&mut h, 11);
    assert_eq!((last[0], &last[1..7]), (1, &other[..]));
    assert_eq!(last[7..], frame[14..]);
    // After a restart both attributes read as stored; the status bits start clear.
    drop(h);
    let mut h = harness(&store);
    assert_eq!(get(&mut h, 10), [0]);
    assert_eq!(get(&mut h, 11), last);
    assert_eq!(get(&mut h, 1), 1u32.to_le_bytes());
    // Attribute 11 is cleared with zeros only (it records what the device saw).
    assert_eq!(set(&mut h, 11, &last), General::InvalidAttributeValue as u8);
    assert_eq!(set(&mut h, 11, &[0; 34]), General::NotEnoughData as u8);
    assert_eq!(set(&mut h, 11, &[0; 35]), 0);
    drop(h);
    let mut h = harness(&store);
    assert_eq!(get(&mut h, 11), [0; 35]);
    // Skipping detection in one run (a test rig's `--acd off`) stores nothing.
    assert_eq!(set(&mut h, 10, &[1]), 0);
    h.adapter.skip_acd();
    assert!(!h.adapter.acd_selected());
    drop(h);
    assert!(harness(&store).adapter.acd_selected());
}
