//! The CIP Security objects (feature `cip-security`): off until the runtime turns them on;
//! Get_Attributes_All of each; the configuration sequence (Begin_Config, Sets, Apply_Config,
//! End_Config) with its state machine and statuses; Certificate Management Create / Delete /
//! Verify_Certificate; the ListIdentity CIP Security item; the settings surviving a restart.
#![cfg(feature = "cip-security")]

mod common;

use common::*;
use enip_stack::nv::{AbStore, NvError, NvStore, RamFlash, IMAGE_SIZE, MAX_WRITE_SIZE};
use enip_stack::objects::security::{CertStatus, ObjectMode};
use enip_stack::originator;
use enip_stack::time::{Duration, Instant};
use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use enip_stack::SocketId;
use std::cell::RefCell;
use std::rc::Rc;

type SmallFlash = RamFlash<{ MAX_WRITE_SIZE + IMAGE_SIZE }>;

/// A store the test keeps a handle on; writes fail while `.1` is set.
#[derive(Clone)]
struct Shared(Rc<RefCell<AbStore<SmallFlash>>>, Rc<RefCell<bool>>);

fn shared() -> Shared {
    Shared(
        Rc::new(RefCell::new(AbStore::mount(SmallFlash::new()))),
        Rc::new(RefCell::new(false)),
    )
}

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

/// An adapter with the security objects on, started with `store`.
fn start(store: &Shared) -> Harness {
    let mut h = Harness::new();
    h.adapter
        .attach_store(Box::leak(Box::new(store.clone())))
        .unwrap();
    h.adapter.enable_security(true);
    h
}

fn path(class: u32, instance: u32, attribute: Option<u32>) -> Vec<SegmentRepr<'static>> {
    let mut p = vec![
        SegmentRepr::Logical(LogicalType::Class, class),
        SegmentRepr::Logical(LogicalType::Instance, instance),
    ];
    p.extend(attribute.map(|a| SegmentRepr::Logical(LogicalType::Attribute, a)));
    p
}

/// General status, extended status words and data.
fn call(
    h: &mut Harness,
    service: u8,
    class: u32,
    instance: u32,
    data: &[u8],
) -> (u8, Vec<u16>, Vec<u8>) {
    status(&h.request(service, &path(class, instance, None), data))
}

fn get(h: &mut Harness, class: u32, attribute: u32) -> (u8, Vec<u8>) {
    let (g, _, d) = status(&h.request(0x0E, &path(class, 1, Some(attribute)), &[]));
    (g, d)
}

fn set(h: &mut Harness, class: u32, attribute: u32, value: &[u8]) -> (u8, Vec<u16>) {
    let (g, ext, _) = status(&h.request(0x10, &path(class, 1, Some(attribute)), value));
    (g, ext)
}

/// The items of a ListIdentity reply: (type, data).
fn list_identity(h: &mut Harness) -> Vec<(u16, Vec<u8>)> {
    let mut request = [0u8; 24];
    request[0] = 0x63;
    let reply = h.tcp(&request);
    let mut items = Vec::new();
    let mut at = 26;
    for _ in 0..u16::from_le_bytes([reply[24], reply[25]]) {
        let kind = u16::from_le_bytes([reply[at], reply[at + 1]]);
        let len = usize::from(u16::from_le_bytes([reply[at + 2], reply[at + 3]]));
        items.push((kind, reply[at + 4..at + 4 + len].to_vec()));
        at += 4 + len;
    }
    assert_eq!(at, reply.len());
    items
}

/// A path (with its USINT size) to Certificate Management instance `i`, as a list of one.
fn cert_list(i: u8) -> Vec<u8> {
    vec![1, 2, 0x20, 0x5F, 0x24, i]
}

#[test]
fn off_until_the_runtime_turns_the_objects_on() {
    let mut h = Harness::new();
    for class in [0x5D, 0x5E, 0x5F] {
        assert_eq!(get(&mut h, class, 1).0, 0x05, "class {class:#x}");
    }
    let items = list_identity(&mut h);
    assert_eq!(items.len(), 1);
    assert_eq!(get_class(&mut h, 0xF5, 1, 14).0, 0x14);
    h.adapter.enable_security(false);
    let items = list_identity(&mut h);
    assert_eq!(items[1], (0x86, vec![0x02, 0x00, 0, 0, 0b0111]));
    h.adapter.enable_security(true);
    assert_eq!(list_identity(&mut h)[1].1[4], 0b1111);
}

