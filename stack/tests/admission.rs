//! The device's say on connections: a Forward_Open admission hook that limits Class 1
//! connections, refuses configurations and RPIs with its own statuses; opened and closed
//! events with the originator and the close reason; and inputs the device says changed,
//! produced by an application-triggered connection without any clock of the device's.

mod common;

use common::*;
use enip_stack::cip::connection_status::{OUT_OF_CONNECTIONS, OWNERSHIP_CONFLICT};
use enip_stack::cip::context::RequestContext;
use enip_stack::cip::object::{AttributeDef, ClassDef, DataType};
use enip_stack::cip::{CipError, CipResult, General};
use enip_stack::device::Kind;
use enip_stack::device::{
    AttributeRef, CloseReason, ConnectionEvent, ConnectionInfo, Device, InputChanges, OpenRequest,
};
use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use enip_stack::wire::forward_open::{ForwardOpenReplyRepr, NetworkParams};
use enip_stack::wire::io_datagram::Packet;
use enip_stack::wire::Writer;
use enip_stack::{AssemblyInfo, AssemblyRole, IdentityInfo, Instant, SocketId};

const INPUT: u16 = 100;
const OUTPUT: u16 = 150;
const CONFIG: u16 = 151;
const INPUT_ONLY: u16 = 152;
/// The extended status this device chose for a configuration it does not accept.
const BAD_CONFIG: u16 = 0x0321;
/// The device's own RPI floor, 2 ms.
const MIN_RPI_US: u32 = 2_000;
/// A vendor class whose attribute 1 is the first input byte.
const SETPOINT: u16 = 0x71;

const ASSEMBLIES: [AssemblyInfo; 4] = [
    AssemblyInfo {
        instance: INPUT,
        role: AssemblyRole::Input,
        size: 4,
        run_idle_header: false,
    },
    AssemblyInfo {
        instance: OUTPUT,
        role: AssemblyRole::Output,
        size: 4,
        run_idle_header: true,
    },
    AssemblyInfo {
        instance: CONFIG,
        role: AssemblyRole::Config,
        size: 2,
        run_idle_header: false,
    },
    AssemblyInfo {
        instance: INPUT_ONLY,
        role: AssemblyRole::InputOnlyHeartbeat,
        size: 0,
        run_idle_header: false,
    },
];

/// One Class 1 connection at a time; configuration byte 0 at most 10; RPI at least 2 ms.
/// It has no clock: its inputs change only when attribute 1 of class 0x71 is set.
#[derive(Default)]
struct Station {
    inputs: [u8; 4],
    config: [u8; 2],
    class1_open: usize,
    events: Vec<ConnectionEvent>,
    admitted: Vec<(Kind, Option<Vec<u8>>)>,
    changes: InputChanges,
}

