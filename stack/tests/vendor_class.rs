//! A vendor class declared only through the public API (`ClassDef`, `AttributeDef`, the
//! `Device` value hooks), and every CIP status rule the stack serves it with: one test per
//! rule, over SendRRData from a registered session.

mod common;

use std::net::SocketAddrV4;

use common::*;
use enip_stack::cip::context::{RequestContext, Via};
use enip_stack::cip::object::{AttributeDef, ClassDef, DataType};
use enip_stack::cip::{CipError, CipResult, General, Request};
use enip_stack::device::{AttributeRef, Device};
use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use enip_stack::wire::forward_open::{ForwardOpenReplyRepr, NetworkParams};
use enip_stack::wire::Writer;
use enip_stack::{AssemblyInfo, AssemblyRole, IdentityInfo};

const AXIS: u16 = 0x70;
/// Instance whose Sets the object refuses for its own state (0x0C).
const LOCKED: u32 = 3;

const AXIS_CLASS: ClassDef = ClassDef {
    id: AXIS,
    name: "Axis",
    revision: 3,
    max_instance: 3,
    attributes: &[
        AttributeDef::get(1, DataType::Dint, "Position"),
        AttributeDef::get_set(2, DataType::Udint, "Limit"),
        AttributeDef::get_set(3, DataType::ShortString { max: 8 }, "Name"),
        AttributeDef::set(4, DataType::Udint, "Key"),
        AttributeDef::get(5, DataType::Bytes(1200), "Trace"),
    ],
    get_all: &[1, 2, 3],
    optional_attributes: &[],
};

const ASSEMBLIES: [AssemblyInfo; 1] = [AssemblyInfo {
    instance: 100,
    role: AssemblyRole::Input,
    size: 4,
    run_idle_header: false,
}];

#[derive(Default)]
struct Axes {
    limit: [u32; 3],
    name: [Vec<u8>; 3],
    key: u32,
    /// While running, limits cannot change (0x10).
    running: bool,
    /// The contexts vendor service 0x4B saw.
    contexts: Vec<RequestContext>,
}

fn index(at: &AttributeRef<'_>) -> usize {
    at.instance as usize - 1
}

impl Device for Axes {
    fn identity(&self) -> &IdentityInfo {
        &IDENTITY
    }
    fn assemblies(&self) -> &[AssemblyInfo] {
        &ASSEMBLIES
    }
    fn read_assembly(&mut self, _instance: u16, out: &mut [u8]) -> CipResult<usize> {
        out.fill(0);
        Ok(out.len())
    }
    fn write_assembly(&mut self, _instance: u16, _data: &[u8]) -> CipResult {
        Err(General::AttributeNotSettable.into())
    }
    fn classes(&self) -> &[ClassDef] {
        &[AXIS_CLASS]
    }
    fn get_attribute(
        &mut self,
        _cx: &RequestContext,
        at: &AttributeRef<'_>,
        w: &mut Writer<'_>,
    ) -> CipResult {
        let i = index(at);
        match at.attribute.id {
            1 => w.u32(-(at.instance as i32) as u32)?,
            2 => w.u32(self.limit[i])?,
            3 => {
                w.u8(self.name[i].len() as u8)?;
                w.bytes(&self.name[i])?;
            }
            4 => unreachable!("write-only attributes are never read"),
            // More than any reply frame holds.
            _ => w.zeros(FRAME)?,
        }
        Ok(())
    }
    fn set_attribute(
        &mut self,
        _cx: &RequestContext,
        at: &AttributeRef<'_>,
        value: &[u8],
    ) -> CipResult {
        if at.instance == LOCKED {
            return Err(General::ObjectStateConflict.into());
        }
        let i = index(at);
        match at.attribute.id {
            2 => {
                let v = u32::from_le_bytes(value.try_into().unwrap());
                if v > 1000 {
                    return Err(General::InvalidAttributeValue.into());
                }
                if self.running {
                    return Err(General::DeviceStateConflict.into());
                }
                self.limit[i] = v;
            }
            3 => self.name[i] = value[1..].to_vec(),
            4 => self.key = u32::from_le_bytes(value.try_into().unwrap()),
            _ => unreachable!("read-only attributes are never written"),
        }
        Ok(())
    }
    fn handle_request(
        &mut self,
        cx: &RequestContext,
        req: &Request<'_>,
        reply: &mut Writer<'_>,
    ) -> Option<CipResult> {
        (req.service == 0x4B).then(|| {
            self.contexts.push(*cx);
            reply.u8(0x4B).map_err(CipError::from)
        })
    }
}

