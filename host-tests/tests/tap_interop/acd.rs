//! Address Conflict Detection (RFC 5227 timing) against independent peers, on the host board
//! (`enip-host --acd on`) and the emulated board (its default image, built with ACD on):
//! tshark sees the ARP probes (sender 0.0.0.0) and announcements before the adapter's first
//! IP packet; a gratuitous ARP for its address from Debian's `arping` (another MAC) is
//! defended with an announcement within a second and recorded in TCP/IP attribute 11, read
//! with pycomm3 (`host-tests/peers/acd.py`), a second claim within the defend interval makes
//! it give the address up; started while the namespace's interface holds
//! its address (Linux answers the probes), the adapter sends no IP packet, says so in its
//! log, and after a restart on the same `--nv-file` attribute 11 still names that interface.

use std::net::{Ipv4Addr, SocketAddrV4, UdpSocket};
use std::path::Path;
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use crate::common;
use host_tests::netns::{Namespace, BROADCAST_IP, HOST_IP};
use host_tests::peers;
use host_tests::process::run_bounded;
use host_tests::rig::{self, Board, Options, Rig, BOARD_IP, ENCAP_PORT, TAP};

/// The MAC address `arping` claims the adapter's address from.
const FOREIGN_MAC: &str = "02:00:5e:00:53:99";
/// How soon a claim must be answered.
const DEFEND_WITHIN: f64 = 1.0;
/// What the adapter logs (at the default level) when its address is taken.
const TAKEN_LOG: &str = "in use by another host";
/// Bound for the adapter to find its address taken (probing takes at most 5 s).
const TAKEN_BOUND: Duration = Duration::from_secs(12);
/// Bound for one peer or tool run.
const TOOL_TIMEOUT: Duration = Duration::from_secs(30);

/// One ARP or IP frame of a capture.
#[derive(Debug)]
struct Frame {
    t: f64,
    src: String,
    arp: Option<(Ipv4Addr, Ipv4Addr)>,
    ip: bool,
}

/// The ARP and IP frames of `pcap`, in order.
fn frames(pcap: &Path) -> Vec<Frame> {
    let mut cmd = std::process::Command::new("tshark");
    cmd.args(["-n", "-r"])
        .arg(pcap)
        .args(["-Y", "arp || ip", "-T", "fields"]);
    cmd.args(["-E", "separator=|"]);
    for f in ["frame.time_relative", "eth.src", "arp.src.proto_ipv4"] {
        cmd.args(["-e", f]);
    }
    cmd.args(["-e", "arp.dst.proto_ipv4", "-e", "ip.src"]);
    let out = run_bounded(cmd, None, TOOL_TIMEOUT).expect("tshark -r");
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split('|').collect();
            let ip = |i: usize| f.get(i).and_then(|s| s.parse().ok());
            Frame {
                t: f[0].parse().expect("time"),
                src: f[1].to_string(),
                arp: ip(2).zip(ip(3)),
                ip: f.get(4).is_some_and(|s| !s.is_empty()),
            }
        })
        .collect()
}

/// The adapter's MAC: the sender of the first probe for its address.
fn adapter_mac(frames: &[Frame]) -> String {
    let probe = Some((Ipv4Addr::UNSPECIFIED, BOARD_IP));
    let first = frames.iter().find(|f| f.arp == probe);
    first.expect("no ARP probe for the address").src.clone()
}

/// Three probes RFC 5227's interval apart, then two announcements, all before the
/// adapter's first IP packet (times with room for a loaded host's scheduling, the emulated
/// board's above all); returns the adapter's MAC.
fn assert_probed_before_use(frames: &[Frame]) -> String {
    let mac = adapter_mac(frames);
    let own: Vec<&Frame> = frames.iter().filter(|f| f.src == mac).collect();
    let first_ip = own
        .iter()
        .position(|f| f.ip)
        .expect("the adapter sent no IP");
    let before = &own[..first_ip];
    let probes: Vec<f64> = before
        .iter()
        .filter(|f| f.arp == Some((Ipv4Addr::UNSPECIFIED, BOARD_IP)))
        .map(|f| f.t)
        .collect();
    let announcements: Vec<f64> = before
        .iter()
        .filter(|f| f.arp == Some((BOARD_IP, BOARD_IP)))
        .map(|f| f.t)
        .collect();
    println!("probes at {probes:?}, announcements at {announcements:?}");
    assert_eq!(
        probes.len(),
        3,
        "PROBE_NUM probes before the first IP packet"
    );
    assert!(
        announcements.len() >= 2,
        "ANNOUNCE_NUM before it: {announcements:?}"
    );
    for gap in [probes[1] - probes[0], probes[2] - probes[1]] {
        assert!(
            (0.9..=2.5).contains(&gap),
            "PROBE_MIN..PROBE_MAX apart: {probes:?}"
        );
    }
    let wait = announcements[0] - probes[2];
    assert!(
        (1.8..=2.8).contains(&wait),
        "ANNOUNCE_WAIT after the last probe: {wait}"
    );
    mac
}