#[test]
fn get_attributes_all_of_each_object_in_factory_state() {
    let mut h = start(&shared());
    assert_eq!(
        call(&mut h, 0x01, 0x5D, 1, &[]),
        (0, vec![], vec![0, 0x02, 0x00])
    );
    let eip = vec![
        0, // state
        0, 0, 0, 0, // capability flags
        4, 0xC0, 0x23, 0xC0, 0x24, 0xC0, 0x2B, 0xC0, 0x2C, // available
        2, 0xC0, 0x23, 0xC0, 0x24, // allowed
        0,    // pre-shared keys
        1, 2, 0x20, 0x5F, 0x24, 1, // active device certificate: instance 1
        0, // trusted authorities
        0, // revocation list
        0, 0, 0, // verify client, send chain, check expiration
    ];
    assert_eq!(call(&mut h, 0x01, 0x5E, 1, &[]), (0, vec![], eip));
    let name = b"Default Device Certificate";
    let mut cert = vec![name.len() as u8];
    cert.extend_from_slice(name);
    cert.extend_from_slice(&[1, 0, 0, 0, 0, 0]);
    assert_eq!(call(&mut h, 0x01, 0x5F, 1, &[]), (0, vec![], cert));
    // The runtime's verdict on the certificates shows in the state and the statuses.
    assert!(h
        .adapter
        .set_certificate_status(1, CertStatus::Verified, CertStatus::NotVerified));
    assert_eq!(get(&mut h, 0x5F, 2), (0, vec![3]));
    assert_eq!(get(&mut h, 0x5F, 3), (0, vec![1, 0]));
    assert_eq!(call(&mut h, 0x4C, 0x5F, 1, &[1, 0]).0, 0);
    assert_eq!(call(&mut h, 0x4C, 0x5F, 1, &[2, 0]).0, 0x0C);
    assert_eq!(call(&mut h, 0x4C, 0x5F, 1, &[3, 0]).0, 0x20);
    assert_eq!(call(&mut h, 0x4C, 0x5F, 1, &[1]).0, 0x13);
    // TCP/IP attribute 14 (IANA Port Admin) lists 2221/tcp open.
    let (g, ports) = get_class(&mut h, 0xF5, 1, 14);
    assert_eq!((g, ports[0]), (0, 4));
    let tls = b"\x0fEtherNet/IP TLS\xad\x08\x06\x01\x00";
    assert!(ports.windows(tls.len()).any(|w| w == tls), "{ports:x?}");
    // Create_CSR is not offered without the runtime's signer; the Message Router lists the three classes.
    assert_eq!(call(&mut h, 0x4B, 0x5F, 1, &[]).0, 0x08);
    let (g, list) = get_class(&mut h, 0x02, 1, 1);
    assert_eq!(g, 0);
    let classes: Vec<u16> = list[2..]
        .chunks(2)
        .map(|c| u16::from_le_bytes([c[0], c[1]]))
        .collect();
    assert!(
        [0x5D, 0x5E, 0x5F].iter().all(|c| classes.contains(c)),
        "{classes:x?}"
    );
}

fn get_class(h: &mut Harness, class: u32, instance: u32, attribute: u32) -> (u8, Vec<u8>) {
    let (g, _, d) = status(&h.request(0x0E, &path(class, instance, Some(attribute)), &[]));
    (g, d)
}

