//! The profile as the stack sees it: System940 requests, assemblies, multicast, reset.

mod device;

extern crate std;

use core::net::Ipv4Addr;
use std::vec;
use std::vec::Vec;

use enip_stack::cip::{CipError, CipResult, General};
use enip_stack::device::Multicast;
use enip_stack::device::MulticastConfig;
use enip_stack::{Adapter, AssemblyRole, Device, Instant, NetworkConfig};

use super::assemblies::{self, status2};
use super::device::status;
use enip_stack::nv::{CutFlash, SharedStore};

use super::params::{id, Value, DEFAULT_MULTICAST};
use super::storage::EpmCopy;
use super::PositionServo;
use crate::storage::testing;

/// Message Router request bytes: class 0x64, 16-bit instance, optional attribute, data.
fn request(service: u8, instance: u16, attribute: Option<u8>, data: &[u8]) -> Vec<u8> {
    let mut path = vec![0x20, 0x64, 0x25, 0x00];
    path.extend_from_slice(&instance.to_le_bytes());
    if let Some(a) = attribute {
        path.extend_from_slice(&[0x30, a]);
    }
    let mut out = vec![service, (path.len() / 2) as u8];
    out.extend(path);
    out.extend_from_slice(data);
    out
}

/// Runs Message Router request `bytes` against `servo` through the stack; returns the
/// general status and the reply data.
fn execute(servo: &mut PositionServo, bytes: &[u8]) -> (CipResult, Vec<u8>) {
    let net = NetworkConfig::new_static(
        Ipv4Addr::new(198, 18, 0, 2),
        Ipv4Addr::new(255, 255, 255, 0),
        [2, 0, 0, 0, 0, 1],
    );
    let mut adapter = Adapter::new(core::mem::take(servo), net, 1);
    let mut buf = [0u8; 512];
    let n = adapter.execute(bytes, Instant(0), &mut buf);
    *servo = adapter.into_device();
    let reply = &buf[..n];
    let additional = 2 * usize::from(reply[3]);
    let data = reply[4 + additional..].to_vec();
    match reply[2] {
        0 => (Ok(()), data),
        g => (Err(CipError::new(General::try_from(g).unwrap())), data),
    }
}

/// Runs a request against `servo`; returns the status and the reply data.
fn call(
    servo: &mut PositionServo,
    service: u8,
    instance: u16,
    attribute: Option<u8>,
    data: &[u8],
) -> (CipResult, Vec<u8>) {
    execute(servo, &request(service, instance, attribute, data))
}

fn get(servo: &mut PositionServo, instance: u16, attribute: u8) -> Vec<u8> {
    let (r, d) = call(servo, 0x0E, instance, Some(attribute), &[]);
    r.unwrap();
    d
}

fn set(servo: &mut PositionServo, instance: u16, attribute: u8, data: &[u8]) -> CipResult {
    call(servo, 0x10, instance, Some(attribute), data).0
}

fn err(g: General) -> CipResult {
    Err(CipError::new(g))
}

fn text(s: &str) -> Vec<u8> {
    let mut v = (s.len() as u32).to_le_bytes().to_vec();
    v.extend_from_slice(s.as_bytes());
    v
}

