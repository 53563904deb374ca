//! Class 1 implicit I/O with independent originators: the PyPI `ethernetip` package and npm
//! `st-ethernet-ip` as exclusive owners (data written in O->T comes back in T->O, and
//! Forward_Close frees the slot), EIPScanner (through PyPI `eip2nats`) as an input-only
//! originator, and a listen-only connection following a multicast exclusive owner, driven
//! by the project's scanner.

use std::net::{Ipv4Addr, SocketAddrV4, UdpSocket};
use std::time::{Duration, Instant};

use serde_json::json;

use crate::common;
use enip_stack::wire::forward_open::{ForwardOpenRepr, NetworkParams, Triad};
use enip_stack::wire::io_datagram::Packet;
use host_tests::peers;
use host_tests::rig::{BOARD_IP, HOST_IP};
use host_tests::scanner::Session;

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
    // The board's log at the default level tells a PLC engineer what happened.
    let log = rig.board_log();
    let lines = |what: &str| {
        log.lines()
            .filter(|l| l.contains("connection") && l.contains(what))
            .count()
    };
    assert!(
        lines("opened: ExclusiveOwner from 198.18.0.1") >= 2,
        "opened lines: {log}"
    );
    assert!(
        lines("closed (ExclusiveOwner from 198.18.0.1): Forward_Close") >= 1,
        "closed line: {log}"
    );
    assert!(
        log.contains("registered by 198.18.0.1"),
        "session line: {log}"
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

/// EIPScanner (C++, through the PyPI `eip2nats` bridge and Debian's `nats-server`) opens an
/// input-only connection (configuration 151, heartbeat 152 with the run/idle header it
/// always sends, inputs 100) at 10 ms: every T->O datagram in sequence, 34 bytes, and the
/// inputs follow a write of output assembly 150 (which input 100 echoes) within the run.
#[test]
#[ignore = "needs root: network namespace and TAP"]
fn eipscanner_input_only_follows_the_inputs() {
    let rig = common::start("eipscanner_input_only");
    let pattern: String = (1..=32u8).map(|b| format!("{b:02x}")).collect();
    let input = json!({"host": BOARD_IP.to_string(), "rpi_us": 10_000, "seconds": 2,
        "pattern": pattern});
    let out = peers::run(rig.ns(), "eipscanner_input_only.py", &input, PEER_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}\n{}", rig.board_log()));
    assert_eq!(
        (&out["started"], &out["write"]),
        (&json!(true), &json!(0)),
        "{out}"
    );
    // 2 s at 10 ms: about 200 datagrams, each published once, none missing.
    let messages = out["messages"].as_u64().unwrap_or(0);
    assert!((150..=215).contains(&messages), "{out}");
    assert_eq!(out["published"], out["messages"], "{out}");
    assert_eq!(out["gaps"], 0, "T->O sequence counts: {out}");
    assert_eq!(
        out["lengths"],
        json!([34]),
        "sequence count + 32 bytes: {out}"
    );
    assert_ne!(out["first_data"], json!(pattern), "{out}");
    assert_eq!(out["last_data"], json!(pattern), "{out}");
    let from = out["pattern_from"].as_u64().unwrap_or(0);
    assert!(from > 0, "the written inputs appear during the run: {out}");
    assert_eq!(out["pattern_stays"], true, "{out}");
    let log = rig.board_log();
    assert!(
        log.contains("opened: InputOnly from 198.18.0.1"),
        "opened line: {log}"
    );
    assert!(
        log.contains("closed (InputOnly from 198.18.0.1): Forward_Close"),
        "closed line: {log}"
    );
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
fn forward_open(serial: u16, path: &[u8], multicast: bool, o_t_size: u16) -> ForwardOpenRepr<'_> {
    let t_o_type = if multicast { 0x2800 } else { 0x4800 };
    ForwardOpenRepr {
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

fn seg_class(c: u32) -> enip_stack::wire::epath::SegmentRepr<'static> {
    enip_stack::wire::epath::SegmentRepr::Logical(enip_stack::wire::epath::LogicalType::Class, c)
}

fn seg_instance(i: u32) -> enip_stack::wire::epath::SegmentRepr<'static> {
    enip_stack::wire::epath::SegmentRepr::Logical(enip_stack::wire::epath::LogicalType::Instance, i)
}

fn seg_attribute(a: u32) -> enip_stack::wire::epath::SegmentRepr<'static> {
    enip_stack::wire::epath::SegmentRepr::Logical(
        enip_stack::wire::epath::LogicalType::Attribute,
        a,
    )
}