fn axis(instance: u32, attribute: Option<u32>) -> Vec<SegmentRepr<'static>> {
    let mut p = vec![
        SegmentRepr::Logical(LogicalType::Class, u32::from(AXIS)),
        SegmentRepr::Logical(LogicalType::Instance, instance),
    ];
    p.extend(attribute.map(|a| SegmentRepr::Logical(LogicalType::Attribute, a)));
    p
}

fn harness() -> Harness<Axes> {
    Harness::with_device(Axes::default())
}

/// General status and data of a request to the axis class.
fn ask(
    h: &mut Harness<Axes>,
    service: u8,
    instance: u32,
    attribute: Option<u32>,
    data: &[u8],
) -> (u8, Vec<u8>) {
    let (g, _, d) = status(&h.request(service, &axis(instance, attribute), data));
    (g, d)
}

fn get(h: &mut Harness<Axes>, instance: u32, attribute: u32) -> (u8, Vec<u8>) {
    ask(h, 0x0E, instance, Some(attribute), &[])
}

fn set(h: &mut Harness<Axes>, instance: u32, attribute: u32, value: &[u8]) -> u8 {
    ask(h, 0x10, instance, Some(attribute), value).0
}

#[test]
fn values_round_trip() {
    let mut h = harness();
    assert_eq!(set(&mut h, 2, 2, &500u32.to_le_bytes()), 0);
    assert_eq!(get(&mut h, 2, 2), (0, 500u32.to_le_bytes().to_vec()));
    assert_eq!(set(&mut h, 1, 3, &[2, b'x', b'y']), 0);
    assert_eq!(get(&mut h, 1, 3), (0, vec![2, b'x', b'y']));
    assert_eq!(set(&mut h, 1, 4, &7u32.to_le_bytes()), 0);
    assert_eq!(h.adapter.device().key, 7);
}

#[test]
fn unknown_class_is_0x05() {
    let mut h = harness();
    let path = [
        SegmentRepr::Logical(LogicalType::Class, 0x71),
        SegmentRepr::Logical(LogicalType::Instance, 1),
        SegmentRepr::Logical(LogicalType::Attribute, 1),
    ];
    assert_eq!(status(&h.request(0x0E, &path, &[])).0, 0x05);
}

#[test]
fn path_without_attribute_is_0x05() {
    let mut h = harness();
    assert_eq!(ask(&mut h, 0x0E, 1, None, &[]).0, 0x05);
}

#[test]
fn unknown_instance_is_0x16() {
    let mut h = harness();
    assert_eq!(get(&mut h, 4, 1).0, 0x16);
    assert_eq!(
        ask(&mut h, 0x4B, 4, None, &[]).0,
        0x16,
        "before any vendor service"
    );
}

#[test]
fn unsupported_service_is_0x08() {
    let mut h = harness();
    assert_eq!(ask(&mut h, 0x4C, 1, None, &[]).0, 0x08);
    assert_eq!(
        ask(&mut h, 0x02, 1, None, &[]).0,
        0x08,
        "Set_Attributes_All"
    );
}

#[test]
fn unknown_attribute_is_0x14() {
    let mut h = harness();
    assert_eq!(get(&mut h, 1, 9).0, 0x14);
    assert_eq!(set(&mut h, 1, 9, &[0; 4]), 0x14);
}

#[test]
fn read_only_attribute_is_0x0e() {
    let mut h = harness();
    assert_eq!(set(&mut h, 1, 1, &[0; 4]), 0x0E);
    assert_eq!(set(&mut h, 1, 1, &[0; 9]), 0x0E, "before the length");
}

#[test]
fn write_only_attribute_is_0x2c() {
    let mut h = harness();
    assert_eq!(get(&mut h, 1, 4).0, 0x2C);
}

#[test]
fn short_value_is_0x13() {
    let mut h = harness();
    assert_eq!(set(&mut h, 1, 2, &[1, 2, 3]), 0x13);
    assert_eq!(
        set(&mut h, 1, 3, &[5, b'a']),
        0x13,
        "a string shorter than its count"
    );
}