#[test]
fn example_6_3_v0_as_real_and_as_integer() {
    let mut servo = PositionServo::new();
    assert_eq!(get(&mut servo, 100, 2), 0.0f32.to_le_bytes());
    set(&mut servo, 100, 2, &42.75f32.to_le_bytes()).unwrap();
    assert_eq!(get(&mut servo, 100, 2), 42.75f32.to_le_bytes());
    assert_eq!(get(&mut servo, 100, 0), 43u32.to_le_bytes());
    assert_eq!(get(&mut servo, 100, 4), text("42.75"));
    // The write-only EPM attributes read the RAM copy.
    assert_eq!(get(&mut servo, 100, 3), get(&mut servo, 100, 2));
    assert_eq!(get(&mut servo, 100, 1), get(&mut servo, 100, 0));
    assert_eq!(get(&mut servo, 100, 5), get(&mut servo, 100, 4));
    // Integer in, REAL out.
    set(&mut servo, 101, 0, &(-7i32).to_le_bytes()).unwrap();
    assert_eq!(get(&mut servo, 101, 2), (-7.0f32).to_le_bytes());
    // Strings, both ways.
    set(&mut servo, 102, 4, &text("3.25")).unwrap();
    assert_eq!(get(&mut servo, 102, 2), 3.25f32.to_le_bytes());
    set(&mut servo, 261, 4, &text("0xC00000BC")).unwrap();
    assert_eq!(get(&mut servo, 261, 4), text("3221225660"));
    assert_eq!(get(&mut servo, 34, 4), text("0"));
    let (r, all) = call(&mut servo, 0x01, 100, None, &[]);
    r.unwrap();
    let mut expected = 43u32.to_le_bytes().to_vec();
    expected.extend_from_slice(&42.75f32.to_le_bytes());
    expected.extend(text("42.75"));
    assert_eq!(all, expected);
}

#[test]
fn epm_copy_is_separate_and_survives_a_reset() {
    let mut servo = PositionServo::new();
    set(&mut servo, id::ACCEL_LIMIT, 3, &500.0f32.to_le_bytes()).unwrap();
    set(&mut servo, id::ACCEL_LIMIT, 2, &250.0f32.to_le_bytes()).unwrap();
    set(&mut servo, id::V0, 1, &9u32.to_le_bytes()).unwrap();
    assert_eq!(servo.variables().real(id::ACCEL_LIMIT), 250.0);
    let stored = servo.storage().value(id::ACCEL_LIMIT);
    assert_eq!(stored, Some(500.0f32.to_bits()));
    servo.reset(0).unwrap();
    assert_eq!(servo.variables().real(id::ACCEL_LIMIT), 500.0);
    assert_eq!(servo.variables().real(id::V0), 9.0);
    servo.reset(1).unwrap();
    assert_eq!(servo.variables().real(id::ACCEL_LIMIT), 100.0);
    assert_eq!(servo.storage().value(id::V0), None);
}

/// ACCEL_LIMIT and V0 as a drive powered up from `store` has them.
fn after_power_up(store: SharedStore) -> (f32, f32) {
    let servo = PositionServo::with_storage(EpmCopy::in_store(store));
    let v = servo.variables();
    (v.real(id::ACCEL_LIMIT), v.real(id::V0))
}

/// Writes ACCEL_LIMIT to RAM and EPM (attribute 3); true if it was accepted.
fn save_accel(store: SharedStore, value: f32) -> bool {
    let mut servo = PositionServo::with_storage(EpmCopy::in_store(store));
    set(&mut servo, id::ACCEL_LIMIT, 3, &value.to_le_bytes()).is_ok()
}

#[test]
fn epm_survives_a_restart_in_the_store() {
    let store = testing::store();
    assert!(save_accel(store, 500.0));
    let mut servo = PositionServo::with_storage(EpmCopy::in_store(store));
    set(&mut servo, id::V0, 1, &9u32.to_le_bytes()).unwrap();
    assert_eq!(after_power_up(store), (500.0, 9.0));
    servo.reset(1).unwrap();
    assert_eq!(after_power_up(store), (100.0, 0.0));
    // A store that cannot write: 0x19, and the EPM copy is unchanged.
    let mut dead = CutFlash::new();
    dead.cut_after(0);
    let mut failing = PositionServo::with_storage(EpmCopy::in_store(testing::store_on(dead).0));
    assert_eq!(
        set(&mut failing, id::ACCEL_LIMIT, 3, &7.0f32.to_le_bytes()),
        err(General::StoreOperationFailure)
    );
    assert_eq!(failing.storage().value(id::ACCEL_LIMIT), None);
}

#[test]
fn every_power_cut_during_an_epm_write_keeps_the_old_or_the_new_value() {
    let steps = testing::every_power_cut(
        |store| assert!(save_accel(store, 500.0)),
        |store| save_accel(store, 750.0),
        after_power_up,
    );
    assert!(steps > 50, "{steps} steps");
}

