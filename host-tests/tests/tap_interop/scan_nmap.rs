//! A network scanner nobody here wrote, Debian's `nmap`, against the board while the flood
//! tests' load runs (`floods_load.rs`: Class 1 connections, a pycomm3 session, fresh
//! clients): the port states of TCP SYN, FIN, NULL, Xmas and ACK scans and of a UDP scan,
//! an ICMP echo ping, its `enip-info` script over TCP and UDP, and OS detection, whose
//! probes are the odd segments a scanner sends (no flags, SYN with FIN, URG and PSH, ACKs
//! to open and closed ports, a UDP datagram to a closed port).
//!
//! What the board must show (RFC 9293 3.10.7 for the segments, RFC 1122 3.2.2.6 for the
//! echo): 44818 open and every other TCP port closed, each closed port answering with a RST
//! (not "filtered", as an ICMP "protocol unreachable" from a stack without TCP of its own
//! would make it); FIN, NULL and Xmas probes dropped by the listening port and reset by the
//! closed one; a closed UDP port answered with ICMP "port unreachable"; echo requests
//! answered, but not those to the broadcast address; segments with IPv4 identification 0 (no counter for an idle scan); its
//! identity read by `enip-info`; and the load undisturbed.

use std::collections::BTreeMap;
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use crate::common;
use crate::floods::{assert_t_o_held, hping3_count};
use crate::floods_load::{flood_run, phase, Flood, QEMU_RPI, RPI};
use host_tests::netns::Namespace;
use host_tests::process::run_bounded;
use host_tests::rig::{Rig, BOARD_IP};

/// The scans' phase: they take 11 to 13 s on either board; the rest is room.
const SCAN_PHASE: Duration = Duration::from_secs(20);
/// The phase without scans before it.
const QUIET_PHASE: Duration = Duration::from_secs(2);
/// A TCP port nothing on the board listens on.
const CLOSED_TCP: u16 = 80;
/// A UDP port nothing on the board listens on (SNMP's).
const CLOSED_UDP: u16 = 161;

/// Runs `nmap args` against the board inside `ns`, bounded by `until`; its standard output.
fn nmap(ns: &Namespace, args: &[&str], until: Instant) -> String {
    let mut cmd = ns.command("nmap");
    // No DNS, no host discovery unless asked for, and no more than the board.
    cmd.args(["-n", "--max-retries", "2"]).args(args);
    cmd.arg(BOARD_IP.to_string());
    let left = until.saturating_duration_since(Instant::now());
    let out = run_bounded(cmd, None, left).unwrap_or_else(|e| panic!("nmap {args:?}: {e}"));
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "nmap {args:?} failed: {text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    text
}

/// The port states of an `-oG -` report: "44818/tcp" -> "open", ...
fn port_states(grepable: &str) -> BTreeMap<String, String> {
    let ports = grepable
        .lines()
        .filter_map(|l| l.split_once("Ports: "))
        .flat_map(|(_, ports)| ports.split('\t').next().unwrap_or("").split(", "));
    ports
        .filter_map(|p| {
            let mut f = p.split('/');
            let (port, state, proto) = (f.next()?, f.next()?, f.next()?);
            Some((format!("{port}/{proto}"), state.to_string()))
        })
        .collect()
}

/// A port scan of `kind` (`-sS`, `-sU`, ...) of `ports`: their states.
fn scan(ns: &Namespace, kind: &str, ports: &str, until: Instant) -> Value {
    let report = nmap(ns, &["-Pn", kind, "-p", ports, "-oG", "-"], until);
    json!(port_states(&report))
}

/// The fields `enip-info` printed ("productName" -> "enip-rs generic", ...). Asked a second
/// time if the first printed none: over TCP the script needs one of the board's three
/// sessions, and the load's session churn (a new session every 250 ms, beside pycomm3's and
/// the scanner's) can hold the last one at that moment; the script does not try again. The
/// first report is printed when it was.
fn enip_info(ns: &Namespace, kind: &str, until: Instant) -> Value {
    let args = ["-Pn", kind, "-p", "44818", "--script", "enip-info"];
    let report = nmap(ns, &args, until);
    let fields = script_fields(&report);
    if fields.as_object().is_some_and(|f| !f.is_empty()) {
        return fields;
    }
    println!("enip-info {kind} printed nothing, asked again; its report:\n{report}");
    script_fields(&nmap(ns, &args, until))
}

