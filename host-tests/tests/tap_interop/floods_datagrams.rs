//! UDP floods and frame-level storms of issue 28 item 1 on the TAP board, each against the
//! running load of `floods_load.rs` and compared with the same load without it in the same
//! run: on UDP 2222, valid-looking O->T datagrams with unknown connection IDs, with the load's
//! own O->T IDs from a wrong source address (198.18.0.3, added to the namespace's link) and
//! truncated ones; on UDP 44818, malformed and unicast requests; ARP requests and LLDPDUs
//! from changing senders (`peers/frame_storm.py`, an AF_PACKET socket). Every flood runs on
//! CPU 1, bounded in time and by the count line rate allows.

use std::net::{Ipv4Addr, SocketAddrV4, UdpSocket};
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use crate::common::{self, REPLY};
use crate::floods::{assert_t_o_held, hping3_flood};
use crate::floods_load::{flood_run, phase, pin_flooder_thread, Flood, FLOOD_CPU, RPI};
use enip_stack::originator;
use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use host_tests::enip::{command, Header};
use host_tests::faults::count;
use host_tests::peers;
use host_tests::process::run_bounded;
use host_tests::rig::{Rig, BOARD_IP, HOST_IP, TAP};
use host_tests::scanner::Session;

/// Datagrams or frames a flood sends per second at most: minimum-size frames at 100 Mbit/s.
pub const LINE_RATE: f64 = 148_800.0;
/// The wrong source of forged O->T datagrams with the load's own connection IDs.
const WRONG_SOURCE: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 3);
/// The forged O->T data: what the owner's output assembly must never hold afterwards
/// (alternating bytes: the scanner's own data is 32 equal bytes).
const FORGED_DATA: [u8; 32] = forged_data();

const fn forged_data() -> [u8; 32] {
    let mut d = [0xEE; 32];
    let mut i = 1;
    while i < 32 {
        d[i] = 0x11;
        i += 2;
    }
    d
}

fn phase_length() -> Duration {
    Duration::from_secs(count("ENIP_FAULTS_FLOOD_SECONDS", 2, 30))
}

/// The most a flood of `secs` may send.
fn line_rate_bound(until: Instant) -> u64 {
    (LINE_RATE
        * until
            .saturating_duration_since(Instant::now())
            .as_secs_f64())
    .ceil() as u64
}

/// Sends `next(i)` to `to` from `s` until `until`, paced to `per_second` datagrams a second
/// (a TAP has no line rate of its own: unpaced, this machine sends twice what 100 Mbit/s
/// carries, which no Ethernet port of the adapter would ever see); returns what was sent.
fn blast(
    s: &UdpSocket,
    to: SocketAddrV4,
    until: Instant,
    per_second: f64,
    mut next: impl FnMut(u64) -> Vec<u8>,
) -> u64 {
    let start = Instant::now();
    let mut sent = 0;
    loop {
        let now = Instant::now();
        if now >= until {
            return sent;
        }
        let allowed = (per_second * now.duration_since(start).as_secs_f64()) as u64 + 1;
        if sent >= allowed {
            std::thread::yield_now();
            continue;
        }
        // A full TAP queue refuses some: counted as not sent.
        if s.send_to(&next(sent), to).is_ok() {
            sent += 1;
        }
    }
}