#[test]
fn errors_carry_the_proper_cip_status() {
    let mut servo = PositionServo::new();
    let four = 1u32.to_le_bytes();
    assert_eq!(
        call(&mut servo, 0x0E, 99, Some(0), &[]).0,
        err(General::ObjectDoesNotExist)
    );
    assert_eq!(
        call(&mut servo, 0x0E, 999, Some(0), &[]).0,
        err(General::ObjectDoesNotExist)
    );
    assert_eq!(
        call(&mut servo, 0x0E, 100, Some(6), &[]).0,
        err(General::AttributeNotSupported)
    );
    assert_eq!(
        call(&mut servo, 0x0E, 100, None, &[]).0,
        err(General::PathDestinationUnknown)
    );
    assert_eq!(
        call(&mut servo, 0x0E, 100, Some(0), &four).0,
        err(General::TooMuchData)
    );
    assert_eq!(
        call(&mut servo, 0x4C, 100, Some(0), &[]).0,
        err(General::ServiceNotSupported)
    );
    assert_eq!(
        set(&mut servo, id::STATUS, 0, &four),
        err(General::AttributeNotSettable)
    );
    assert_eq!(
        set(&mut servo, id::ACTUAL_POSITION, 2, &four),
        err(General::AttributeNotSettable)
    );
    assert_eq!(
        set(&mut servo, id::ENABLE, 1, &four),
        err(General::AttributeNotSettable)
    );
    assert_eq!(
        set(&mut servo, id::DRIVE_MODE, 0, &7u32.to_le_bytes()),
        err(General::InvalidAttributeValue)
    );
    assert_eq!(
        set(&mut servo, id::V0, 2, &f32::NAN.to_le_bytes()),
        err(General::InvalidAttributeValue)
    );
    assert_eq!(
        set(&mut servo, id::V0, 2, &[1, 2, 3]),
        err(General::NotEnoughData)
    );
    assert_eq!(
        set(&mut servo, id::V0, 0, &[1, 2, 3, 4, 5]),
        err(General::TooMuchData)
    );
    assert_eq!(
        set(&mut servo, id::V0, 4, &[3, 0, 0]),
        err(General::NotEnoughData)
    );
    assert_eq!(
        set(&mut servo, id::V0, 4, &[3, 0, 0, 0, b'1']),
        err(General::NotEnoughData)
    );
    assert_eq!(
        set(&mut servo, id::V0, 4, &[1, 0, 0, 0, b'1', b'2']),
        err(General::TooMuchData)
    );
    assert_eq!(
        set(&mut servo, id::V0, 4, &text("one")),
        err(General::InvalidAttributeValue)
    );
    assert_eq!(
        set(&mut servo, id::MOVED, 2, &1.0f32.to_le_bytes()),
        err(General::DeviceStateConflict)
    );
    // Nothing changed.
    assert_eq!(servo.variables().raw(id::V0), 0);
    // The class: revision and highest variable ID.
    assert_eq!(get(&mut servo, 0, 1), 1u16.to_le_bytes());
    assert_eq!(get(&mut servo, 0, 2), 275u16.to_le_bytes());
    // Class attributes 1-7 through Get_Attributes_All: revision 1, max instance 275,
    // 65 instances, no optional attributes, the optional services Get_Attribute_List and
    // Set_Attribute_List, 7 class attributes, attributes 0-5.
    let (r, all) = call(&mut servo, 0x01, 0, None, &[]);
    r.unwrap();
    assert_eq!(
        all,
        [1, 0, 0x13, 0x01, 65, 0, 0, 0, 2, 0, 3, 0, 4, 0, 7, 0, 5, 0]
    );
}

