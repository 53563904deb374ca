//! Connections of the PositionServo profile with the project's scanner: the connection
//! types of table 9 (exclusive owner, input only, listen only; cyclic and application
//! triggered; no change of state), exact sizes, and the multicast group and TTL of 2.2.1
//! (default, then moved through variables 275 and 273), checked on the wire.

use std::net::{Ipv4Addr, SocketAddrV4, UdpSocket};
use std::path::Path;
use std::time::{Duration, Instant};

use crate::common;
use crate::position_servo::{pcap, start, Target, MULTIPLIER, RPI_MS};
use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use enip_stack::wire::forward_open::{ForwardOpenRepr, NetworkParams, Triad};
use enip_stack::wire::io_datagram::Packet;
use host_tests::rig::{BOARD_IP, HOST_IP};
use host_tests::scanner::{Response, Session};

/// The default multicast group (manual 2.2.1).
const DEFAULT_GROUP: Ipv4Addr = Ipv4Addr::new(239, 192, 15, 32);
/// The group the test moves to through variable 275.
const OTHER_GROUP: Ipv4Addr = Ipv4Addr::new(239, 192, 2, 3);
/// Multicast datagrams a connection must deliver: half a second's worth at the 5 ms RPI.
const ENOUGH: usize = 100;
/// How long they may take: well inside the connection's 10 s first-packet grace (the test
/// sends no O->T data), with room for the emulated board losing periods on a busy host.
const WINDOW: Duration = Duration::from_secs(3);

/// One Forward_Open the test sends.
struct Case {
    name: &'static str,
    serial: u16,
    points: [u8; 8],
    o_t: u16,
    t_o: u16,
    multicast: bool,
    transport: u8,
}

const fn case(name: &'static str, serial: u16, out: u8, inp: u8, o_t: u16, t_o: u16) -> Case {
    Case {
        name,
        serial,
        points: [0x20, 0x04, 0x24, 103, 0x2C, out, 0x2C, inp],
        o_t,
        t_o,
        multicast: false,
        transport: 0x01,
    }
}

/// Sizes are data plus the sequence count, plus the run/idle header for outputs.
const CASES: [Case; 7] = [
    Case {
        multicast: true,
        ..case("multicast owner 106/105", 1, 106, 105, 14, 38)
    },
    Case {
        multicast: true,
        ..case("listen only 199/105", 2, 199, 105, 2, 38)
    },
    case("input only 198/104", 3, 198, 104, 2, 10),
    Case {
        transport: 0x21,
        ..case("app-triggered owner 108/104", 4, 108, 104, 30, 10)
    },
    case("keep-alive owner 109/104", 5, 109, 104, 10, 10),
    Case {
        transport: 0x11,
        ..case("change of state 109/105", 6, 109, 105, 10, 38)
    },
    case("wrong O->T size 106/104", 7, 106, 104, 10, 10),
];

/// A Class 1 Forward_Open at the examples' RPI: `o_t` and `t_o` are the connection sizes
/// (data plus sequence count, plus the run/idle header for outputs).
fn forward_open(
    serial: u16,
    path: &[u8],
    o_t: u16,
    t_o: u16,
    multicast: bool,
) -> ForwardOpenRepr<'_> {
    let rpi = RPI_MS * 1000;
    ForwardOpenRepr {
        large: false,
        priority_tick: 0x0A,
        timeout_ticks: 0x0E,
        o_t_connection_id: 0,
        t_o_connection_id: 0x5050_0000 + u32::from(serial),
        triad: Triad {
            connection_serial: serial,
            vendor_id: 0xBEEF,
            originator_serial: 0x0940,
        },
        timeout_multiplier: MULTIPLIER as u8,
        o_t_rpi: rpi,
        o_t_params: NetworkParams::from_u16(0x4800 | o_t),
        t_o_rpi: rpi,
        t_o_params: NetworkParams::from_u16(if multicast { 0x2800 } else { 0x4800 } | t_o),
        transport: 0x01,
        path,
    }
}

/// T->O datagrams of connection `id` arriving on `rx`, counted until [`ENOUGH`] have come
/// or [`WINDOW`] has passed. The count stops early rather than over a fixed time, since an
/// emulated board on a loaded host may lose whole periods while the host runs other work.
fn count_datagrams(rx: &UdpSocket, id: u32) -> usize {
    let mut buf = [0u8; 600];
    let until = Instant::now() + WINDOW;
    let mut seen = 0;
    while Instant::now() < until && seen < ENOUGH {
        if let Ok((n, _)) = rx.recv_from(&mut buf) {
            let ours = buf
                .get(..n)
                .and_then(|d| Packet::new_checked(d).ok())
                .is_some_and(|p| p.connection_id() == id);
            seen += usize::from(ours);
        }
    }
    seen
}