#[test]
fn configuration_sequence_with_its_statuses_survives_a_restart() {
    let store = shared();
    let mut h = start(&store);
    // Nothing is settable outside a configuration session.
    assert_eq!(set(&mut h, 0x5E, 9, &[1]).0, 0x0C);
    assert_eq!(call(&mut h, 0x4D, 0x5E, 1, &[]).0, 0x0C);
    assert_eq!(call(&mut h, 0x4C, 0x5E, 1, &[]).0, 0x0C);
    assert_eq!(call(&mut h, 0x4B, 0x5D, 1, &[]).0, 0);
    assert_eq!(call(&mut h, 0x4B, 0x5D, 1, &[]).0, 0x0C);
    assert_eq!(call(&mut h, 0x4B, 0x5E, 1, &[]).0, 0);
    assert_eq!(get(&mut h, 0x5E, 1), (0, vec![1]));
    // Another client (here a local request) may not act in this session.
    let mut reply = [0u8; 64];
    let mut req = [0u8; 64];
    let mut w = enip_stack::wire::Writer::new(&mut req);
    originator::request(&mut w, 0x4D, &path(0x5E, 1, None), &[]).unwrap();
    let n = w.len();
    let len = h.adapter.execute(&req[..n], h.now, &mut reply);
    assert_eq!(reply[2], 0x0C, "{:x?}", &reply[..len]);
    // Allowed suites: only available ones, no duplicates, exact length.
    assert_eq!(set(&mut h, 0x5E, 4, &[1, 0x00, 0x3C]).0, 0x09);
    assert_eq!(set(&mut h, 0x5E, 4, &[2, 0xC0, 0x23, 0xC0, 0x23]).0, 0x09);
    assert_eq!(set(&mut h, 0x5E, 4, &[2, 0xC0, 0x23]).0, 0x13);
    assert_eq!(set(&mut h, 0x5E, 4, &[1, 0xC0, 0x23, 0]).0, 0x15);
    assert_eq!(set(&mut h, 0x5E, 4, &[0]).0, 0);
    assert_eq!(call(&mut h, 0x4D, 0x5E, 1, &[]).1, vec![0x0004]);
    assert_eq!(set(&mut h, 0x5E, 4, &[2, 0xC0, 0x2B, 0xC0, 0x23]).0, 0);
    // A pre-shared key without its usage byte.
    assert_eq!(set(&mut h, 0x5E, 5, &[1, 1, b'a', 1, b'k']).0, 0x13);
    assert_eq!(set(&mut h, 0x5E, 9, &[2]).0, 0x09);
    assert_eq!(set(&mut h, 0x5E, 9, &[1]).0, 0);
    // Client verification with no trusted CA cannot be applied.
    assert_eq!(call(&mut h, 0x4D, 0x5E, 1, &[]), (0x0C, vec![], vec![]));
    // A CA's instance: Create (class service), then name it.
    let (g, _, d) = call(&mut h, 0x08, 0x5F, 0, &[5, b'p', b'l', b'a', b'n', b't']);
    assert_eq!((g, d), (0, vec![2, 0]));
    assert_eq!(call(&mut h, 0x08, 0x5F, 0, &[0]).0, 0x20);
    assert_eq!(set(&mut h, 0x5E, 7, &cert_list(3)).0, 0x09);
    assert_eq!(set(&mut h, 0x5E, 7, &[1, 2, 0x20, 0x5E, 0x24, 2]).0, 0x09);
    assert_eq!(set(&mut h, 0x5E, 7, &cert_list(2)).0, 0);
    assert_eq!(get(&mut h, 0x5E, 7), (0, cert_list(2)));
    assert_eq!(call(&mut h, 0x4D, 0x5E, 1, &[0, 0]).0, 0x13);
    assert_eq!(call(&mut h, 0x4D, 0x5E, 1, &[0, 0, 0, 0]).0, 0);
    assert_eq!(get(&mut h, 0x5E, 1), (0, vec![2]));
    assert_eq!(call(&mut h, 0x4D, 0x5D, 1, &[]).0, 0);
    assert_eq!(get(&mut h, 0x5D, 1), (0, vec![2]));
    assert_eq!(get(&mut h, 0x5D, 3), (0, vec![0x02, 0x00]));
    // An instance in use, or the factory one, is not deleted; cleanup keeps named ones.
    assert_eq!(call(&mut h, 0x09, 0x5F, 2, &[]).0, 0x0C);
    assert_eq!(call(&mut h, 0x09, 0x5F, 1, &[]).0, 0x2D);
    assert_eq!(call(&mut h, 0x08, 0x5F, 0, &[3, b'o', b'l', b'd']).0, 0);
    assert_eq!(call(&mut h, 0x4E, 0x5D, 1, &[]).0, 0);
    assert_eq!(get_class(&mut h, 0x5F, 3, 1).0, 0x16);
    let generation = h.adapter.security(h.now).generation;
    // A restart finds the applied settings.
    drop(h);
    let mut h = start(&store);
    let st = h.adapter.security(Instant(0));
    assert_eq!(
        (st.cip_mode, st.eip_mode),
        (ObjectMode::Configured, ObjectMode::Configured)
    );
    assert_eq!(&st.active.allowed[..], &[0xC02B, 0xC023]);
    assert_eq!(
        (st.active.verify_client, st.active.trusted_ca),
        (true, Some(2))
    );
    assert!(generation > 0);
    assert_eq!(list_identity(&mut h)[1].1, vec![0x02, 0x00, 2, 2, 0b1111]);
    assert_eq!(get_class(&mut h, 0x5F, 2, 1), (0, b"\x05plant".to_vec()));
    // Configured: reconfigured or reset only over TLS.
    assert_eq!(call(&mut h, 0x4B, 0x5E, 1, &[]).0, 0x0F);
    assert_eq!(call(&mut h, 0x4B, 0x5D, 1, &[]).0, 0x0F);
    assert_eq!(call(&mut h, 0x05, 0x5E, 1, &[]).0, 0x0F);
    let close_44818 = [1, 0x12, 0xAF, 6, 0];
    assert_eq!(call(&mut h, 0x4C, 0xF5, 1, &close_44818).0, 0x0F);
    h.adapter.set_session_secure(SocketId(0), true);
    // Over TLS: 44818/tcp closes (only it is configurable), and stays closed after a restart.
    assert_eq!(call(&mut h, 0x4C, 0xF5, 1, &[1, 0xAE, 0x08, 6, 0]).0, 0x09);
    assert_eq!(call(&mut h, 0x4C, 0xF5, 1, &[1, 0x12, 0xAF, 6, 2]).0, 0x09);
    assert_eq!(call(&mut h, 0x4C, 0xF5, 1, &[1, 0x12, 0xAF, 6]).0, 0x13);
    assert_eq!(call(&mut h, 0x4C, 0xF5, 1, &close_44818).0, 0);
    drop(h);
    let mut h = start(&store);
    assert!(h.adapter.security(h.now).plain_tcp_closed);
    assert_eq!(list_identity(&mut h)[1].1[4], 0b1110);
    let (_, ports) = get_class(&mut h, 0xF5, 1, 14);
    assert_eq!(&ports[..18], b"\x04\x0bEtherNet/IP\x12\xaf\x06\x00\x01");
    h.adapter.set_session_secure(SocketId(0), true);
    assert_eq!(call(&mut h, 0x05, 0x5E, 1, &[1]).0, 0x15);
    assert_eq!(call(&mut h, 0x05, 0x5E, 1, &[]).0, 0);
    let st = h.adapter.security(h.now);
    assert_eq!(st.eip_mode, ObjectMode::FactoryDefault);
    assert_eq!(&st.active.allowed[..], &[0xC023, 0xC024]);
    assert!(!st.active.verify_client);
    assert_eq!(call(&mut h, 0x4B, 0x5D, 1, &[]).0, 0);
}