/// Forged O->T on UDP 2222 until `until` at `per_second` datagrams a second, a third of the
/// time each: valid-looking datagrams with unknown connection IDs, the load's own O->T IDs
/// (data [`FORGED_DATA`], sequence numbers far ahead) from [`WRONG_SOURCE`], and truncated
/// ones.
pub fn forged_io(f: &Flood<'_>, until: Instant, per_second: f64) -> Value {
    pin_flooder_thread();
    // Already there from an earlier flood of the same run: fine.
    let _ =
        f.ns.exec_checked("ip", &["addr", "add", "198.18.0.3/24", "dev", TAP]);
    let to = SocketAddrV4::new(BOARD_IP, 2222);
    let host = UdpSocket::bind(SocketAddrV4::new(HOST_IP, 0)).expect("bind");
    let wrong = UdpSocket::bind(SocketAddrV4::new(WRONG_SOURCE, 0)).expect("bind 198.18.0.3");
    let start = Instant::now();
    let third = until.saturating_duration_since(start) / 3;
    let datagram = |id: u32, seq: u32, len: Option<usize>| {
        let mut buf = [0u8; 128];
        let n = originator::io_datagram(&mut buf, id, seq, seq as u16, Some(true), &FORGED_DATA)
            .expect("datagram");
        buf[..len.unwrap_or(n).min(n)].to_vec()
    };
    let unknown = blast(&host, to, start + third, per_second, |i| {
        datagram(0x0BAD_0000 + (i % 4096) as u32, i as u32, None)
    });
    let ids: Vec<u32> = f.opened.iter().map(|c| c.o_t_id).collect();
    let wrong_source = blast(&wrong, to, start + third * 2, per_second, |i| {
        let id = ids[(i as usize) % ids.len()];
        datagram(id, 1_000_000 + i as u32, None)
    });
    let truncated = blast(&host, to, until, per_second, |i| {
        datagram(
            ids[(i as usize) % ids.len()],
            1_000_000 + i as u32,
            Some(2 + (i % 20) as usize),
        )
    });
    let secs = start.elapsed().as_secs_f64();
    json!({
        "unknown_ids": unknown,
        "known_ids_wrong_source": wrong_source,
        "truncated": truncated,
        "datagrams_per_second": ((unknown + wrong_source + truncated) as f64 / secs).round(),
        "owner_output_after": owner_output(),
    })
}

