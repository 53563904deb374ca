//! Identity Reset during running Class 1 I/O (issue 13 item 2), types 0 and 1, on a board with
//! a non-volatile store (`--nv-file`): the reply goes out, every I/O connection ends right
//! after it, the device serves new sessions and connections, and the host name set through
//! TCP/IP attribute 6 survives type 0 and is back to its factory value (empty) after type 1,
//! in RAM and in the store. A host process does not restart itself on a Reset (`enip-host`
//! only logs it), so the power cycle is played by restarting the board on the same file.
//! `ENIP_FAULTS_LONG=1` (or `ENIP_FAULTS_RESET_ROUNDS=N`) repeats the reset (5 rounds).

use std::io;
use std::net::{Ipv4Addr, SocketAddrV4, UdpSocket};
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use crate::common::{self, REPLY};
use crate::fault_io::{board_real_time, drive, ms_between, Feed, IO_PORT};
use crate::faults::{cm_counter, forward_open, session, triad};
use crate::tcpip_nv;
use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use host_tests::faults::{count, most, ms, report};
use host_tests::rig::BOARD_IP;
use host_tests::scanner::Session;
use host_tests::scanner::{HEARTBEAT_O_T, INPUT_ONLY_PATH, OWNER_O_T, OWNER_PATH};

/// The host name set before each reset.
const HOST_NAME: &[u8] = b"fault-host";
/// RPI of the running connections.
const RPI: Duration = Duration::from_millis(10);
/// Their timeout multiplier code: x32 (320 ms), so that this shared machine's scheduling
/// stalls do not end them before the reset does.
const MULTIPLIER: u8 = 3;
/// Bound for a new session and connection after the reset reply.
const BACK_BOUND: Duration = Duration::from_secs(1);

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn faults_identity_reset_type_0() {
    reset_during_io(0);
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn faults_identity_reset_type_1() {
    reset_during_io(1);
}

/// The host name the board should hold after a Reset of type `kind`.
fn expected_name(kind: u8) -> &'static [u8] {
    if kind == 0 {
        HOST_NAME
    } else {
        b""
    }
}

fn reset_during_io(kind: u8) {
    let name = format!("faults_identity_reset_type_{kind}");
    let rounds = count("ENIP_FAULTS_RESET_ROUNDS", 1, 5);
    let file = common::fresh_nv_file(&format!("{name}.nv"));
    let nv = file.to_str().unwrap();
    let rig = tcpip_nv::start(&name, &["--nv-file", nv], BOARD_IP);
    board_real_time(&rig);
    let figures: Vec<Value> = (0..rounds)
        .map(|round| {
            rig.ns()
                .inside(|| reset_round(kind, round as u16))
                .expect("namespace")
                .unwrap_or_else(|e| panic!("round {round}: {e}\n{}", rig.board_log()))
        })
        .collect();
    let log = rig.board_log();
    let requested = format!("identity reset type {kind} requested");
    assert_eq!(
        log.matches(&requested).count(),
        rounds as usize,
        "{requested}\n{log}"
    );
    common::finish(rig);
    // The power cycle: the same store, a new process.
    let rig = tcpip_nv::start(&format!("{name}_power_cycle"), &["--nv-file", nv], BOARD_IP);
    let stored = rig
        .ns()
        .inside(|| Session::connect(BOARD_IP, REPLY).and_then(|mut s| host_name(&mut s)))
        .expect("namespace")
        .expect("host name after the power cycle");
    common::finish(rig);
    report(
        &format!("identity_reset_type_{kind}"),
        json!({
            "rounds": rounds,
            "rpi_ms": ms(RPI),
            "worst_reply_ms": most(&figures, "reply_ms"),
            "worst_io_ended_after_reply_ms": most(&figures, "io_ended_after_reply_ms"),
            "worst_session_after_reply_ms": most(&figures, "session_after_reply_ms"),
            "worst_forward_open_after_reply_ms": most(&figures, "forward_open_after_reply_ms"),
            "host_name_after_power_cycle": String::from_utf8_lossy(&stored),
            "host_name_expected": String::from_utf8_lossy(expected_name(kind)),
            "per_round": figures,
        }),
    );
    assert_eq!(
        stored,
        expected_name(kind),
        "host name in the store after Reset type {kind} and a power cycle"
    );
}

