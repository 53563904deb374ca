//! LLDP against Debian's `lldpd` (issue 26 item 2), on the host board and on the emulated
//! board: pycomm3 sets the host name (TCP/IP attribute 6, the LLDP System Name) and a short
//! msgTxInterval and msgTxHold through the LLDP Management object (0x109), checking its Set
//! rules and reading it back; `lldpd` runs inside the test's namespace on the TAP facing the
//! board (its own control socket and configuration, a 1 s tx-interval, stopped by PID at the
//! end) and must list the adapter as a neighbour with its chassis MAC, system name and TTL =
//! msgTxInterval x msgTxHold; the adapter's LLDP Data Table (0x10A) must list `lldpd`'s
//! chassis MAC; tshark must dissect the adapter's LLDPDUs with the ODVA CIP Identification
//! and CIP MAC Address TLVs and nothing malformed. The host board, stopped by SIGTERM, sends
//! the shutdown LLDPDU (TTL 0); the emulated board is killed with QEMU and sends none.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use crate::common;
use host_tests::capture;
use host_tests::netns::Namespace;
use host_tests::peers;
use host_tests::process::{run_bounded, LoggedChild, SIGTERM};
use host_tests::rig::{Rig, BOARD_IP, TAP};

/// Bound for one peer program run.
const PEER_TIMEOUT: Duration = Duration::from_secs(30);
/// Bound for one `lldpcli` call.
const LLDPCLI_TIMEOUT: Duration = Duration::from_secs(10);
/// How long the neighbours may take to see each other (both send every second or two).
const DISCOVERY: Duration = Duration::from_secs(10);
/// How long lldpd may take to stop after SIGTERM.
const LLDPD_STOP: Duration = Duration::from_secs(3);
/// The host name the adapter announces as its System Name.
const HOST_NAME: &str = "lldp-adapter";
/// The adapter's msgTxInterval in the test (seconds).
const TX_INTERVAL: u16 = 2;
/// The adapter's msgTxHold in the test.
const TX_HOLD: u8 = 3;
/// lldpd's configuration: an LLDPDU every second (TTL 4 s with its hold of 4).
const LLDPD_CONFIG: &str = "configure lldp tx-interval 1\nconfigure system hostname lldp-peer\n";

#[test]
#[ignore = "needs root: network namespace, TAP and lldpd"]
fn lldp_neighbours_on_the_host_board() {
    let rig = common::start("lldp_host");
    let mac = scenario(&rig, "host");
    let log = rig.board_log();
    let pcap = rig
        .finish()
        .unwrap_or_else(|e| panic!("{e}\n{log}"))
        .expect("the rig captures");
    check_capture(&pcap, &mac);
    // SIGTERM: the shutdown LLDPDU went out before the board exited.
    let shutdown = format!("lldp && eth.src == {mac} && lldp.time_to_live == 0");
    let n = capture::count(&pcap, &shutdown).expect("read capture");
    assert_eq!(n, 1, "shutdown LLDPDUs in {}\n{log}", pcap.display());
}

#[test]
#[ignore = "needs root: network namespace, TAP, QEMU and lldpd"]
fn lldp_neighbours_on_the_emulated_board() {
    let Some(elf) = host_tests::rig::qemu_elf("generic") else {
        return;
    };
    let pcap = common::scratch("lldp_qemu.pcapng");
    let rig = Rig::start_qemu(&elf, Some(&pcap)).unwrap_or_else(|e| panic!("{e}"));
    let mac = scenario(&rig, "qemu");
    let log = rig.board_log();
    assert!(!log.contains("PANIC"), "the board panicked:\n{log}");
    let pcap = rig
        .finish()
        .unwrap_or_else(|e| panic!("{e}\n{log}"))
        .expect("the rig captures");
    check_capture(&pcap, &mac);
}

