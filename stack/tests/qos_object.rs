//! The QoS object (class 0x48): its defaults, the range of a Set (0-63, else 0x09), the
//! class attributes, the values saved in the store and applied from the next start, and the
//! DSCP a Class 1 connection's T->O packets get from its priority.

mod common;

use std::cell::RefCell;
use std::rc::Rc;

use common::*;
use enip_stack::device::CloseReason;
use enip_stack::nv::{key, AbStore, NvError, NvStore, RamFlash, IMAGE_SIZE, MAX_WRITE_SIZE};
use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use enip_stack::wire::forward_open::NetworkParams;

type SmallFlash = RamFlash<{ MAX_WRITE_SIZE + IMAGE_SIZE }>;

/// A store the test keeps a handle on while the adapter uses it; `fail` makes writes fail.
#[derive(Clone)]
struct Shared(Rc<RefCell<AbStore<SmallFlash>>>, Rc<RefCell<bool>>);

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

fn shared() -> Shared {
    Shared(
        Rc::new(RefCell::new(AbStore::mount(SmallFlash::new()))),
        Rc::new(RefCell::new(false)),
    )
}

/// An adapter started with `store`, as after a power cycle.
fn start(store: &Shared) -> Harness {
    let mut h = Harness::new();
    h.adapter
        .attach_store(Box::leak(Box::new(store.clone())))
        .unwrap();
    h
}

fn qos(instance: u32, attribute: Option<u32>) -> Vec<SegmentRepr<'static>> {
    let mut p = vec![
        SegmentRepr::Logical(LogicalType::Class, 0x48),
        SegmentRepr::Logical(LogicalType::Instance, instance),
    ];
    p.extend(attribute.map(|a| SegmentRepr::Logical(LogicalType::Attribute, a)));
    p
}

fn get(h: &mut Harness, attribute: u32) -> u8 {
    let (g, _, d) = status(&h.request(0x0E, &qos(1, Some(attribute)), &[]));
    assert_eq!((g, d.len()), (0, 1), "attribute {attribute}");
    d[0]
}

fn set(h: &mut Harness, attribute: u32, value: &[u8]) -> u8 {
    status(&h.request(0x10, &qos(1, Some(attribute)), value)).0
}

fn all(h: &mut Harness) -> Vec<u8> {
    (1..=8).map(|a| get(h, a)).collect()
}

/// The DSCP of the T->O packets of a connection opened with T->O `priority`.
fn t_o_dscp(h: &mut Harness, serial: u16, priority: u16) -> u8 {
    let path = io_path(Some(151), 110, 100, None);
    let mut f = fo(serial, &path, 10_000);
    f.t_o_params = NetworkParams::from_u16(0x4000 | (priority << 10) | (2 + 32));
    let (g, ext, _) = status(&h.forward_open(&f));
    assert_eq!((g, ext), (0, vec![]), "priority {priority}");
    let due = h
        .adapter
        .io_due(h.now)
        .expect("a T->O datagram due at the open");
    h.adapter.write_io(due, h.now, None);
    // Closed again, so that the next one may own the output too.
    h.adapter.close_all(CloseReason::Reset);
    due.dscp
}

#[test]
fn defaults_class_attributes_and_services() {
    let mut h = Harness::new();
    assert_eq!(all(&mut h), [0, 59, 47, 55, 47, 43, 31, 27]);
    assert_eq!(h.adapter.explicit_dscp(), 27);
    // Class: revision 1, one instance, optional attributes 1-3, highest attribute 8.
    let class = |h: &mut Harness, a| status(&h.request(0x0E, &qos(0, Some(a)), &[]));
    assert_eq!(class(&mut h, 1).2, [1, 0]);
    assert_eq!(class(&mut h, 2).2, [1, 0]);
    assert_eq!(class(&mut h, 4).2, [3, 0, 1, 0, 2, 0, 3, 0]);
    assert_eq!(class(&mut h, 7).2, [8, 0]);
    // No Get_Attributes_All for the instance (the specification defines none), no instance 2,
    // no attribute 9.
    assert_eq!(status(&h.request(0x01, &qos(1, None), &[])).0, 0x08);
    assert_eq!(status(&h.request(0x0E, &qos(2, Some(4)), &[])).0, 0x16);
    assert_eq!(status(&h.request(0x0E, &qos(1, Some(9)), &[])).0, 0x14);
    // The Message Router lists the class.
    let router = [
        SegmentRepr::Logical(LogicalType::Class, 2),
        SegmentRepr::Logical(LogicalType::Instance, 1),
        SegmentRepr::Logical(LogicalType::Attribute, 1),
    ];
    let (_, _, list) = status(&h.request(0x0E, &router, &[]));
    assert!(list[2..].chunks(2).any(|c| c == [0x48, 0]), "{list:?}");
}