#[test]
fn attribute_lists_on_a_variable() {
    let mut servo = PositionServo::new();
    set(&mut servo, 100, 2, &2.5f32.to_le_bytes()).unwrap();
    // Get_Attribute_List of V0 as integer and REAL: count, then id, status, value each.
    let (r, d) = call(&mut servo, 0x03, 100, None, &[2, 0, 0, 0, 2, 0]);
    r.unwrap();
    let mut expected = vec![2, 0, 0, 0, 0, 0, 3, 0, 0, 0, 2, 0, 0, 0];
    expected.extend_from_slice(&2.5f32.to_le_bytes());
    assert_eq!(d, expected);
    // Set_Attribute_List: V0 = 7 (integer), then an out-of-range text to the read-only
    // STATUS-free attribute 3 (EPM REAL) = 1.5: both applied, each with status 0.
    let mut list = vec![2, 0, 0, 0];
    list.extend_from_slice(&7u32.to_le_bytes());
    list.extend_from_slice(&[3, 0]);
    list.extend_from_slice(&1.5f32.to_le_bytes());
    let (r, d) = call(&mut servo, 0x04, 100, None, &list);
    r.unwrap();
    assert_eq!(d, [2, 0, 0, 0, 0, 0, 3, 0, 0, 0]);
    assert_eq!(servo.variables().real(id::V0), 1.5);
    assert_eq!(servo.storage().value(id::V0), Some(1.5f32.to_bits()));
    // An unknown attribute ends the list (its value's length is unknown); a read-only
    // one is skipped and the next entry still applies.
    let mut list = vec![2, 0, 9, 0];
    list.extend_from_slice(&text("5"));
    let (r, d) = call(&mut servo, 0x04, 100, None, &list);
    assert_eq!(r, Err(CipError::new(General::AttributeListError)));
    assert_eq!(d, [1, 0, 9, 0, 0x14, 0]);
    let mut list = vec![2, 0, 0, 0];
    list.extend_from_slice(&1u32.to_le_bytes());
    list.extend_from_slice(&[4, 0]);
    list.extend_from_slice(&text("3"));
    let (r, d) = call(&mut servo, 0x04, id::STATUS, None, &list);
    assert_eq!(r, Err(CipError::new(General::AttributeListError)));
    assert_eq!(d, [2, 0, 0, 0, 0x0E, 0, 4, 0, 0x0E, 0]);
}

#[test]
fn other_classes_are_not_ours() {
    let mut servo = PositionServo::new();
    let (r, _) = execute(&mut servo, &[0x0E, 3, 0x20, 0x65, 0x24, 0x01, 0x30, 0x01]);
    assert_eq!(r, err(General::PathDestinationUnknown));
    assert_eq!(
        servo.classes().iter().map(|c| c.id).collect::<Vec<_>>(),
        [0x64]
    );
}

#[test]
fn assemblies_have_the_sizes_of_tables_14_to_21() {
    let servo = PositionServo::new();
    let expected = [
        (103, AssemblyRole::Config, 0, false),
        (104, AssemblyRole::Input, 8, false),
        (105, AssemblyRole::Input, 36, false),
        (106, AssemblyRole::Output, 8, true),
        (108, AssemblyRole::Output, 24, true),
        (109, AssemblyRole::Output, 4, true),
        (198, AssemblyRole::InputOnlyHeartbeat, 0, false),
        (199, AssemblyRole::ListenOnlyHeartbeat, 0, false),
    ];
    let got: Vec<_> = servo
        .assemblies()
        .iter()
        .map(|a| (a.instance, a.role, a.size, a.run_idle_header))
        .collect();
    assert_eq!(got, expected);
}