impl Device for Station {
    fn identity(&self) -> &IdentityInfo {
        &IDENTITY
    }
    fn assemblies(&self) -> &[AssemblyInfo] {
        &ASSEMBLIES
    }
    fn read_assembly(&mut self, instance: u16, out: &mut [u8]) -> CipResult<usize> {
        match instance {
            INPUT => out.copy_from_slice(&self.inputs),
            CONFIG => out.copy_from_slice(&self.config),
            _ => out.fill(0),
        }
        Ok(out.len())
    }
    fn write_assembly(&mut self, instance: u16, data: &[u8]) -> CipResult {
        match instance {
            CONFIG if data[1] == 0xEE => Err(General::InvalidAttributeValue.into()),
            CONFIG => {
                self.config.copy_from_slice(data);
                Ok(())
            }
            _ => Ok(()),
        }
    }
    fn classes(&self) -> &[ClassDef] {
        const CLASS: ClassDef = ClassDef {
            id: SETPOINT,
            name: "Setpoint",
            revision: 1,
            max_instance: 1,
            attributes: &[AttributeDef::get_set(1, DataType::Usint, "Value")],
            get_all: &[],
            optional_attributes: &[],
        };
        &[CLASS]
    }
    fn get_attribute(
        &mut self,
        _: &RequestContext,
        _: &AttributeRef<'_>,
        w: &mut Writer<'_>,
    ) -> CipResult {
        Ok(w.u8(self.inputs[0])?)
    }
    fn set_attribute(
        &mut self,
        _: &RequestContext,
        _: &AttributeRef<'_>,
        value: &[u8],
    ) -> CipResult {
        self.inputs[0] = value[0];
        self.changes.mark(INPUT);
        Ok(())
    }
    fn input_changes(&mut self) -> Option<&mut InputChanges> {
        Some(&mut self.changes)
    }
    fn admit(&mut self, request: &OpenRequest<'_>) -> CipResult {
        self.admitted
            .push((request.kind, request.config_data.map(<[u8]>::to_vec)));
        if request.is_class1() && self.class1_open > 0 {
            return Err(CipError::connection(
                if request.kind == Kind::ExclusiveOwner {
                    OWNERSHIP_CONFLICT
                } else {
                    OUT_OF_CONNECTIONS
                },
            ));
        }
        if request.config_data.is_some_and(|d| d[0] > 10) {
            return Err(CipError::connection(BAD_CONFIG).with_additional(BAD_CONFIG, 1));
        }
        request.refuse_rpi(MIN_RPI_US, 10_000_000)
    }
    fn connection_event(&mut self, event: ConnectionEvent) {
        match event {
            ConnectionEvent::Opened(c) if c.kind != Kind::Explicit => self.class1_open += 1,
            ConnectionEvent::Closed(c, _) if c.kind != Kind::Explicit => self.class1_open -= 1,
            _ => {}
        }
        self.events.push(event);
    }
}

fn harness() -> Harness<Station> {
    Harness::with_device(Station::default())
}

/// An exclusive owner (or, with `input_only`, an input-only connection) at `rpi` with the
/// 2-byte configuration `config`.
fn open(
    h: &mut Harness<Station>,
    serial: u16,
    input_only: bool,
    config: &[u8],
    rpi: u32,
) -> (u8, Vec<u16>, Vec<u8>) {
    let consumed = if input_only { INPUT_ONLY } else { OUTPUT };
    let path = io_path(
        Some(CONFIG.into()),
        consumed.into(),
        INPUT.into(),
        Some(config),
    );
    let mut f = fo(serial, &path, rpi);
    f.o_t_params = NetworkParams::from_u16(0x4800 | if input_only { 2 } else { 2 + 4 + 4 });
    f.t_o_params = NetworkParams::from_u16(0x4800 | (2 + 4));
    status(&h.forward_open(&f))
}

fn opened(events: &[ConnectionEvent]) -> Vec<ConnectionInfo> {
    events
        .iter()
        .filter_map(|e| match e {
            ConnectionEvent::Opened(c) => Some(*c),
            _ => None,
        })
        .collect()
}

fn closed(events: &[ConnectionEvent]) -> Vec<(ConnectionInfo, CloseReason)> {
    events
        .iter()
        .filter_map(|e| match e {
            ConnectionEvent::Closed(c, r) => Some((*c, *r)),
            _ => None,
        })
        .collect()
}

#[test]
fn a_second_class1_connection_is_refused_as_the_device_says() {
    let mut h = harness();
    assert_eq!(open(&mut h, 1, false, &[1, 0], 10_000).0, 0);
    let (g, ext, _) = open(&mut h, 2, false, &[1, 0], 10_000);
    assert_eq!((g, ext), (0x01, vec![OWNERSHIP_CONFLICT]));
    let (g, ext, _) = open(&mut h, 3, true, &[1, 0], 10_000);
    assert_eq!((g, ext), (0x01, vec![OUT_OF_CONNECTIONS]));
    // After the first closes, the slot is the device's to give again.
    assert_eq!(close(&mut h, 1).0, 0);
    assert_eq!(open(&mut h, 3, true, &[1, 0], 10_000).0, 0);
    assert_eq!(h.adapter.connections().len(), 1);
}