#[test]
fn a_set_takes_0_to_63_and_refuses_anything_else_with_0x09() {
    let store = shared();
    let mut h = start(&store);
    for attribute in 2..=8 {
        for bad in [64, 0x80, 0xFF] {
            assert_eq!(set(&mut h, attribute, &[bad]), 0x09, "{attribute}: {bad}");
        }
        assert_eq!(set(&mut h, attribute, &[63]), 0, "{attribute}");
        assert_eq!(get(&mut h, attribute), 63);
        assert_eq!(set(&mut h, attribute, &[0]), 0, "{attribute}");
        assert_eq!(get(&mut h, attribute), 0);
    }
    // The 802.1Q tag: this device sends no tagged frames, so only "disabled" is accepted.
    assert_eq!(set(&mut h, 1, &[1]), 0x09);
    assert_eq!(set(&mut h, 1, &[0]), 0);
    // A value of the wrong size.
    assert_eq!(set(&mut h, 8, &[]), 0x13);
    assert_eq!(set(&mut h, 8, &[1, 2]), 0x15);
    assert_eq!(all(&mut h), [0, 0, 0, 0, 0, 0, 0, 0]);
    // A store that cannot save: 0x19 and nothing changed.
    *store.1.borrow_mut() = true;
    assert_eq!(set(&mut h, 8, &[20]), 0x19);
    assert_eq!(get(&mut h, 8), 0);
}

#[test]
fn set_values_are_saved_and_apply_from_the_next_start() {
    let store = shared();
    let mut h = start(&store);
    assert_eq!(t_o_dscp(&mut h, 1, 2), 47);
    assert_eq!(set(&mut h, 5, &[40]), 0);
    assert_eq!(set(&mut h, 8, &[20]), 0);
    // Read back at once, but the packets keep the values the device started with.
    assert_eq!((get(&mut h, 5), get(&mut h, 8)), (40, 20));
    assert_eq!(t_o_dscp(&mut h, 2, 2), 47);
    assert_eq!(h.adapter.explicit_dscp(), 27);
    // The next start: the stored values, in use.
    let mut h = start(&store);
    assert_eq!(all(&mut h), [0, 59, 47, 55, 40, 43, 31, 20]);
    assert_eq!(h.adapter.explicit_dscp(), 20);
    assert_eq!(t_o_dscp(&mut h, 1, 2), 40);
}

#[test]
fn each_priority_gets_its_dscp() {
    let mut h = Harness::new();
    // Low, high, scheduled, urgent.
    for (serial, priority, dscp) in [(1, 0, 31), (2, 1, 43), (3, 2, 47), (4, 3, 55)] {
        assert_eq!(
            t_o_dscp(&mut h, serial, priority),
            dscp,
            "priority {priority}"
        );
    }
}

#[test]
fn factory_reset_restores_the_defaults() {
    let store = shared();
    let mut h = start(&store);
    assert_eq!(set(&mut h, 4, &[12]), 0);
    let identity = [
        SegmentRepr::Logical(LogicalType::Class, 1),
        SegmentRepr::Logical(LogicalType::Instance, 1),
    ];
    assert_eq!(status(&h.request(0x05, &identity, &[1])).0, 0);
    assert_eq!(get(&mut h, 4), 55);
    let mut buf = [0u8; 16];
    assert_eq!(store.clone().read(key::QOS, &mut buf), Ok(None));
    let mut h = start(&store);
    assert_eq!(all(&mut h), [0, 59, 47, 55, 47, 43, 31, 27]);
}