/// `arping` in `ns` claims the adapter's address from [`FOREIGN_MAC`] (one gratuitous ARP).
fn claim(ns: &Namespace) {
    let ip = BOARD_IP.to_string();
    let mut cmd = ns.command("arping");
    cmd.args([
        "-U",
        "-p",
        "-s",
        FOREIGN_MAC,
        "-S",
        &ip,
        "-i",
        TAP,
        "-c",
        "1",
        "-w",
        "1",
    ]);
    cmd.arg(&ip);
    let out = run_bounded(cmd, None, TOOL_TIMEOUT).expect("arping");
    println!("arping: {}", String::from_utf8_lossy(&out.stdout).trim());
}

/// TCP/IP attributes 1, 2, 10 and 11 read with pycomm3 (hex values).
fn read_attributes(rig: &Rig) -> Value {
    let input = json!({"host": BOARD_IP.to_string()});
    let out = peers::run(rig.ns(), "acd.py", &input, TOOL_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}\nboard log:\n{}", rig.board_log()));
    println!("acd.py: {out}");
    out
}

/// Attribute 11 as hex: activity, remote MAC, then the ARP PDU from `mac` with operation `op`
/// and sender `sender` (compared up to its sender address).
fn expected_last(activity: u8, mac: &str, op: u16) -> String {
    let mac: String = mac.split(':').collect();
    let sender = hex(&BOARD_IP.octets());
    format!("{activity:02x}{mac}000108000604{op:04x}{mac}{sender}")
}

fn hex(b: &[u8]) -> String {
    b.iter().map(|b| format!("{b:02x}")).collect()
}