/// 7.3, Assembly Object: "Instance Services: Get_Attribute_All, Get_Attribute_Single". Get_
/// Attributes_All on an instance answers its data, attribute 3, as Get_Attribute_Single does.
#[test]
fn assembly_instances_answer_get_attributes_all_with_their_data() {
    let mut servo = PositionServo::new();
    servo.write(id::V0, Value::Real(2.5), false).unwrap();
    for (instance, size) in [
        (103u8, 0),
        (104, 8),
        (105, 36),
        (106, 8),
        (108, 24),
        (109, 4),
    ] {
        let path = [0x20, 0x04, 0x24, instance];
        let (r, all) = execute(&mut servo, &[&[0x01, 2][..], &path].concat());
        assert_eq!(r, Ok(()), "assembly {instance}");
        let single = [&[0x0E, 3][..], &path, &[0x30, 0x03]].concat();
        let (r, data) = execute(&mut servo, &single);
        assert_eq!(r, Ok(()));
        assert_eq!((all.len(), &all), (size, &data), "assembly {instance}");
    }
    // A service the manual does not list for the class is still refused.
    let (r, _) = execute(&mut servo, &[0x02, 3, 0x20, 0x04, 0x24, 105, 0x30, 0x03]);
    assert_eq!(r, err(General::ServiceNotSupported));
}

fn read(servo: &mut PositionServo, instance: u16) -> Vec<u8> {
    let mut buf = [0u8; 64];
    let n = servo.read_assembly(instance, &mut buf).unwrap();
    buf[..n].to_vec()
}

fn words(data: &[u8]) -> Vec<[u8; 4]> {
    data.chunks(4).map(|c| c.try_into().unwrap()).collect()
}

#[test]
fn control_and_monitor_assemblies() {
    let mut servo = PositionServo::new();
    for (v, x) in [(id::DRIVE_MODE, 1), (id::REFERENCE_SOURCE, 1)] {
        servo.write(v, Value::Integer(x), false).unwrap();
    }
    let mut out = 1.0f32.to_le_bytes().to_vec();
    out.extend_from_slice(&25.0f32.to_le_bytes());
    servo.write_assembly(106, &out).unwrap();
    assert_eq!(read(&mut servo, 106), out);
    assert_eq!(servo.variables().real(id::REFERENCE), 25.0);
    servo.poll(Instant(0));
    let w = words(&read(&mut servo, 104));
    assert_eq!(u32::from_le_bytes(w[0]) & 1, 1, "STATUS2 enabled");
    assert_eq!(u32::from_le_bytes(w[1]), 1 << 2, "INPUTS: A3");
    for ms in 1..=20 {
        servo.poll(Instant(ms * 1000));
    }
    let w = words(&read(&mut servo, 105));
    assert_eq!(w.len(), 9);
    assert_eq!(f32::from_le_bytes(w[0]), 25.0, "no ramp: at speed");
    assert_eq!(
        f32::from_le_bytes(w[3]),
        servo.variables().real(id::PHASE_CURRENT)
    );
    // Table 13: link B in carries the phase current as REAL.
    servo
        .write(262, Value::Integer(0xC000_00BC), false)
        .unwrap();
    let w = words(&read(&mut servo, 105));
    assert_eq!(w[6], w[3]);
    // 108: enable, reference, then links A-D out (V4-V7 by default).
    let mut ext = Vec::new();
    for f in [0.0f32, 5.0, 1.0, 2.0, 3.0, 4.0] {
        ext.extend_from_slice(&f.to_le_bytes());
    }
    servo.write_assembly(108, &ext).unwrap();
    assert_eq!(servo.variables().raw(id::ENABLE), 0);
    assert_eq!(servo.variables().real(id::V0 + 7), 4.0);
    assert_eq!(read(&mut servo, 108), ext);
    servo.write_assembly(109, &0xBEEFu32.to_le_bytes()).unwrap();
    assert_eq!(servo.variables().raw(id::CIP_HEARTBEAT), 0xBEEF);
    assert_eq!(
        servo.write_assembly(106, &[0; 7]),
        err(General::NotEnoughData)
    );
    assert_eq!(
        servo.write_assembly(105, &[0; 36]),
        err(General::AttributeNotSettable)
    );
    assert_eq!(
        servo.write_assembly(107, &[]),
        err(General::PathDestinationUnknown)
    );
}