/// Garbage aimed at UDP 2222 and malformed Forward_Opens on a second session while an
/// exclusive owner runs at 10 ms: the owner's I/O goes on untouched (no loss, no timeout,
/// its own data echoed), and the adapter's replies dissect cleanly.
#[test]
#[ignore = "needs root: network namespace and TAP"]
fn io_survives_hostile_datagrams_and_forward_opens() {
    use host_tests::scanner::{exchange, open_generic};
    use std::sync::atomic::{AtomicBool, Ordering};

    let rig = common::start("io_hostile");
    let outcome = rig.ns().inside(|| -> std::io::Result<_> {
        let mut owner = Session::connect(BOARD_IP, common::REPLY)?;
        let opened = open_generic(&mut owner, 1, 10_000, 2)?;
        let o_t = opened[0].o_t_id;
        let stop = AtomicBool::new(false);
        std::thread::scope(|s| {
            let attacker = s.spawn(|| -> std::io::Result<(u32, Vec<u8>)> {
                let udp = UdpSocket::bind(SocketAddrV4::new(HOST_IP, 0))?;
                let to = SocketAddrV4::new(BOARD_IP, 2222);
                let mut sent = 0u32;
                let mut buf = [0u8; 128];
                // Let the owner's own sequence numbers start first: a spoofed datagram with a
                // newer sequence number from the originator's address is, by design, data.
                std::thread::sleep(Duration::from_millis(200));
                // Bounded: at most 2000 datagrams, stopped early when the exchange ends.
                for k in 0..2000u32 {
                    if stop.load(Ordering::Relaxed) {
                        break;
                    }
                    let garbage: Vec<u8> = match k % 5 {
                        0 => (0..(k % 40) as u8).collect(),
                        // The owner's connection ID, a stale sequence number (0 never advances).
                        1 => {
                            let n = enip_stack::originator::io_datagram(
                                &mut buf,
                                o_t,
                                0,
                                0,
                                Some(true),
                                &[0xEE; 32],
                            )
                            .map_err(|e| std::io::Error::other(format!("{e:?}")))?;
                            buf[..n].to_vec()
                        }
                        // The owner's connection ID, a wrong size.
                        2 => {
                            let n = enip_stack::originator::io_datagram(
                                &mut buf,
                                o_t,
                                k + 1_000_000,
                                0,
                                Some(true),
                                &[0xEE; 31],
                            )
                            .map_err(|e| std::io::Error::other(format!("{e:?}")))?;
                            buf[..n].to_vec()
                        }
                        // An unknown connection ID.
                        3 => {
                            let n = enip_stack::originator::io_datagram(
                                &mut buf,
                                o_t ^ 0xFFFF,
                                k,
                                k as u16,
                                Some(true),
                                &[0xEE; 32],
                            )
                            .map_err(|e| std::io::Error::other(format!("{e:?}")))?;
                            buf[..n].to_vec()
                        }
                        // A CPF claiming more items than it has.
                        _ => vec![9, 0, 0x02, 0x80, 8, 0, 1, 2, 3, 4],
                    };
                    udp.send_to(&garbage, to)?;
                    sent += 1;
                    std::thread::sleep(Duration::from_millis(1));
                }
                // Malformed Forward_Opens on a session of its own.
                let mut other = Session::connect(BOARD_IP, common::REPLY)?;
                let mut statuses = Vec::new();
                for data in [&[1u8, 2, 3][..], &[0u8; 36][..], &[0xFF; 60][..]] {
                    let cm = [
                        enip_stack::wire::epath::SegmentRepr::Logical(
                            enip_stack::wire::epath::LogicalType::Class,
                            6,
                        ),
                        enip_stack::wire::epath::SegmentRepr::Logical(
                            enip_stack::wire::epath::LogicalType::Instance,
                            1,
                        ),
                    ];
                    statuses.push(other.request(0x54, &cm, data)?.general);
                }
                Ok((sent, statuses))
            });
            let record = exchange(
                BOARD_IP,
                &opened,
                Duration::from_millis(10),
                Duration::from_secs(3),
                |k| [(k % 100) as u8 + 1; 32],
            );
            stop.store(true, Ordering::Relaxed);
            let attack = attacker
                .join()
                .map_err(|_| std::io::Error::other("attacker panicked"))??;
            let record = record?;
            owner.forward_close(opened[0].triad)?;
            Ok((record, attack, opened[0].t_o_id))
        })
    });
    let (record, (sent, statuses), t_o) = outcome
        .expect("namespace")
        .unwrap_or_else(|e| panic!("{e}\n{}", rig.board_log()));
    assert!(sent > 100, "only {sent} hostile datagrams went out");
    assert!(
        statuses.iter().all(|&g| g != 0),
        "malformed Forward_Opens must fail: {statuses:02x?}"
    );
    let summary = record.summary(3_000_000, 500_000);
    assert_eq!(summary.timeouts, 0, "the owner's connection must stay up");
    let packets = &record.packets[&t_o];
    assert!(
        packets.len() >= 250,
        "{} T->O packets in 3 s at 10 ms",
        packets.len()
    );
    assert_eq!(summary.connections[0].lost, 0);
    // Never the attacker's 0xEE data (the owner's own data is 1..=100): its ticks come back.
    assert!(packets
        .iter()
        .all(|(_, _, head)| head[0] != 0xEE || head[1] != 0xEE));
    assert!(
        packets
            .iter()
            .any(|(_, _, head)| head[0] != 0 && head == &[head[0]; 4]),
        "the owner's data is echoed"
    );
    common::finish_hostile(rig);
}