/// A gratuitous ARP for the adapter's address is defended within a second and recorded in
/// attribute 11; status bit 6 (conflict seen), not 7 (address kept). A second one within the
/// defend interval costs the address: logged, and no IP packet from it afterwards.
fn defends(rig: Rig, pcap: &Path) {
    claim(rig.ns());
    std::thread::sleep(Duration::from_millis(1200));
    let r = read_attributes(&rig);
    let u32_of = |a: &str| u32::from_str_radix(r[a]["value"].as_str().unwrap(), 16).unwrap();
    assert_eq!(
        u32_of("2").swap_bytes() & 0x80,
        0x80,
        "capability bit 7: {r}"
    );
    assert_eq!(
        u32_of("1").swap_bytes() & 0xC0,
        0x40,
        "status bits 6/7: {r}"
    );
    assert_eq!(r["10"]["value"], "01", "{r}");
    let last = r["11"]["value"].as_str().unwrap();
    assert!(last.starts_with(&expected_last(2, FOREIGN_MAC, 1)), "{r}");
    assert!(
        rig.board_log().contains("defending it"),
        "{}",
        rig.board_log()
    );
    // A second claim within DEFEND_INTERVAL (10 s): the address is given up.
    claim(rig.ns());
    let start = Instant::now();
    while !rig.board_log().contains(TAKEN_LOG) {
        assert!(
            start.elapsed() < Duration::from_secs(1),
            "{}",
            rig.board_log()
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    ask_everyone(rig.ns());
    rig.finish().unwrap_or_else(|e| panic!("{e}"));
    let all = frames(pcap);
    let mac = assert_probed_before_use(&all);
    let foreign = all
        .iter()
        .find(|f| f.src == FOREIGN_MAC && f.arp == Some((BOARD_IP, BOARD_IP)))
        .expect("arping's claim not captured");
    let defence = all
        .iter()
        .find(|f| f.src == mac && f.t > foreign.t && f.arp == Some((BOARD_IP, BOARD_IP)))
        .expect("no defence");
    println!("claim at {}, defended at {}", foreign.t, defence.t);
    assert!(defence.t - foreign.t <= DEFEND_WITHIN);
    // Nothing from the address after the second claim (not even to a ListIdentity).
    let second = all
        .iter()
        .filter(|f| f.src == FOREIGN_MAC && f.arp == Some((BOARD_IP, BOARD_IP)))
        .nth(1)
        .expect("arping's second claim not captured");
    let after: Vec<&Frame> = all
        .iter()
        .filter(|f| f.src == mac && f.t > second.t)
        .collect();
    assert!(
        after.iter().all(|f| !f.ip),
        "IP after the address was lost: {after:?}"
    );
    assert_clean(pcap);
}

/// Every frame of `pcap` dissects cleanly but for the conflicts provoked on purpose (also
/// flagged where Wireshark dissects the ARP PDU attribute 11 carries).
fn assert_clean(pcap: &Path) {
    let tolerated = format!("Duplicate IP address configured ({BOARD_IP})");
    let bad = host_tests::capture::problems(pcap, "", &[&tolerated]).expect("read capture");
    assert!(bad.is_empty(), "{}:\n{}", pcap.display(), bad.join("\n"));
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn acd_host_probes_announces_and_defends() {
    let pcap = common::scratch("acd_host.pcapng");
    let nv = common::fresh_nv_file("acd_host.bin");
    let extra = ["--acd", "on", "--nv-file", nv.to_str().unwrap()];
    let rig = Rig::start_with_args(&common::host_bin(), "generic", &extra, Some(&pcap))
        .unwrap_or_else(|e| panic!("rig: {e}"));
    defends(rig, &pcap);
}

#[test]
#[ignore = "needs root: network namespace, TAP and QEMU"]
fn acd_qemu_probes_announces_and_defends() {
    let Some(elf) = rig::qemu_elf("generic") else {
        return;
    };
    let pcap = common::scratch("acd_qemu.pcapng");
    let rig = Rig::start_qemu(&elf, Some(&pcap)).unwrap_or_else(|e| panic!("rig: {e}"));
    defends(rig, &pcap);
}

/// Starts `board` while the namespace's interface holds the adapter's address: the adapter
/// says in its log that the address is taken and sends no IP packet, even to a broadcast
/// ListIdentity; returns the interface's MAC.
fn refuses_a_taken_address(board: Board<'_>, pcap: &Path) -> String {
    let rig = Rig::launch_unverified(board, &Options::capturing(Some(pcap)))
        .unwrap_or_else(|e| panic!("rig: {e}"));
    let ns = rig.ns();
    // Added as the board starts: at least two of its probes (1 to 2 s apart) come after.
    let taken = format!("{BOARD_IP}/32");
    ns.exec_checked("ip", &["addr", "add", &taken, "dev", TAP])
        .unwrap();
    let cat = format!("/sys/class/net/{TAP}/address");
    let mut cmd = ns.command("cat");
    cmd.arg(&cat);
    let out = run_bounded(cmd, None, TOOL_TIMEOUT).expect("cat");
    let holder = String::from_utf8_lossy(&out.stdout).trim().to_string();
    let start = Instant::now();
    while !rig.board_log().contains(TAKEN_LOG) {
        assert!(
            start.elapsed() < TAKEN_BOUND,
            "no conflict: {}",
            rig.board_log()
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    println!("{}", rig.board_log());
    ask_everyone(ns);
    rig.finish().unwrap_or_else(|e| panic!("{e}"));
    let all = frames(pcap);
    let mac = adapter_mac(&all);
    let own: Vec<&Frame> = all.iter().filter(|f| f.src == mac).collect();
    assert!(
        own.iter().all(|f| !f.ip),
        "an IP packet from a taken address: {own:?}"
    );
    let announced = own.iter().any(|f| f.arp == Some((BOARD_IP, BOARD_IP)));
    assert!(!announced, "a taken address announced: {own:?}");
    holder
}

/// Broadcast ListIdentity requests for a second: a board using its address would answer.
fn ask_everyone(ns: &Namespace) {
    let list_identity = [
        0x63, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    ];
    ns.inside(|| {
        let s = UdpSocket::bind(SocketAddrV4::new(HOST_IP, 0)).unwrap();
        s.set_broadcast(true).unwrap();
        let everyone = SocketAddrV4::new(BROADCAST_IP, ENCAP_PORT);
        for _ in 0..5 {
            s.send_to(&list_identity, everyone).unwrap();
            std::thread::sleep(Duration::from_millis(200));
        }
    })
    .unwrap();
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn acd_host_does_not_use_a_taken_address_and_remembers_it() {
    let nv = common::fresh_nv_file("acd_taken.bin");
    let nv = nv.to_str().unwrap();
    let bin = common::host_bin();
    let extra = ["--acd", "on", "--nv-file", nv];
    let board = Board::Host {
        bin: &bin,
        profile: "generic",
        extra: &extra,
        answers_at: BOARD_IP,
    };
    let holder = refuses_a_taken_address(board, &common::scratch("acd_taken.pcapng"));
    // Restarted on the same file with the address free: attribute 11 names the holder
    // (its reply to a probe: operation 2).
    let pcap = common::scratch("acd_taken_restart.pcapng");
    let rig = Rig::start_with_args(&bin, "generic", &extra, Some(&pcap))
        .unwrap_or_else(|e| panic!("rig: {e}"));
    let r = read_attributes(&rig);
    let last = r["11"]["value"].as_str().unwrap();
    assert!(last.starts_with(&expected_last(1, &holder, 2)), "{r}");
    assert_eq!(r["1"]["value"], "01000000", "no conflict in this run: {r}");
    rig.finish().unwrap_or_else(|e| panic!("{e}"));
    assert_clean(&pcap);
}

#[test]
#[ignore = "needs root: network namespace, TAP and QEMU"]
fn acd_qemu_does_not_use_a_taken_address() {
    let Some(elf) = rig::qemu_elf("generic") else {
        return;
    };
    let board = Board::Qemu {
        elf: &elf,
        extra: &[],
    };
    refuses_a_taken_address(board, &common::scratch("acd_taken_qemu.pcapng"));
}