/// The whole exchange on a running board; returns the board's MAC (lower-case, colons).
fn scenario(rig: &Rig, name: &str) -> String {
    let input = json!({"host": BOARD_IP.to_string(), "phase": "setup", "host_name": HOST_NAME,
        "tx_interval": TX_INTERVAL, "tx_hold": TX_HOLD});
    let setup = peers::run(rig.ns(), "lldp_objects.py", &input, PEER_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}\nboard log:\n{}", rig.board_log()));
    println!("lldp_objects.py setup: {setup}");
    for (attr, status) in [
        ("host_name", 0),
        ("bad_interval", 0x09),
        ("bad_hold", 0x09),
        ("bad_enable", 0x09),
        ("datastore_set", 0x0E),
        ("enable", 0),
        ("interval", 0),
        ("hold", 0),
    ] {
        assert_eq!(setup[attr]["status"], status, "{attr}: {setup}");
    }
    let read = &setup["read"];
    assert_eq!(read["1"]["data"], "020003", "LLDP Enable: {setup}");
    assert_eq!(read["2"]["data"], format!("{TX_INTERVAL:02x}00"), "{setup}");
    assert_eq!(read["3"]["data"], format!("{TX_HOLD:02x}"), "{setup}");
    assert_eq!(read["4"]["data"], "0100", "LLDP Datastore: {setup}");
    assert_eq!(read["5"]["status"], 0, "Last Change: {setup}");
    let mac = mac_text(setup["mac"]["data"].as_str().unwrap_or_default());

    let lldpd = Lldpd::start(rig.ns(), name);
    let peer_mac = lldpd.chassis_mac();
    let neighbour = lldpd.wait_for_neighbour(&mac);
    println!("lldpd sees: {neighbour:?}");
    let key = |k: &str| neighbour.get(k).map(String::as_str);
    assert_eq!(key("chassis.name"), Some(HOST_NAME), "{neighbour:?}");
    let ttl = (u32::from(TX_INTERVAL) * u32::from(TX_HOLD)).to_string();
    assert_eq!(key("port.ttl"), Some(ttl.as_str()), "{neighbour:?}");
    assert_eq!(key("chassis.mgmt-ip"), Some("198.18.0.2"), "{neighbour:?}");
    assert_eq!(key("chassis.Station.enabled"), Some("on"), "{neighbour:?}");

    // The adapter's Data Table: lldpd's chassis MAC, within the discovery bound.
    let peer_hex = peer_mac.replace(':', "");
    let listed = |t: &Value| -> Option<Value> {
        let instances = t["instances"].as_object()?;
        instances
            .values()
            .find(|n| n["2"]["data"] == peer_hex)
            .cloned()
    };
    let deadline = Instant::now() + DISCOVERY;
    let (table, instance) = loop {
        let input = json!({"host": BOARD_IP.to_string(), "phase": "table"});
        let t = peers::run(rig.ns(), "lldp_objects.py", &input, PEER_TIMEOUT)
            .unwrap_or_else(|e| panic!("{e}\nboard log:\n{}", rig.board_log()));
        if let Some(found) = listed(&t) {
            break (t, found);
        }
        assert!(
            Instant::now() < deadline,
            "lldpd ({peer_mac}) not in the Data Table: {t}"
        );
        std::thread::sleep(Duration::from_millis(500));
    };
    println!("LLDP Data Table: {table}");
    assert_eq!(
        instance["1"]["data"], "0100",
        "Ethernet Link instance: {table}"
    );
    assert_eq!(instance["3"]["status"], 0, "{table}");
    // lldpd announces a TTL of 4 x its 1 s tx-interval, and (on a TAP, not forwarding)
    // the station capability as the one enabled.
    assert_eq!(instance["4"]["data"], "0400", "TTL: {table}");
    let caps = instance["5"]["data"].as_str().unwrap_or_default();
    assert_eq!(caps.get(4..), Some("8000"), "enabled capabilities: {table}");
    assert_eq!(table["count"]["data"], "0100", "instances: {table}");
    assert_eq!(table["last_change"]["status"], 0, "{table}");
    lldpd.stop();
    mac
}

/// The MAC address in a reply's hex data, as `aa:bb:...`.
fn mac_text(hex: &str) -> String {
    let bytes: Vec<&str> = (0..hex.len() / 2)
        .filter_map(|i| hex.get(2 * i..2 * i + 2))
        .collect();
    assert_eq!(bytes.len(), 6, "not a MAC address: {hex}");
    bytes.join(":")
}

/// lldpd in the namespace, on the TAP only, with its own control socket and configuration;
/// stopped (by its PID) when the test is done or fails.
struct Lldpd {
    ns_name: String,
    socket: PathBuf,
    child: LoggedChild,
}

impl Lldpd {
    fn start(ns: &Namespace, name: &str) -> Self {
        let socket = common::scratch(&format!("lldpd_{name}.socket"));
        let config = common::scratch(&format!("lldpd_{name}.conf"));
        let _ = std::fs::remove_file(&socket);
        std::fs::write(&config, LLDPD_CONFIG)
            .unwrap_or_else(|e| panic!("{}: {e}", config.display()));
        let mut cmd = ns.command("lldpd");
        // -d: in the foreground (no daemon, no pid file): its PID is the child's.
        cmd.arg("-d")
            .arg("-u")
            .arg(&socket)
            .arg("-O")
            .arg(&config)
            .args(["-I", TAP]);
        let child = LoggedChild::spawn("lldpd", cmd).unwrap_or_else(|e| panic!("lldpd: {e}"));
        Lldpd {
            ns_name: ns.name().to_string(),
            socket,
            child,
        }
    }