#[test]
fn a_lapsed_or_aborted_session_drops_its_changes() {
    let mut h = start(&shared());
    // 44818 closes only on a configured device.
    h.adapter.set_session_secure(SocketId(0), true);
    assert_eq!(call(&mut h, 0x4C, 0xF5, 1, &[1, 0x12, 0xAF, 6, 0]).0, 0x0C);
    assert_eq!(call(&mut h, 0x4B, 0x5E, 1, &[]).0, 0);
    assert_eq!(set(&mut h, 0x5E, 10, &[1]).0, 0);
    assert_eq!(get(&mut h, 0x5E, 10), (0, vec![1]));
    assert_eq!(call(&mut h, 0x4E, 0x5E, 1, &[]).0, 0);
    assert_eq!(get(&mut h, 0x5E, 1), (0, vec![0]));
    assert_eq!(get(&mut h, 0x5E, 10), (0, vec![0]));
    assert_eq!(call(&mut h, 0x4B, 0x5E, 1, &[]).0, 0);
    h.now = h.now.add(Duration::from_secs(9));
    assert_eq!(call(&mut h, 0x4C, 0x5E, 1, &[]).0, 0);
    h.now = h.now.add(Duration::from_secs(9));
    assert_eq!(set(&mut h, 0x5E, 10, &[1]).0, 0);
    h.now = h.now.add(Duration::from_secs(11));
    assert_eq!(set(&mut h, 0x5E, 10, &[1]).0, 0x0C);
    assert_eq!(get(&mut h, 0x5E, 1), (0, vec![0]));
    assert_eq!(get(&mut h, 0x5E, 10), (0, vec![0]));
}