/// The lines a script printed: "|   productName: enip-rs generic", the last "|_  ...".
fn script_fields(report: &str) -> Value {
    let fields: BTreeMap<&str, &str> = report
        .lines()
        .filter_map(|l| l.strip_prefix('|'))
        .filter_map(|l| l.trim_start_matches(['_', ' ']).split_once(": "))
        .map(|(k, v)| (k.trim(), v.trim()))
        .collect();
    json!(fields)
}

/// OS detection's probes and what the board answered to each, from the fingerprint nmap
/// prints: "T5" -> {"R": "Y", "F": "AR", ...}.
fn os_probes(ns: &Namespace, until: Instant) -> Value {
    let ports = format!("44818,{CLOSED_TCP}");
    let report = nmap(
        ns,
        &["-Pn", "-O", "--max-os-tries", "1", "-d", "-p", &ports],
        until,
    );
    let fingerprint: String = report
        .lines()
        .filter_map(|l| l.strip_prefix("OS:"))
        .collect();
    // Wrapped in `OS:` lines as a rule; in one piece when nmap finds its test conditions
    // less than ideal.
    let fingerprint = if fingerprint.is_empty() {
        report
            .lines()
            .skip_while(|l| !l.starts_with("TCP/IP fingerprint:"))
            .skip(1)
            .take_while(|l| l.contains('('))
            .collect::<String>()
    } else {
        fingerprint
    };
    let probes: BTreeMap<String, BTreeMap<String, String>> = fingerprint
        .split_inclusive(')')
        .filter_map(|t| {
            let (name, fields) = t.trim().strip_suffix(')')?.split_once('(')?;
            let fields = fields
                .split('%')
                .filter_map(|kv| kv.split_once('='))
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect();
            Some((name.to_string(), fields))
        })
        .collect();
    json!(probes)
}

/// Echo replies to three echo requests to the namespace's broadcast address (hping3: nmap
/// has no broadcast ping): none is answered (RFC 1122 3.2.2.6; the board is no amplifier).
fn broadcast_echo_replies(ns: &Namespace, until: Instant) -> u64 {
    let mut cmd = ns.command("hping3");
    cmd.args(["--icmp", "-c", "3", "-i", "u200000", "198.18.0.255"]);
    let left = until.saturating_duration_since(Instant::now());
    let out = run_bounded(cmd, None, left).unwrap_or_else(|e| panic!("hping3: {e}"));
    // Its statistics go to standard error.
    hping3_count(&String::from_utf8_lossy(&out.stderr), "packets received")
}

/// Every scan, one after the other, within `f.until`; their findings.
fn scans(f: &Flood<'_>) -> Value {
    let (ns, until) = (f.ns, f.until);
    let tcp = format!("22,{CLOSED_TCP},2222,44818");
    let probed = format!("{CLOSED_TCP},44818");
    let udp = format!("{CLOSED_UDP},2222,44818");
    let start = Instant::now();
    let ping = nmap(ns, &["-sn", "-PE", "--disable-arp-ping", "--reason"], until);
    let mut found = json!({
        "syn": scan(ns, "-sS", &tcp, until),
        "fin": scan(ns, "-sF", &probed, until),
        "null": scan(ns, "-sN", &probed, until),
        "xmas": scan(ns, "-sX", &probed, until),
        "ack": scan(ns, "-sA", &probed, until),
        "udp": scan(ns, "-sU", &udp, until),
        "echo_ping_up": ping.contains("Host is up, received echo-reply"),
        "broadcast_echo_replies": broadcast_echo_replies(ns, until),
        "enip_info_tcp": enip_info(ns, "-sT", until),
        "enip_info_udp": enip_info(ns, "-sU", until),
        "os_probes": os_probes(ns, until),
    });
    found["seconds"] = json!(start.elapsed().as_secs_f64());
    found
}