#[test]
fn the_device_sees_the_whole_request_before_the_connection_exists() {
    let mut h = harness();
    assert_eq!(open(&mut h, 1, false, &[7, 9], 10_000).0, 0);
    assert_eq!(
        h.adapter.device().admitted,
        [(Kind::ExclusiveOwner, Some(vec![7, 9]))]
    );
    assert_eq!(h.adapter.device().config, [7, 9], "written once admitted");
}

#[test]
fn a_refused_configuration_gets_the_devices_extended_status() {
    let mut h = harness();
    let (g, words, _) = open(&mut h, 1, false, &[11, 0], 10_000);
    assert_eq!((g, words), (0x01, vec![BAD_CONFIG, 1]));
    assert_eq!(h.adapter.device().config, [0, 0], "nothing written");
    assert!(h.adapter.connections().is_empty());
    // A configuration write_assembly refuses is "target not configured" (0x0110).
    let (g, words, _) = open(&mut h, 2, false, &[1, 0xEE], 10_000);
    assert_eq!((g, words), (0x01, vec![0x0110]));
    assert!(h.adapter.connections().is_empty());
    assert!(opened(&h.adapter.device().events).is_empty());
}

#[test]
fn the_devices_rpi_floor_is_refused_with_the_acceptable_value() {
    let mut h = harness();
    let (g, words, _) = open(&mut h, 1, false, &[1, 0], 1_000);
    assert_eq!(g, 0x01);
    // 0x0112, both directions "minimum" (2), acceptable 2000 us each.
    assert_eq!(words, [0x0112, 0x0202, 2000, 0, 2000, 0]);
}

#[test]
fn opened_and_closed_events_carry_the_originator_and_the_reason() {
    let mut h = harness();
    // Forward_Close.
    assert_eq!(open(&mut h, 1, false, &[1, 0], 10_000).0, 0);
    let o = opened(&h.adapter.device().events)[0];
    assert_eq!(o.originator, SCANNER_IP);
    assert_eq!(o.kind, Kind::ExclusiveOwner);
    assert_eq!(
        (o.points.config, o.points.consumed, o.points.produced),
        (Some(CONFIG), Some(OUTPUT), Some(INPUT))
    );
    assert_eq!((o.o_t_rpi_us, o.t_o_rpi_us), (10_000, 10_000));
    assert_eq!(o.triad.connection_serial, 1);
    assert_eq!(close(&mut h, 1).0, 0);
    let (c, reason) = closed(&h.adapter.device().events)[0];
    assert_eq!(
        (c.slot, c.originator, reason),
        (o.slot, SCANNER_IP, CloseReason::ForwardClose)
    );

    // Timeout: no O->T data for the grace period, then multiplier x RPI.
    assert_eq!(open(&mut h, 2, false, &[1, 0], 10_000).0, 0);
    let mut out = [0u8; 64];
    while h.adapter.poll_io(Instant(10_000_000), &mut out).is_some() {}
    let (_, reason) = closed(&h.adapter.device().events)[1];
    assert_eq!(reason, CloseReason::Timeout);

    // Session closed: a Class 3 connection ends with its session.
    let mr = [0x20, 0x02, 0x24, 0x01];
    let mut f = fo(3, &mr, 100_000);
    f.transport = 0xA3;
    f.o_t_params = NetworkParams::from_u16(0x4800 | 500);
    f.t_o_params = NetworkParams::from_u16(0x4800 | 500);
    assert_eq!(status(&h.forward_open(&f)).0, 0);
    h.adapter.tcp_close(SocketId(0), h.now);
    let (c, reason) = closed(&h.adapter.device().events)[2];
    assert_eq!(
        (c.kind, c.originator, reason),
        (Kind::Explicit, SCANNER_IP, CloseReason::SessionClosed)
    );
}

#[test]
fn a_reset_closes_every_connection_with_its_reason() {
    let mut h = harness();
    assert_eq!(open(&mut h, 1, false, &[1, 0], 10_000).0, 0);
    h.adapter.close_all(CloseReason::Reset);
    assert!(h.adapter.connections().is_empty());
    assert_eq!(closed(&h.adapter.device().events)[0].1, CloseReason::Reset);
}