    /// `lldpcli -u SOCKET args... -f keyvalue` inside the namespace: its `key=value` lines.
    fn cli(&self, args: &[&str]) -> BTreeMap<String, String> {
        let mut cmd = Command::new("ip");
        cmd.args(["netns", "exec", &self.ns_name, "lldpcli", "-u"])
            .arg(&self.socket)
            .args(args)
            .args(["-f", "keyvalue"]);
        let out = run_bounded(cmd, None, LLDPCLI_TIMEOUT)
            .unwrap_or_else(|e| panic!("lldpcli {args:?}: {e}\n{}", self.child.output()));
        String::from_utf8_lossy(&out.stdout)
            .lines()
            .filter_map(|l| l.split_once('='))
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect()
    }

    /// lldpd's own chassis MAC (bounded wait for lldpd to answer).
    fn chassis_mac(&self) -> String {
        let deadline = Instant::now() + DISCOVERY;
        loop {
            let v = self.cli(&["show", "chassis"]);
            if let Some(mac) = v.get("local-chassis.chassis.mac") {
                return mac.to_lowercase();
            }
            assert!(
                Instant::now() < deadline,
                "lldpd shows no chassis: {v:?}\n{}",
                self.child.output()
            );
            std::thread::sleep(Duration::from_millis(200));
        }
    }

    /// Waits (bounded) until lldpd lists a neighbour on the TAP with chassis MAC `mac`;
    /// returns that neighbour's keys below `lldp.<TAP>.`.
    fn wait_for_neighbour(&self, mac: &str) -> BTreeMap<String, String> {
        let prefix = format!("lldp.{TAP}.");
        let deadline = Instant::now() + DISCOVERY;
        loop {
            let v = self.cli(&["show", "neighbors", "details"]);
            let ours: BTreeMap<String, String> = v
                .iter()
                .filter_map(|(k, x)| Some((k.strip_prefix(&prefix)?.to_string(), x.clone())))
                .collect();
            if ours.get("chassis.mac").map(|m| m.to_lowercase()).as_deref() == Some(mac) {
                return ours;
            }
            assert!(
                Instant::now() < deadline,
                "lldpd does not list {mac}: {v:?}\n{}",
                self.child.output()
            );
            std::thread::sleep(Duration::from_millis(200));
        }
    }

    fn stop(mut self) {
        self.child.stop(SIGTERM, LLDPD_STOP);
        let _ = std::fs::remove_file(&self.socket);
    }
}

/// The capture: the adapter's LLDPDUs (two at least, with the ODVA CIP Identification and
/// CIP MAC Address TLVs, the System Name and the TTL set), no LLDP frame malformed, and no
/// frame of the adapter's malformed or warned about.
fn check_capture(pcap: &Path, mac: &str) {
    let ours = format!("lldp && eth.src == {mac}");
    let count = |filter: &str| capture::count(pcap, filter).expect("read capture");
    let n = count(&ours);
    assert!(n >= 2, "{n} LLDPDUs from the adapter in {}", pcap.display());
    let ident = count(&format!("{ours} && cip.lldp.subtype == 1"));
    assert!(
        ident >= 1,
        "no CIP Identification TLV in {}",
        pcap.display()
    );
    let cip_mac = count(&format!("{ours} && cip.lldp.mac_address == {mac}"));
    assert!(cip_mac >= 1, "no CIP MAC Address TLV in {}", pcap.display());
    let ttl = u32::from(TX_INTERVAL) * u32::from(TX_HOLD);
    let named = count(&format!(
        "{ours} && lldp.tlv.system.name == \"{HOST_NAME}\" && lldp.time_to_live == {ttl}"
    ));
    assert!(named >= 1, "no System Name {HOST_NAME} with TTL {ttl}");
    assert_eq!(count("lldp && _ws.malformed"), 0, "malformed LLDP frames");
    // Every frame of the adapter's (lldpd's own carry a TLV Wireshark calls deprecated).
    let bad = capture::problems(pcap, &format!("eth.src == {mac}"), &[]).expect("read capture");
    assert!(bad.is_empty(), "{}:\n{}", pcap.display(), bad.join("\n"));
}