/// Runs the scans against `rig`'s board `program` with the load at `rpi`, checks what they
/// found and that the load held.
fn scan_board(rig: &Rig, program: &str, rpi: Duration, scenario: &str) {
    let run = flood_run(
        rig,
        program,
        rpi,
        scenario,
        QUIET_PHASE,
        &[("nmap", SCAN_PHASE, &scans)],
    );
    let found = &phase(&run, "nmap")["flood"];
    println!("{scenario}: {found:#}");
    let state = |scan: &str, port: String| found[scan][&port].as_str().unwrap_or("?").to_string();
    let closed = format!("{CLOSED_TCP}/tcp");
    for port in ["22/tcp", &closed, "2222/tcp"] {
        assert_eq!(
            state("syn", port.into()),
            "closed",
            "SYN scan, {port}: {found}"
        );
    }
    assert_eq!(state("syn", "44818/tcp".into()), "open", "{found}");
    for kind in ["fin", "null", "xmas"] {
        // The listening port drops them; the closed port resets them.
        assert_eq!(
            (state(kind, "44818/tcp".into()), state(kind, closed.clone())),
            ("open|filtered".into(), "closed".into()),
            "{kind} scan: {found}"
        );
    }
    for port in ["44818/tcp", &closed] {
        assert_eq!(
            state("ack", port.into()),
            "unfiltered",
            "ACK scan, {port}: {found}"
        );
    }
    assert_eq!(
        state("udp", format!("{CLOSED_UDP}/udp")),
        "closed",
        "{found}"
    );
    assert_eq!(found["echo_ping_up"], json!(true), "no echo reply: {found}");
    assert_eq!(
        found["broadcast_echo_replies"],
        json!(0),
        "a broadcast echo request answered: {found}"
    );
    for info in ["enip_info_tcp", "enip_info_udp"] {
        let i = &found[info];
        assert_eq!(
            (&i["productName"], &i["deviceIp"], &i["type"]),
            (
                &json!(common::NAME),
                &json!(BOARD_IP.to_string()),
                &json!("Communications Adapter (12)")
            ),
            "{info}: {found}"
        );
    }
    // OS detection's probes: T1 a SYN to the open port; T2 (no flags) and T3 (SYN, FIN, URG,
    // PSH) to it dropped; T4 an ACK to it, T5-T7 a SYN, an ACK and FIN|PSH|URG to the closed
    // port, each reset; U1 a UDP datagram to a closed port, "port unreachable".
    let os = &found["os_probes"];
    let answered = |t: &str| os[t]["R"].as_str().unwrap_or("?").to_string();
    for t in ["T1", "T4", "T5", "T6", "T7", "U1"] {
        assert_eq!(answered(t), "Y", "OS probe {t} unanswered: {os}");
    }
    for t in ["T2", "T3"] {
        assert_eq!(answered(t), "N", "OS probe {t} answered: {os}");
    }
    for (t, flags) in [("T4", "R"), ("T5", "AR"), ("T6", "R"), ("T7", "AR")] {
        assert_eq!(os[t]["F"], json!(flags), "OS probe {t}: {os}");
    }
    // The IPv4 identification of the SYN-ACKs (TI) and of the closed port's RSTs (CI): zero,
    // so the board cannot serve as an idle scan's zombie (`nmap -sI`).
    assert_eq!(
        (&os["SEQ"]["TI"], &os["SEQ"]["CI"]),
        (&json!("Z"), &json!("Z")),
        "IP identification: {os}"
    );
    assert_t_o_held(&run, "nmap");
    let fresh = &phase(&run, "nmap")["new_sessions"];
    assert!(
        fresh["served"].as_u64().unwrap_or(0) > 0,
        "no new session served during the scans: {run}"
    );
}

#[test]
#[ignore = "needs root: network namespace and TAP, nmap"]
fn scan_nmap() {
    let rig = Rig::start(&common::host_bin(), "generic", None).expect("rig");
    scan_board(&rig, "enip-host", RPI, "scan_nmap");
    rig.finish().expect("the board ran to the end");
}

#[test]
#[ignore = "needs root: network namespace and TAP, QEMU, nmap"]
fn scan_nmap_qemu() {
    let Some(elf) = host_tests::rig::qemu_elf("generic") else {
        return;
    };
    let rig = Rig::start_qemu(&elf, None).unwrap_or_else(|e| panic!("{e}"));
    scan_board(&rig, "qemu-system-arm", QEMU_RPI, "scan_nmap_qemu");
    rig.finish().expect("the board ran to the end");
}