/// The owner's output assembly (150) read twice 50 ms apart, as hex; forged data there
/// would stay put (its sequence numbers are ahead of the scanner's).
fn owner_output() -> Value {
    let read = || -> std::io::Result<Vec<u8>> {
        let mut s = Session::connect(BOARD_IP, REPLY)?;
        let p = [
            SegmentRepr::Logical(LogicalType::Class, 4),
            SegmentRepr::Logical(LogicalType::Instance, 150),
            SegmentRepr::Logical(LogicalType::Attribute, 3),
        ];
        let r = s.request(0x0E, &p, &[])?;
        Ok(if r.general == 0 {
            r.data
        } else {
            vec![r.general]
        })
    };
    let first = read().map(|d| hex(&d)).unwrap_or_else(|e| e.to_string());
    std::thread::sleep(Duration::from_millis(50));
    let second = read().map(|d| hex(&d)).unwrap_or_else(|e| e.to_string());
    json!([first, second])
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Malformed and unicast requests on UDP 44818 until `until` at `per_second` a second:
/// garbage, cut headers, unknown commands, and ListServices, ListIdentity and NOP requests;
/// replies counted.
pub fn malformed_encapsulation(f: &Flood<'_>, until: Instant, per_second: f64) -> Value {
    pin_flooder_thread();
    let _ = f;
    let s = UdpSocket::bind(SocketAddrV4::new(HOST_IP, 0)).expect("bind");
    s.set_nonblocking(true).expect("nonblocking");
    let to = SocketAddrV4::new(BOARD_IP, 44818);
    let start = Instant::now();
    let (mut replies, mut reply_bytes) = (0u64, 0u64);
    let mut buf = [0u8; 1500];
    let mut drain = |s: &UdpSocket| {
        while let Ok((n, _)) = s.recv_from(&mut buf) {
            replies += 1;
            reply_bytes += n as u64;
        }
    };
    let requests = [
        command::LIST_SERVICES,
        command::LIST_IDENTITY,
        0x0000, // NOP
        0x00AB, // no such command
    ];
    let request = |i: u64| match i % 4 {
        0 => vec![(i % 251) as u8; (i % 40) as usize],
        1 => Header::new(command::LIST_IDENTITY).bytes()[..(i % 24) as usize].to_vec(),
        _ => Header::new(requests[(i / 4 % 4) as usize]).bytes().to_vec(),
    };
    // In slices of 10 ms, the replies read in between: the socket's buffer holds only a few
    // hundred.
    let mut sent = 0;
    while Instant::now() < until {
        let slice = (Instant::now() + Duration::from_millis(10)).min(until);
        let from = sent;
        sent += blast(&s, to, slice, per_second, |i| request(from + i));
        drain(&s);
    }
    std::thread::sleep(Duration::from_millis(100));
    drain(&s);
    let secs = start.elapsed().as_secs_f64();
    json!({
        "requests": sent,
        "requests_per_second": (sent as f64 / secs).round(),
        "replies": replies,
        "reply_bytes": reply_bytes,
    })
}

/// UDP floods on 2222 (unknown IDs, known IDs from a wrong source, truncated) and on 44818
/// (malformed and unicast requests), and a ping flood (`hping3 --icmp --flood`), 2 s each
/// (long: 30 s), against the load: no connection times out, pycomm3 answered, a new session
/// within 1 s after each flood, the owner's output assembly never holds the forged data,
/// and less than 10 % of the T->O goes missing under the ping flood.
#[test]
#[ignore = "needs root: network namespace and TAP"]
fn faults_flood_udp() {
    let len = phase_length();
    let rig = Rig::start(&common::host_bin(), "generic", None).expect("rig");
    let io = |f: &Flood<'_>| forged_io(f, f.until, LINE_RATE);
    let encap = |f: &Flood<'_>| malformed_encapsulation(f, f.until, LINE_RATE);
    // A ping flood from the host, each echo request answered by the network stack.
    let echo = |f: &Flood<'_>| hping3_flood(f, &["--icmp"], None);
    let run = flood_run(
        &rig,
        "enip-host",
        RPI,
        "flood_udp",
        len,
        &[
            ("udp 2222", len, &io),
            ("udp 44818", len, &encap),
            ("icmp echo", len, &echo),
        ],
    );
    assert_t_o_held(&run, "icmp echo");
    let forged = hex(&FORGED_DATA);
    let after = &phase(&run, "udp 2222")["flood"]["owner_output_after"];
    assert!(
        after
            .as_array()
            .is_some_and(|r| r.iter().all(|x| x.as_str() != Some(&forged))),
        "forged O->T data reached the owner's assembly: {after}"
    );
    rig.finish().expect("the board ran to the end");
}

/// An ARP, LLDP, SYN, ACK or echo storm from `peers/frame_storm.py` on CPU 1 until
/// `until`, at `per_second` frames at most.
pub fn frame_storm(f: &Flood<'_>, kind: &str, per_second: f64) -> Value {
    let secs = f.until.saturating_duration_since(Instant::now());
    let input = json!({
        "iface": TAP,
        "kind": kind,
        "seconds": secs.as_secs_f64(),
        "max_frames": line_rate_bound(f.until),
        "per_second": per_second,
        "target": BOARD_IP.to_string(),
        "source": HOST_IP.to_string(),
    });
    let mut cmd = f.ns.command("taskset");
    cmd.args(["-c", &FLOOD_CPU.to_string(), &peers::python()])
        .arg(peers::script("frame_storm.py"));
    let text = input.to_string();
    let out = run_bounded(cmd, Some(text.as_bytes()), secs + Duration::from_secs(10))
        .expect("frame_storm.py runs");
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .rev()
        .find_map(|l| serde_json::from_str(l).ok())
        .unwrap_or_else(|| panic!("frame_storm.py: {}", String::from_utf8_lossy(&out.stderr)))
}

/// ARP requests for the board from changing senders and LLDPDUs from changing chassis, 2 s
/// each (long: 30 s), against the load: no connection times out, pycomm3 answered, a new
/// session within 1 s after each storm.
#[test]
#[ignore = "needs root: network namespace and TAP"]
fn faults_flood_arp_and_lldp() {
    let len = phase_length();
    let rig = Rig::start(&common::host_bin(), "generic", None).expect("rig");
    let arp = |f: &Flood<'_>| frame_storm(f, "arp", LINE_RATE);
    let lldp = |f: &Flood<'_>| frame_storm(f, "lldp", LINE_RATE);
    flood_run(
        &rig,
        "enip-host",
        RPI,
        "flood_arp_and_lldp",
        len,
        &[("arp storm", len, &arp), ("lldp storm", len, &lldp)],
    );
    rig.finish().expect("the board ran to the end");
}
