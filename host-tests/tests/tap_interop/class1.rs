//! Class 1 implicit I/O with independent originators: the PyPI `ethernetip` package and npm
//! `st-ethernet-ip` as exclusive owners (data written in O->T comes back in T->O, and
//! Forward_Close frees the slot), and a listen-only connection following a multicast
//! exclusive owner, driven by the project's scanner.

use std::net::{Ipv4Addr, SocketAddrV4, UdpSocket};
use std::time::{Duration, Instant};

use serde_json::json;

use crate::common;
use host_tests::peers;
use host_tests::rig::{BOARD_IP, HOST_IP};
use host_tests::scanner::Session;
use stack::wire::forward_open::{ForwardOpen, NetworkParams, Triad};
use stack::wire::io_datagram::Packet;

/// Bound for one peer program run.
const PEER_TIMEOUT: Duration = Duration::from_secs(60);

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn ethernetip_exclusive_owner_echoes_and_frees_the_slot() {
    let rig = common::start("ethernetip_exclusive_owner");
    let input = json!({"host": BOARD_IP.to_string(), "rpi_ms": 10, "seconds": 3});
    let out = peers::run(rig.ns(), "ethernetip_class1.py", &input, PEER_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}\n{}", rig.board_log()));
    assert_eq!(out["forward_open"], 0, "{out}");
    assert_eq!(
        out["echoed"], true,
        "O->T data must come back in T->O: {out}"
    );
    assert_eq!(out["forward_close"], 0, "{out}");
    assert_eq!(
        out["reopen"], 0,
        "the closed connection's slot and ownership are free: {out}"
    );
    common::finish(rig);
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn st_ethernet_ip_exclusive_owner_echoes_and_closes() {
    let rig = common::start("st_ethernet_ip_exclusive_owner");
    let input = json!({"host": BOARD_IP.to_string(), "rpi_ms": 10, "seconds": 4});
    let out = peers::run_node(rig.ns(), "st_ethernet_ip_class1.js", &input, PEER_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}\n{}", rig.board_log()));
    assert_eq!(out["connected"], true, "{out}");
    assert_eq!(out["echoed"], true, "{out}");
    assert_eq!(out["forward_close"], true, "{out}");
    // The slot and the ownership of output 150 are free again.
    let reopened = rig
        .ns()
        .inside(|| {
            let mut s = Session::connect(BOARD_IP, common::REPLY)?;
            let path = [0x20, 0x04, 0x24, 151, 0x2C, 150, 0x2C, 100];
            let r = s.forward_open(&forward_open(1, &path, false, 38))?;
            if let Ok(ok) = &r {
                s.forward_close(ok.triad)?;
            }
            Ok::<_, std::io::Error>(r.is_ok())
        })
        .expect("namespace")
        .expect("session");
    assert!(reopened);
    common::finish(rig);
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn listen_only_follows_a_multicast_owner() {
    let rig = common::start("listen_only_multicast");
    let result = rig
        .ns()
        .inside(|| -> std::io::Result<(u32, u32, usize, u8)> {
            let rx = UdpSocket::bind(SocketAddrV4::new(Ipv4Addr::UNSPECIFIED, 2222))?;
            rx.set_read_timeout(Some(Duration::from_millis(50)))?;
            let mut s = Session::connect(BOARD_IP, common::REPLY)?;
            let owner_path = [0x20, 0x04, 0x2C, 150, 0x2C, 100];
            let owner = s
                .forward_open(&forward_open(1, &owner_path, true, 38))?
                .map_err(|e| std::io::Error::other(format!("owner refused: {e:?}")))?;
            let listen_path = [0x20, 0x04, 0x2C, 153, 0x2C, 100];
            let listener = s
                .forward_open(&forward_open(2, &listen_path, true, 2))?
                .map_err(|e| std::io::Error::other(format!("listener refused: {e:?}")))?;
            // The group comes from the TCP/IP object (attribute 9).
            let attr9 = s.request(
                0x0E,
                &[seg_class(0xF5), seg_instance(1), seg_attribute(9)],
                &[],
            )?;
            let group = Ipv4Addr::from(u32::from_le_bytes([
                attr9.data[4],
                attr9.data[5],
                attr9.data[6],
                attr9.data[7],
            ]));
            rx.join_multicast_v4(&group, &HOST_IP)?;
            let mut seen = 0;
            let mut buf = [0u8; 600];
            let until = Instant::now() + Duration::from_secs(2);
            while Instant::now() < until {
                if let Ok((n, _)) = rx.recv_from(&mut buf) {
                    if Packet::new_checked(&buf[..n])
                        .is_ok_and(|p| p.connection_id() == owner.t_o_connection_id)
                    {
                        seen += 1;
                    }
                }
            }
            // Closing the owner closes the listener too: its Forward_Close finds nothing.
            s.forward_close(owner.triad)?;
            let after = s.forward_close(listener.triad)?;
            Ok((
                owner.t_o_connection_id,
                listener.t_o_connection_id,
                seen,
                after.general,
            ))
        });
    let (owner_id, listener_id, seen, after) = result
        .expect("namespace")
        .unwrap_or_else(|e| panic!("{e}\n{}", rig.board_log()));
    assert_eq!(
        owner_id, listener_id,
        "the listener shares the owner's T->O connection"
    );
    assert!(
        seen >= 50,
        "multicast T->O at 10 ms for 2 s: only {seen} datagrams"
    );
    assert_eq!(after, 0x01, "the listener went with its owner");
    common::finish(rig);
}

/// A Forward_Open at 10 ms for the generic profile's 32-byte assemblies.
fn forward_open(serial: u16, path: &[u8], multicast: bool, o_t_size: u16) -> ForwardOpen<'_> {
    let t_o_type = if multicast { 0x2800 } else { 0x4800 };
    ForwardOpen {
        large: false,
        priority_tick: 0x0A,
        timeout_ticks: 0x0E,
        o_t_connection_id: 0,
        t_o_connection_id: 0x4C00_0000 + u32::from(serial),
        triad: Triad {
            connection_serial: serial,
            vendor_id: 0xBEEF,
            originator_serial: 0x7E57,
        },
        timeout_multiplier: 2,
        o_t_rpi: 10_000,
        o_t_params: NetworkParams::from_u16(0x4800 | o_t_size),
        t_o_rpi: 10_000,
        t_o_params: NetworkParams::from_u16(t_o_type | 34),
        transport: 0x01,
        path,
    }
}

fn seg_class(c: u32) -> stack::wire::epath::Segment<'static> {
    stack::wire::epath::Segment::Logical(stack::wire::epath::LogicalType::Class, c)
}

fn seg_instance(i: u32) -> stack::wire::epath::Segment<'static> {
    stack::wire::epath::Segment::Logical(stack::wire::epath::LogicalType::Instance, i)
}

fn seg_attribute(a: u32) -> stack::wire::epath::Segment<'static> {
    stack::wire::epath::Segment::Logical(stack::wire::epath::LogicalType::Attribute, a)
}