#[test]
fn inputs_changed_by_a_write_are_produced_within_the_inhibit_time() {
    let mut h = harness();
    // Application triggered, 5 ms production inhibit, 100 ms RPI.
    let mut path = vec![0x43, 5];
    path.extend(io_path(
        Some(CONFIG.into()),
        OUTPUT.into(),
        INPUT.into(),
        Some(&[1, 0]),
    ));
    let mut f = fo(1, &path, 100_000);
    f.transport = 0x21;
    f.o_t_params = NetworkParams::from_u16(0x4800 | (2 + 4 + 4));
    f.t_o_params = NetworkParams::from_u16(0x4800 | (2 + 4));
    let (g, _, data) = status(&h.forward_open(&f));
    assert_eq!(g, 0);
    let t_o = ForwardOpenReplyRepr::parse(&data)
        .unwrap()
        .t_o_connection_id;
    let mut out = [0u8; 64];
    // The production at open, then nothing due until the RPI.
    assert!(h.adapter.poll_io(Instant(0), &mut out).is_some());
    assert_eq!(h.adapter.io_deadline(), Some(Instant(100_000)));

    // At 1 ms an explicit write changes the inputs; the device has no clock of its own.
    h.now = Instant(1_000);
    let setpoint = [
        SegmentRepr::Logical(LogicalType::Class, SETPOINT.into()),
        SegmentRepr::Logical(LogicalType::Instance, 1),
        SegmentRepr::Logical(LogicalType::Attribute, 1),
    ];
    assert_eq!(status(&h.request(0x10, &setpoint, &[0x42])).0, 0);
    assert_eq!(h.adapter.io_deadline(), Some(Instant(0)), "due at once");
    let (to, len) = h.adapter.poll_io(h.now, &mut out).unwrap();
    assert_eq!(to.ip(), &SCANNER_IP);
    let p = Packet::new_checked(&out[..len]).unwrap();
    assert_eq!(p.connection_id(), t_o);
    assert_eq!(
        p.connected_data(),
        [1, 0, 0x42, 0, 0, 0],
        "new sequence count, new data"
    );

    // A second change at 2 ms waits out the 5 ms inhibit time after that production.
    h.now = Instant(2_000);
    assert_eq!(status(&h.request(0x10, &setpoint, &[0x43])).0, 0);
    assert_eq!(h.adapter.io_deadline(), Some(Instant(6_000)));
    assert!(h.adapter.poll_io(Instant(5_999), &mut out).is_none());
    let (_, len) = h.adapter.poll_io(Instant(6_000), &mut out).unwrap();
    assert_eq!(
        Packet::new_checked(&out[..len]).unwrap().connected_data(),
        [2, 0, 0x43, 0, 0, 0]
    );
    // Unchanged inputs trigger nothing: the next datagram is the RPI's, same sequence count.
    assert_eq!(status(&h.request(0x0E, &setpoint, &[])).0, 0);
    assert_eq!(h.adapter.io_deadline(), Some(Instant(106_000)));
}

/// A device whose input assembly size is its configuration (class 0x72 attribute 1), as
/// the Parker controller's is: a resize under a running connection closes it.
struct Resizable {
    assemblies: [AssemblyInfo; 2],
    events: Vec<ConnectionEvent>,
    /// Accept the input carried from 2 bytes up to its size (else exactly its size).
    ranged_input: bool,
}