fn set_variable(s: &mut Session, var: u32, value: u32) -> std::io::Result<u8> {
    let path = [
        SegmentRepr::Logical(LogicalType::Class, 0x64),
        SegmentRepr::Logical(LogicalType::Instance, var),
        SegmentRepr::Logical(LogicalType::Attribute, 0),
    ];
    Ok(s.request(0x10, &path, &value.to_le_bytes())?.general)
}

/// What the connection test saw: (name, general status, extended status or datagrams).
type Seen = Vec<(&'static str, u8, usize)>;

fn connections(s: &mut Session) -> std::io::Result<Seen> {
    let rx = UdpSocket::bind(SocketAddrV4::new(Ipv4Addr::UNSPECIFIED, 2222))?;
    rx.set_read_timeout(Some(Duration::from_millis(20)))?;
    rx.join_multicast_v4(&DEFAULT_GROUP, &HOST_IP)?;
    let mut seen = Seen::new();
    let mut opened = Vec::new();
    let refused = |r: &Response| usize::from(r.additional.first().copied().unwrap_or(0));
    for c in &CASES {
        let fo = ForwardOpenRepr {
            transport: c.transport,
            ..forward_open(c.serial, &c.points, c.o_t, c.t_o, c.multicast)
        };
        match s.forward_open(&fo)? {
            Ok(reply) => {
                let n = if c.multicast && c.o_t > 2 {
                    count_datagrams(&rx, reply.t_o_connection_id)
                } else {
                    0
                };
                seen.push((c.name, 0, n));
                opened.push(reply.triad);
            }
            Err(r) => seen.push((c.name, r.general, refused(&r))),
        }
    }
    for triad in opened.drain(..) {
        s.forward_close(triad)?;
    }
    // Variables 275/273 move the group and the TTL of the next multicast connection.
    seen.push(("set 275", set_variable(s, 275, u32::from(OTHER_GROUP))?, 0));
    seen.push(("set 273", set_variable(s, 273, 5)?, 0));
    rx.join_multicast_v4(&OTHER_GROUP, &HOST_IP)?;
    let owner = &CASES[0];
    let name = "multicast owner on 239.192.2.3";
    match s.forward_open(&forward_open(8, &owner.points, owner.o_t, owner.t_o, true))? {
        Ok(reply) => {
            let n = count_datagrams(&rx, reply.t_o_connection_id);
            seen.push((name, 0, n));
            s.forward_close(reply.triad)?;
        }
        Err(r) => seen.push((name, r.general, 0)),
    }
    Ok(seen)
}

/// Connection types of table 9, sizes, no change of state, and the multicast group of
/// 2.2.1 (default, then moved through variable 275; TTL 5 through 273).
pub fn connections_scenario(t: &dyn Target) {
    let seen = t
        .ns()
        .inside(|| {
            let mut s = Session::connect(BOARD_IP, common::REPLY)?;
            // Defaults, whatever an earlier scenario on the same board set.
            set_variable(&mut s, 275, u32::from(DEFAULT_GROUP))?;
            set_variable(&mut s, 273, 1)?;
            connections(&mut s)
        })
        .expect("namespace")
        .unwrap_or_else(|e| panic!("{e}\n{}", t.log()));
    println!("{seen:?}");
    let expected: [(&str, u8, Option<usize>); 10] = [
        ("multicast owner 106/105", 0, None),
        ("listen only 199/105", 0, Some(0)),
        ("input only 198/104", 0, Some(0)),
        ("app-triggered owner 108/104", 0, Some(0)),
        ("keep-alive owner 109/104", 0, Some(0)),
        ("change of state 109/105", 0x01, Some(0x0103)),
        ("wrong O->T size 106/104", 0x01, Some(0x0127)),
        ("set 275", 0, Some(0)),
        ("set 273", 0, Some(0)),
        ("multicast owner on 239.192.2.3", 0, None),
    ];
    assert_eq!(seen.len(), expected.len(), "{seen:?}");
    for ((name, g, n), (want_name, want_g, want_n)) in seen.iter().zip(expected) {
        assert_eq!((*name, *g), (want_name, want_g), "{seen:?}");
        match want_n {
            Some(v) => assert_eq!(*n, v, "{name}"),
            None => assert_eq!(*n, ENOUGH, "{name}: multicast datagrams in {WINDOW:?}"),
        }
    }
}

/// The capture shows T->O multicast with TTL 1 on the default group, TTL 5 on the other.
pub fn multicast_on_the_wire(pcap: &Path) {
    for filter in [
        "ip.dst == 239.192.15.32 && ip.ttl == 1 && udp.dstport == 2222",
        "ip.dst == 239.192.2.3 && ip.ttl == 5 && udp.dstport == 2222",
    ] {
        let n = host_tests::capture::count(pcap, filter).expect("read capture");
        assert!(n >= 50, "{filter}: {n} frames in {}", pcap.display());
    }
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn position_servo_connections_and_multicast() {
    let name = "position_servo_connections";
    let rig = start(name);
    connections_scenario(&rig);
    common::finish(rig);
    multicast_on_the_wire(&pcap(name));
}