#[test]
fn a_store_that_cannot_save_changes_nothing() {
    let store = shared();
    let mut h = start(&store);
    assert_eq!(call(&mut h, 0x4B, 0x5E, 1, &[]).0, 0);
    assert_eq!(set(&mut h, 0x5E, 4, &[1, 0xC0, 0x2C]).0, 0);
    *store.1.borrow_mut() = true;
    assert_eq!(call(&mut h, 0x4D, 0x5E, 1, &[]).0, 0x19);
    assert_eq!(call(&mut h, 0x08, 0x5F, 0, &[1, b'x']).0, 0x19);
    assert_eq!(get_class(&mut h, 0x5F, 2, 1).0, 0x16);
    let st = h.adapter.security(h.now);
    assert_eq!(st.eip_mode, ObjectMode::InProgress);
    assert_eq!(&st.active.allowed[..], &[0xC023, 0xC024]);
    // The session goes on: once the store saves again, Apply_Config succeeds.
    *store.1.borrow_mut() = false;
    assert_eq!(call(&mut h, 0x4D, 0x5E, 1, &[]).0, 0);
    assert_eq!(&h.adapter.security(h.now).active.allowed[..], &[0xC02C]);
}

/// EtherNet/IP Security attribute 5 as a Set carries it: one key.
fn psk(identity: &[u8], key: &[u8], usage: u8) -> Vec<u8> {
    let mut v = vec![1, identity.len() as u8];
    v.extend_from_slice(identity);
    v.push(key.len() as u8);
    v.extend_from_slice(key);
    v.push(usage);
    v
}

#[test]
fn a_pre_shared_key_is_written_stored_and_never_read_out() {
    let store = shared();
    let mut h = start(&store);
    assert_eq!(get(&mut h, 0x5E, 5), (0, vec![0]));
    assert_eq!(call(&mut h, 0x4B, 0x5E, 1, &[]).0, 0);
    let key = [0x5A; 32];
    // More than one key, an empty or too long identity or key, a short value: refused.
    let mut two = psk(b"a", &key, 4);
    two[0] = 2;
    assert_eq!(set(&mut h, 0x5E, 5, &two).0, 0x09);
    assert_eq!(set(&mut h, 0x5E, 5, &psk(b"", &key, 4)).0, 0x09);
    assert_eq!(set(&mut h, 0x5E, 5, &psk(b"a", &[], 4)).0, 0x09);
    assert_eq!(set(&mut h, 0x5E, 5, &psk(&[b'i'; 33], &key, 4)).0, 0x09);
    assert_eq!(set(&mut h, 0x5E, 5, &psk(b"a", &[1; 33], 4)).0, 0x09);
    let good = psk(b"plant-1", &key, 4);
    assert_eq!(set(&mut h, 0x5E, 5, &good[..good.len() - 1]).0, 0x13);
    assert_eq!(set(&mut h, 0x5E, 5, &good).0, 0);
    // A Get shows the identity and the usage, a key size of 0 and no key bytes.
    let shown = [&[1, 7][..], b"plant-1", &[0, 4]].concat();
    assert_eq!(get(&mut h, 0x5E, 5), (0, shown.clone()));
    assert_eq!(call(&mut h, 0x4D, 0x5E, 1, &[]).0, 0);
    let (g, _, all) = call(&mut h, 0x01, 0x5E, 1, &[]);
    assert_eq!(g, 0);
    assert!(
        !all.windows(4).any(|w| w == [0x5A; 4]),
        "the key leaks: {all:x?}"
    );
    let stored = |h: &mut Harness| h.adapter.security(h.now).active.psk.clone();
    assert_eq!(stored(&mut h).unwrap().key.as_slice(), key);
    // A restart finds it.
    let mut h = start(&store);
    assert_eq!(get(&mut h, 0x5E, 5), (0, shown.clone()));
    assert_eq!(stored(&mut h).unwrap().key.as_slice(), key);
    // The store's record has a fixed room (156 bytes; 84 with the factory suites and two
    // created instances with 32-byte names): beside this key (42 bytes), a third instance
    // with the longest name does not fit (0x19, not created); a short name does.
    for c in [b'x', b'y'] {
        let name = [&[32][..], &[c; 32]].concat();
        assert_eq!(call(&mut h, 0x08, 0x5F, 0, &name).0, 0);
    }
    let long = [&[32][..], &[b'z'; 32]].concat();
    assert_eq!(call(&mut h, 0x08, 0x5F, 0, &long).0, 0x19);
    assert_eq!(
        call(&mut h, 0x08, 0x5F, 0, b"\x03zzz"),
        (0, vec![], vec![4, 0])
    );
    // Configured: reconfigured over TLS only.
    assert_eq!(call(&mut h, 0x4B, 0x5E, 1, &[]).0, 0x0F);
    h.adapter.set_session_secure(SocketId(0), true);
    assert_eq!(call(&mut h, 0x4B, 0x5E, 1, &[]).0, 0);
    // A 67-byte key does not fit beside them: Apply_Config answers 0x19, the key in use
    // stays.
    assert_eq!(set(&mut h, 0x5E, 5, &psk(&[b'i'; 32], &key, 4)).0, 0);
    assert_eq!(call(&mut h, 0x4D, 0x5E, 1, &[]).0, 0x19);
    assert_eq!(stored(&mut h).unwrap().identity.as_slice(), b"plant-1");
    assert_eq!(set(&mut h, 0x5E, 5, &psk(b"line-2", &[7; 24], 4)).0, 0);
    assert_eq!(call(&mut h, 0x4D, 0x5E, 1, &[]).0, 0);
    let mut h = start(&store);
    assert_eq!(stored(&mut h).unwrap().key.as_slice(), [7; 24]);
    // Reset: no key.
    h.adapter.set_session_secure(SocketId(0), true);
    assert_eq!(call(&mut h, 0x05, 0x5E, 1, &[]).0, 0);
    assert_eq!(get(&mut h, 0x5E, 5), (0, vec![0]));
}