#[test]
fn long_value_is_0x15() {
    let mut h = harness();
    assert_eq!(set(&mut h, 1, 2, &[1, 2, 3, 4, 5]), 0x15);
    assert_eq!(
        ask(&mut h, 0x0E, 1, Some(2), &[0]).0,
        0x15,
        "a Get with data"
    );
}

#[test]
fn invalid_value_is_0x09_and_changes_nothing() {
    let mut h = harness();
    assert_eq!(set(&mut h, 1, 2, &9u32.to_le_bytes()), 0);
    assert_eq!(set(&mut h, 1, 2, &2000u32.to_le_bytes()), 0x09);
    assert_eq!(
        set(
            &mut h,
            1,
            3,
            &[9, b'a', b'b', b'c', b'd', b'e', b'f', b'g', b'h', b'i']
        ),
        0x09,
        "longer than 8"
    );
    assert_eq!(h.adapter.device().limit[0], 9);
}

#[test]
fn object_state_conflict_is_0x0c() {
    let mut h = harness();
    assert_eq!(set(&mut h, LOCKED, 2, &1u32.to_le_bytes()), 0x0C);
}

#[test]
fn device_state_conflict_is_0x10() {
    let mut h = harness();
    h.adapter.device_mut().running = true;
    assert_eq!(set(&mut h, 1, 2, &1u32.to_le_bytes()), 0x10);
}

#[test]
fn reply_too_large_is_0x11() {
    let mut h = harness();
    assert_eq!(get(&mut h, 1, 5).0, 0x11);
    assert_eq!(
        ask(&mut h, 0x03, 1, None, &[2, 0, 1, 0, 5, 0]).0,
        0x11,
        "in a list too"
    );
}

#[test]
fn get_attributes_all_in_the_class_order() {
    let mut h = harness();
    set(&mut h, 2, 2, &3u32.to_le_bytes());
    set(&mut h, 2, 3, &[1, b'z']);
    let (g, d) = ask(&mut h, 0x01, 2, None, &[]);
    assert_eq!(g, 0);
    assert_eq!(d, [0xFE, 0xFF, 0xFF, 0xFF, 3, 0, 0, 0, 1, b'z']);
}

#[test]
fn get_attribute_list_reports_each_attribute() {
    let mut h = harness();
    let (g, d) = ask(&mut h, 0x03, 1, None, &[3, 0, 1, 0, 4, 0, 9, 0]);
    assert_eq!(g, 0x0A);
    assert_eq!(
        d,
        [3, 0, 1, 0, 0, 0, 0xFF, 0xFF, 0xFF, 0xFF, 4, 0, 0x2C, 0, 9, 0, 0x14, 0]
    );
    assert_eq!(
        ask(&mut h, 0x03, 1, None, &[2, 0, 1, 0]).0,
        0x13,
        "count beyond the data"
    );
    // An impossible count is "not enough data" before it is "too many".
    assert_eq!(ask(&mut h, 0x03, 1, None, &[0xFF, 0xFF, 1, 0]).0, 0x13);
    assert_eq!(ask(&mut h, 0x04, 1, None, &[0xFF, 0xFF, 1, 0]).0, 0x13);
    let mut many = vec![33, 0];
    many.extend([1, 0].repeat(33));
    assert_eq!(
        ask(&mut h, 0x03, 1, None, &many).0,
        0x02,
        "more than a reply may carry"
    );
}

#[test]
fn set_attribute_list_applies_each_valid_entry_and_no_refused_one() {
    let mut h = harness();
    let mut list = vec![4, 0];
    list.extend([2, 0, 10, 0, 0, 0]); // limit 10: applied
    list.extend([2, 0, 0xD0, 0x07, 0, 0]); // limit 2000: refused, skipped
    list.extend([1, 0, 0, 0, 0, 0]); // read-only: refused, skipped by its size
    list.extend([3, 0, 2, b'o', b'k']); // name: applied
    let (g, d) = ask(&mut h, 0x04, 1, None, &list);
    assert_eq!(g, 0x0A);
    assert_eq!(
        d,
        [4, 0, 2, 0, 0, 0, 2, 0, 0x09, 0, 1, 0, 0x0E, 0, 3, 0, 0, 0]
    );
    assert_eq!(h.adapter.device().limit[0], 10);
    assert_eq!(h.adapter.device().name[0], b"ok");
    // An unknown attribute ends the list: its value's length cannot be known.
    let (g, d) = ask(&mut h, 0x04, 1, None, &[2, 0, 9, 0, 1, 2, 2, 0, 5, 0, 0, 0]);
    assert_eq!(g, 0x0A);
    assert_eq!(d, [1, 0, 9, 0, 0x14, 0]);
    assert_eq!(h.adapter.device().limit[0], 10);
}