/// Sets the host name, runs an owner and an input-only connection, resets in the middle;
/// returns the round's figures.
fn reset_round(kind: u8, round: u16) -> io::Result<Value> {
    let udp = UdpSocket::bind(SocketAddrV4::new(Ipv4Addr::UNSPECIFIED, IO_PORT))?;
    let mut s = session()?;
    let mut value = (HOST_NAME.len() as u16).to_le_bytes().to_vec();
    value.extend_from_slice(HOST_NAME);
    let r = s.request(0x10, &tcpip_attribute(6), &value)?;
    if r.general != 0 {
        return Err(io::Error::other(format!("setting the host name: {r:?}")));
    }
    let timeouts_before = cm_counter(&mut s, 8)?;
    let refused = |e| io::Error::other(format!("Forward_Open refused: {e:?}"));
    let rpi_us = RPI.as_micros() as u32;
    let serial = 10 * round;
    let owner = s
        .forward_open(&forward_open(
            triad(serial + 1, 0x5E7),
            &OWNER_PATH,
            OWNER_O_T,
            MULTIPLIER,
            rpi_us,
        ))?
        .map_err(refused)?;
    let input = s
        .forward_open(&forward_open(
            triad(serial + 2, 0x5E7),
            &INPUT_ONLY_PATH,
            HEARTBEAT_O_T,
            MULTIPLIER,
            rpi_us,
        ))?
        .map_err(refused)?;
    let feeds = [Feed::new(&owner, RPI, true), Feed::new(&input, RPI, false)];
    let end = Instant::now() + Duration::from_millis(1500);
    let (traffic, sent_at, reply_at, reply) = std::thread::scope(|sc| -> io::Result<_> {
        let io = sc.spawn(|| drive(&udp, &feeds, end));
        std::thread::sleep(Duration::from_millis(500));
        let sent_at = Instant::now();
        let identity = [
            SegmentRepr::Logical(LogicalType::Class, 1),
            SegmentRepr::Logical(LogicalType::Instance, 1),
        ];
        let reply = s.request(0x05, &identity, &[kind])?;
        let reply_at = Instant::now();
        let traffic = io
            .join()
            .map_err(|_| io::Error::other("I/O thread panicked"))??;
        Ok((traffic, sent_at, reply_at, reply))
    })?;
    let back = Instant::now();
    let mut fresh = session()?;
    let session_after = back.elapsed();
    let again = fresh
        .forward_open(&forward_open(
            triad(serial + 3, 0x5E7),
            &OWNER_PATH,
            OWNER_O_T,
            0,
            100_000,
        ))?
        .map_err(refused)?;
    let forward_open_after = back.elapsed();
    let r = fresh.forward_close(again.triad)?;
    if r.general != 0 {
        return Err(io::Error::other(format!(
            "Forward_Close after the reset: {r:?}"
        )));
    }
    let name = host_name(&mut fresh)?;
    let timeouts = cm_counter(&mut fresh, 8)?.wrapping_sub(timeouts_before);
    // The I/O ran 1 s past the reply: the time to the next session is measured from there.
    let ended = [owner.t_o_connection_id, input.t_o_connection_id]
        .iter()
        .filter_map(|id| traffic.arrivals(*id).max())
        .max();
    let ended_ms = ended.map(|t| ms_between(reply_at, t));
    let requester_kept = s.request(0x0E, &tcpip_attribute(13), &[]).is_ok();
    let figures = json!({
        "reply_status": reply.general,
        "reply_ms": ms(reply_at - sent_at),
        "io_ended_after_reply_ms": ended_ms,
        "session_after_reply_ms": ms(session_after),
        "forward_open_after_reply_ms": ms(forward_open_after),
        "host_name_after": String::from_utf8_lossy(&name),
        "timeouts_counted": timeouts,
        "requesting_session_kept": requester_kept,
    });
    println!("reset type {kind} round {round}: {figures}");
    let fail = |what: &str| Err(io::Error::other(format!("{what}: {figures}")));
    if reply.general != 0 {
        return fail("the Reset was refused");
    }
    // The connections close as the reply goes out: at most one more RPI of T->O in flight.
    if ended_ms.is_none_or(|e| e > ms(RPI) + 10.0) {
        return fail("the I/O connections did not end with the reset");
    }
    if ended_ms.is_some_and(|e| e < -(ms(RPI) + ms(reply_at - sent_at) + 10.0)) {
        return fail("the I/O connections were not running up to the reset");
    }
    if session_after > BACK_BOUND || forward_open_after > BACK_BOUND {
        return fail("the device did not serve within 1 s of the reset");
    }
    if name != expected_name(kind) {
        return fail("wrong host name after the reset");
    }
    if timeouts != 0 {
        return fail("connections ended by the reset counted as timeouts");
    }
    Ok(figures)
}

/// The path of TCP/IP Interface instance 1 attribute `attr`.
fn tcpip_attribute(attr: u32) -> [SegmentRepr<'static>; 3] {
    [
        SegmentRepr::Logical(LogicalType::Class, 0xF5),
        SegmentRepr::Logical(LogicalType::Instance, 1),
        SegmentRepr::Logical(LogicalType::Attribute, attr),
    ]
}

/// TCP/IP attribute 6, the host name (a STRING: UINT length, characters, pad).
fn host_name(s: &mut Session) -> io::Result<Vec<u8>> {
    let r = s.request(0x0E, &tcpip_attribute(6), &[])?;
    let len = r
        .data
        .get(..2)
        .map(|b| usize::from(u16::from_le_bytes([b[0], b[1]])));
    len.and_then(|n| r.data.get(2..2 + n))
        .filter(|_| r.general == 0)
        .map(<[u8]>::to_vec)
        .ok_or_else(|| io::Error::other(format!("TCP/IP attribute 6: {r:?}")))
}