#[test]
fn a_lapsed_session_ends_before_list_identity_and_the_port_admin_service() {
    let mut h = start(&shared());
    h.adapter.set_session_secure(SocketId(0), true);
    assert_eq!(call(&mut h, 0x4B, 0x5E, 1, &[]).0, 0);
    assert_eq!(call(&mut h, 0x4D, 0x5E, 1, &[]).0, 0);
    assert_eq!(call(&mut h, 0x4B, 0x5D, 1, &[]).0, 0);
    assert_eq!(call(&mut h, 0x4B, 0x5E, 1, &[]).0, 0);
    let states = |h: &mut Harness| {
        let items = list_identity(h);
        let (_, item) = items.iter().find(|(kind, _)| *kind == 0x86).unwrap();
        (item[2], item[3])
    };
    assert_eq!(states(&mut h), (1, 1));
    h.now = h.now.add(Duration::from_secs(11));
    // No request to the security objects since: the item shows the states they returned to.
    assert_eq!(states(&mut h), (0, 2));
    assert_eq!(call(&mut h, 0x4B, 0x5E, 1, &[]).0, 0);
    h.now = h.now.add(Duration::from_secs(11));
    // The object is configured again, so 44818 may close (not 0x0C for a lapsed session).
    assert_eq!(call(&mut h, 0x4C, 0xF5, 1, &[1, 0x12, 0xAF, 6, 0]).0, 0);
    assert_eq!(get(&mut h, 0x5E, 1), (0, vec![2]));
}

#[test]
fn a_session_begun_over_tls_takes_no_plaintext_request_from_the_same_address() {
    let mut h = start(&shared());
    // Configured over plaintext (factory default): the whole sequence over plaintext works.
    assert_eq!(call(&mut h, 0x4B, 0x5E, 1, &[]).0, 0);
    assert_eq!(call(&mut h, 0x4D, 0x5E, 1, &[]).0, 0);
    assert_eq!(call(&mut h, 0x4B, 0x5D, 1, &[]).0, 0);
    assert_eq!(call(&mut h, 0x4D, 0x5D, 1, &[]).0, 0);
    // Reconfigured over TLS; the same address's plaintext session (socket 0 no longer
    // secure) may not act in it: that would undo the TLS-only rule of Begin_Config.
    h.adapter.set_session_secure(SocketId(0), true);
    assert_eq!(call(&mut h, 0x4B, 0x5D, 1, &[]).0, 0);
    assert_eq!(call(&mut h, 0x4B, 0x5E, 1, &[]).0, 0);
    h.adapter.set_session_secure(SocketId(0), false);
    assert_eq!(set(&mut h, 0x5E, 10, &[1]).0, 0x0F);
    for (class, service) in [
        (0x5E, 0x4C),
        (0x5E, 0x4D),
        (0x5E, 0x4E),
        (0x5D, 0x4C),
        (0x5D, 0x4D),
    ] {
        assert_eq!(
            call(&mut h, service, class, 1, &[]).0,
            0x0F,
            "{class:#x} {service:#x}"
        );
    }
    h.adapter.set_session_secure(SocketId(0), true);
    assert_eq!(set(&mut h, 0x5E, 10, &[1]).0, 0);
    assert_eq!(call(&mut h, 0x4D, 0x5E, 1, &[]).0, 0);
    assert_eq!(call(&mut h, 0x4D, 0x5D, 1, &[]).0, 0);
    assert_eq!(get(&mut h, 0x5E, 10), (0, vec![1]));
}