#[test]
fn class_attributes_1_to_7() {
    let mut h = harness();
    let class = |h: &mut Harness<Axes>, a| ask(h, 0x0E, 0, Some(a), &[]);
    assert_eq!(class(&mut h, 1), (0, vec![3, 0]));
    assert_eq!(class(&mut h, 2), (0, vec![3, 0]));
    assert_eq!(class(&mut h, 3), (0, vec![3, 0]));
    assert_eq!(class(&mut h, 6), (0, vec![7, 0]));
    assert_eq!(class(&mut h, 7), (0, vec![5, 0]));
    assert_eq!(class(&mut h, 8).0, 0x14);
    assert_eq!(ask(&mut h, 0x10, 0, Some(1), &[1, 0]).0, 0x0E);
    let (g, d) = ask(&mut h, 0x01, 0, None, &[]);
    assert_eq!(g, 0);
    // No optional attributes; optional services Get_Attribute_List and Set_Attribute_List.
    assert_eq!(d, [3, 0, 3, 0, 3, 0, 0, 0, 2, 0, 3, 0, 4, 0, 7, 0, 5, 0]);
    assert_eq!(class(&mut h, 5), (0, vec![2, 0, 3, 0, 4, 0]));
}

#[test]
fn the_message_router_lists_the_class() {
    let mut h = harness();
    let path = [
        SegmentRepr::Logical(LogicalType::Class, 2),
        SegmentRepr::Logical(LogicalType::Instance, 1),
        SegmentRepr::Logical(LogicalType::Attribute, 1),
    ];
    let (g, _, d) = status(&h.request(0x0E, &path, &[]));
    assert_eq!(g, 0);
    // The nine standard classes, then the vendor class.
    assert_eq!(d[0], 10);
    assert_eq!(&d[d.len() - 2..], &[AXIS as u8, 0]);
}

#[test]
fn vendor_services_see_where_the_request_came_from() {
    let mut h = harness();
    h.now = enip_stack::Instant(1234);
    assert_eq!(ask(&mut h, 0x4B, 2, None, &[]), (0, vec![0x4B]));
    let cx = h.adapter.device().contexts[0];
    assert_eq!(cx.via, Via::Unconnected);
    assert_eq!(cx.peer, Some(SocketAddrV4::new(SCANNER_IP, 50000)));
    assert_eq!(cx.now, enip_stack::Instant(1234));

    // The same service over a Class 3 connection names its slot.
    let mr = [0x20, 0x02, 0x24, 0x01];
    let mut f = fo(9, &mr, 100_000);
    f.transport = 0xA3;
    f.o_t_params = NetworkParams::from_u16(0x4800 | 500);
    f.t_o_params = NetworkParams::from_u16(0x4800 | 500);
    let (g, _, data) = status(&h.forward_open(&f));
    assert_eq!(g, 0);
    let id = ForwardOpenReplyRepr::parse(&data)
        .unwrap()
        .o_t_connection_id;
    let mut buf = vec![0u8; 600];
    let n = enip_stack::originator::send_unit_data(&mut buf, h.session, id, 1, |w| {
        enip_stack::originator::request(w, 0x4B, &axis(1, None), &[])
    })
    .unwrap();
    let reply = h.tcp(&buf[..n]);
    assert_eq!(
        enip_stack::originator::parse_reply(&reply)
            .unwrap()
            .response
            .unwrap()
            .general_status,
        0
    );
    let cx = h.adapter.device().contexts[1];
    assert!(cx.is_connected());
    let slot = h.adapter.connections().find_o_t(id).unwrap();
    assert_eq!(cx.via, Via::Connected { slot });
}