impl Device for Resizable {
    fn identity(&self) -> &IdentityInfo {
        &IDENTITY
    }
    fn assemblies(&self) -> &[AssemblyInfo] {
        &self.assemblies
    }
    fn read_assembly(&mut self, _instance: u16, out: &mut [u8]) -> CipResult<usize> {
        out.fill(7);
        Ok(out.len())
    }
    fn write_assembly(&mut self, _instance: u16, _data: &[u8]) -> CipResult {
        Ok(())
    }
    fn classes(&self) -> &[ClassDef] {
        const CLASS: ClassDef = ClassDef {
            id: 0x72,
            name: "Layout",
            revision: 1,
            max_instance: 1,
            attributes: &[AttributeDef::get_set(1, DataType::Uint, "Input size")],
            get_all: &[],
            optional_attributes: &[],
        };
        &[CLASS]
    }
    fn set_attribute(
        &mut self,
        _: &RequestContext,
        _: &AttributeRef<'_>,
        value: &[u8],
    ) -> CipResult {
        self.assemblies[0].size = u16::from_le_bytes([value[0], value[1]]);
        Ok(())
    }
    fn connection_event(&mut self, event: ConnectionEvent) {
        self.events.push(event);
    }
    fn accepts_connection_size(&self, assembly: &AssemblyInfo, data: usize) -> bool {
        match assembly.instance {
            INPUT if self.ranged_input => data >= 2,
            _ => data == usize::from(assembly.size),
        }
    }
}

#[test]
fn a_device_may_accept_a_range_of_connection_sizes() {
    let mut h = Harness::with_device(Resizable {
        assemblies: [ASSEMBLIES[0], ASSEMBLIES[1]],
        events: Vec::new(),
        ranged_input: true,
    });
    let path = io_path(None, OUTPUT.into(), INPUT.into(), None);
    let mut f = fo(1, &path, 10_000);
    f.o_t_params = NetworkParams::from_u16(0x4800 | (2 + 4 + 4));
    for (t_o, expected) in [(2 + 1, 0x01), (2 + 5, 0x01), (2 + 3, 0)] {
        f.t_o_params = NetworkParams::from_u16(0x4800 | t_o);
        let (g, words, _) = status(&h.forward_open(&f));
        assert_eq!(g, expected, "T->O {t_o}");
        if g != 0 {
            assert_eq!(words, [0x0128, 2 + 4], "the assembly's size is acceptable");
        }
    }
    // Production carries the 3 bytes the connection asked for.
    let mut out = [0u8; 64];
    let (_, len) = h.adapter.poll_io(h.now, &mut out).unwrap();
    assert_eq!(
        Packet::new_checked(&out[..len]).unwrap().connected_data(),
        [1, 0, 7, 7, 7]
    );
}

#[test]
fn an_assembly_resized_under_a_connection_closes_it() {
    let mut h = Harness::with_device(Resizable {
        assemblies: [ASSEMBLIES[0], ASSEMBLIES[1]],
        events: Vec::new(),
        ranged_input: false,
    });
    let path = io_path(None, OUTPUT.into(), INPUT.into(), None);
    let mut f = fo(1, &path, 10_000);
    f.o_t_params = NetworkParams::from_u16(0x4800 | (2 + 4 + 4));
    f.t_o_params = NetworkParams::from_u16(0x4800 | (2 + 4));
    assert_eq!(status(&h.forward_open(&f)).0, 0);
    let layout = [
        SegmentRepr::Logical(LogicalType::Class, 0x72),
        SegmentRepr::Logical(LogicalType::Instance, 1),
        SegmentRepr::Logical(LogicalType::Attribute, 1),
    ];
    assert_eq!(status(&h.request(0x10, &layout, &[8, 0])).0, 0);
    assert!(h.adapter.connections().is_empty());
    assert!(matches!(
        h.adapter
            .device()
            .events
            .iter()
            .rev()
            .find(|e| matches!(e, ConnectionEvent::Closed(..))),
        Some(ConnectionEvent::Closed(_, CloseReason::Reconfigured))
    ));
    // The next Forward_Open meets the new size: 0x0128 with the size it expects.
    let (g, words, _) = status(&h.forward_open(&f));
    assert_eq!((g, words), (0x01, vec![0x0128, 2 + 8]));
    f.t_o_params = NetworkParams::from_u16(0x4800 | (2 + 8));
    assert_eq!(status(&h.forward_open(&f)).0, 0);
    let mut out = [0u8; 64];
    let (_, len) = h.adapter.poll_io(h.now, &mut out).unwrap();
    assert_eq!(
        Packet::new_checked(&out[..len])
            .unwrap()
            .connected_data()
            .len(),
        2 + 8
    );
}