#[test]
fn status2_maps_table_18() {
    let all_status = [0, 3, 5, 7, 8, 13, 19, 22, 24, 25, 27, 28, 29]
        .iter()
        .fold(0u32, |a, b| a | 1 << b);
    assert_eq!(status2(all_status, 0), 0x1FFF);
    assert_eq!(status2(0, 1 << 21 | 1 << 22), 0x6000);
    assert_eq!(status2(status::MOTION_COMPLETED, status::EX_OWNED), 1 << 9);
    assert_eq!(status2(!all_status, !(1 << 21 | 1 << 22)), 0);
    assert_eq!(assemblies::INFOS.len(), assemblies::ASSEMBLIES.len());
}

fn mcast(alloc_control: u8, num_mcast: u16, start: [u8; 4], ttl: u8) -> Multicast {
    Multicast {
        ttl,
        config: MulticastConfig {
            alloc_control,
            num_mcast,
            start: Ipv4Addr::from(start),
        },
    }
}

#[test]
fn multicast_is_variables_273_and_275() {
    let mut servo = PositionServo::new();
    assert_eq!(servo.multicast(), Some(mcast(0, 1, [239, 192, 15, 32], 1)));
    servo
        .write(id::MULTICAST_ADDRESS, Value::Integer(0xEFC0_0203), false)
        .unwrap();
    servo
        .write(id::MULTICAST_TTL, Value::Integer(4), false)
        .unwrap();
    assert_eq!(servo.multicast(), Some(mcast(1, 1, [239, 192, 2, 3], 4)));
    servo
        .set_multicast(mcast(1, 1, [239, 192, 9, 9], 16))
        .unwrap();
    assert_eq!(servo.variables().raw(id::MULTICAST_ADDRESS), 0xEFC0_0909);
    assert_eq!(servo.variables().raw(id::MULTICAST_TTL), 16);
    assert_eq!(
        servo.storage().value(id::MULTICAST_TTL),
        Some(16),
        "non-volatile"
    );
    assert_eq!(
        servo.set_multicast(mcast(1, 2, [239, 192, 9, 9], 16)),
        err(General::InvalidAttributeValue)
    );
    servo.set_multicast(mcast(0, 0, [0; 4], 16)).unwrap();
    assert_eq!(
        servo.variables().raw(id::MULTICAST_ADDRESS),
        DEFAULT_MULTICAST
    );
    assert_eq!(
        servo.admit(&change_of_state_request()),
        Err(CipError::connection(0x0103))
    );
}

#[test]
fn selectable_by_name() {
    let p = crate::Profile::from_name("position-servo").unwrap();
    assert_eq!(p.name(), "position-servo");
    assert_eq!(p.identity().product_name, "EnetIP 940");
    let mut p = p;
    assert_eq!(
        p.admit(&change_of_state_request()),
        Err(CipError::connection(0x0103))
    );
}

/// An exclusive owner of 106/104 with a change-of-state trigger, as the stack admits it.
fn change_of_state_request() -> enip_stack::device::OpenRequest<'static> {
    use enip_stack::device::{ConnectionPoints, Direction, OpenRequest};
    use enip_stack::wire::forward_open::{ConnectionType, NetworkParams, Triad};
    let params = |size| NetworkParams {
        redundant_owner: false,
        connection_type: ConnectionType::PointToPoint,
        priority: 0,
        variable: false,
        size,
    };
    OpenRequest {
        kind: enip_stack::device::Kind::ExclusiveOwner,
        transport_class: 1,
        trigger: enip_stack::device::Trigger::ChangeOfState,
        inhibit: enip_stack::Duration::from_millis(0),
        points: ConnectionPoints {
            config: Some(103),
            consumed: Some(106),
            produced: Some(104),
        },
        o_t: Direction {
            rpi_us: 10_000,
            params: params(14),
        },
        t_o: Direction {
            rpi_us: 10_000,
            params: params(10),
        },
        timeout_multiplier: 2,
        originator: Ipv4Addr::new(198, 18, 0, 1),
        triad: Triad {
            connection_serial: 1,
            vendor_id: 1,
            originator_serial: 1,
        },
        key: None,
        config_data: None,
    }
}