/// A class whose attribute 1 has a size only the device knows (`DataType::RunTime`): a table
/// of `entries` 16-bit words, told to the stack through `Device::attribute_size`.
const TABLE: u16 = 0x71;

const TABLE_CLASS: ClassDef = ClassDef {
    id: TABLE,
    name: "Table",
    revision: 1,
    max_instance: 2,
    attributes: &[
        AttributeDef::get_set(1, DataType::RunTime, "Entries"),
        AttributeDef::get_set(2, DataType::Usint, "Mode"),
    ],
    get_all: &[1, 2],
    optional_attributes: &[],
};

struct Tables {
    /// Instance 1 has three entries; instance 2 says nothing about its size.
    entries: Vec<u8>,
    mode: u8,
}

impl Device for Tables {
    fn identity(&self) -> &IdentityInfo {
        &IDENTITY
    }
    fn assemblies(&self) -> &[AssemblyInfo] {
        &ASSEMBLIES
    }
    fn read_assembly(&mut self, _instance: u16, out: &mut [u8]) -> CipResult<usize> {
        out.fill(0);
        Ok(out.len())
    }
    fn write_assembly(&mut self, _instance: u16, _data: &[u8]) -> CipResult {
        Err(General::AttributeNotSettable.into())
    }
    fn classes(&self) -> &[ClassDef] {
        &[TABLE_CLASS]
    }
    fn attribute_size(&self, at: &AttributeRef<'_>) -> Option<usize> {
        (at.instance == 1 && at.attribute.id == 1).then_some(3 * 2)
    }
    fn get_attribute(
        &mut self,
        _cx: &RequestContext,
        at: &AttributeRef<'_>,
        w: &mut Writer<'_>,
    ) -> CipResult {
        match at.attribute.id {
            1 => w.bytes(&self.entries)?,
            _ => w.u8(self.mode)?,
        }
        Ok(())
    }
    fn set_attribute(
        &mut self,
        _cx: &RequestContext,
        at: &AttributeRef<'_>,
        value: &[u8],
    ) -> CipResult {
        match at.attribute.id {
            1 => self.entries = value.to_vec(),
            _ => self.mode = value[0],
        }
        Ok(())
    }
}

fn table(
    h: &mut Harness<Tables>,
    service: u8,
    instance: u32,
    attribute: Option<u32>,
    data: &[u8],
) -> (u8, Vec<u8>) {
    let mut path = vec![
        SegmentRepr::Logical(LogicalType::Class, u32::from(TABLE)),
        SegmentRepr::Logical(LogicalType::Instance, instance),
    ];
    path.extend(attribute.map(|a| SegmentRepr::Logical(LogicalType::Attribute, a)));
    let (g, _, d) = status(&h.request(service, &path, data));
    (g, d)
}

#[test]
fn a_run_time_attribute_takes_the_size_the_device_gives() {
    let mut h = Harness::with_device(Tables {
        entries: vec![0; 6],
        mode: 0,
    });
    let entries = [1, 0, 2, 0, 3, 0];
    assert_eq!(table(&mut h, 0x10, 1, Some(1), &entries).0, 0);
    assert_eq!(h.adapter.device().entries, entries);
    assert_eq!(table(&mut h, 0x0E, 1, Some(1), &[]), (0, entries.to_vec()));
    assert_eq!(table(&mut h, 0x10, 1, Some(1), &entries[..4]).0, 0x13);
    assert_eq!(table(&mut h, 0x10, 1, Some(1), &[0; 8]).0, 0x15);
    // Set_Attribute_List finds the next entry after the run-time size.
    let mut list = vec![2, 0, 1, 0];
    list.extend([9, 0, 8, 0, 7, 0]);
    list.extend([2, 0, 5]);
    let (g, d) = table(&mut h, 0x04, 1, None, &list);
    assert_eq!((g, d), (0, vec![2, 0, 1, 0, 0, 0, 2, 0, 0, 0]));
    assert_eq!(h.adapter.device().entries, [9, 0, 8, 0, 7, 0]);
    assert_eq!(h.adapter.device().mode, 5);
    // Without a size from the device the value cannot be delimited.
    assert_eq!(table(&mut h, 0x10, 2, Some(1), &entries).0, 0x14);
}
