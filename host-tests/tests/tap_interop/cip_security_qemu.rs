//! CIP Security on the microcontroller path (issue 24): the emulated board's TLS image
//! (`ENIP_QEMU_TLS_ELF`: `enip-qemu-mps2` built with feature `tls`, mbedTLS in its static
//! arena, a self-signed P-256 certificate made at build time) booted in QEMU on a TAP, then
//!
//! - `openssl s_client` completes TLS 1.2 handshakes on 2221 with ECDHE-ECDSA-AES128-SHA256
//!   and AES256-SHA384, and is refused AES-GCM (not offered by default) and TLS 1.3;
//! - pycomm3 over Python's `ssl`, trusting the certificate the board presented, reads
//!   Identity over TLS unconnected and over a Class 3 connection;
//! - after the configuration sequence over 44818 (Begin_Config, allowed suites AES-128-GCM
//!   and AES-128-CBC, Apply_Config, End_Config), a handshake with AES-128-GCM succeeds and one
//!   with AES-256-CBC-SHA384 is refused.
//!
//! The capture (the TLS records undecrypted, the configuration in plaintext) is checked like
//! every other. Skipped, loudly, without the ELF.

use std::path::Path;
use std::time::Duration;

use host_tests::netns::Namespace;
use host_tests::peers;
use host_tests::process::run_bounded;
use host_tests::rig::{Rig, BOARD_IP};
use serde_json::json;

use crate::common;

/// The variable naming the TLS image.
const ELF_VAR: &str = "ENIP_QEMU_TLS_ELF";
/// How long a peer or a command may take.
const TIMEOUT: Duration = Duration::from_secs(60);
/// Connection attempts of one `s_client` run.
const CONNECT_TRIES: usize = 10;

/// `openssl s_client` to the board's 2221 with `args`: its output. The image has one TLS
/// socket, which listens again only once the previous connection has closed: a refused
/// connect is tried again (up to [`CONNECT_TRIES`] times).
fn s_client(ns: &Namespace, args: &[&str]) -> String {
    let mut out = String::new();
    for _ in 0..CONNECT_TRIES {
        let mut cmd = ns.command("openssl");
        cmd.args(["s_client", "-connect", &format!("{BOARD_IP}:2221")])
            .args(args);
        let run = run_bounded(cmd, Some(b"Q\n"), TIMEOUT).expect("s_client runs");
        out = format!(
            "{}{}",
            String::from_utf8_lossy(&run.stdout),
            String::from_utf8_lossy(&run.stderr)
        );
        if !out.contains("Connection refused") {
            break;
        }
        std::thread::sleep(Duration::from_millis(300));
    }
    out
}

/// The PEM certificate in `s_client`'s output.
fn presented_certificate(out: &str) -> String {
    let (begin, end) = ("-----BEGIN CERTIFICATE-----", "-----END CERTIFICATE-----");
    let from = out.find(begin).expect("s_client shows the certificate");
    let to = out[from..].find(end).expect("the certificate ends") + from + end.len();
    format!("{}\n", &out[from..to])
}

#[test]
#[ignore = "needs root, QEMU and ENIP_QEMU_TLS_ELF"]
fn tls_on_2221_of_the_emulated_board_through_mbedtls() {
    let Some(elf) = std::env::var_os(ELF_VAR) else {
        eprintln!("SKIPPED: set {ELF_VAR} to enip-qemu-mps2 built with --features tls");
        return;
    };
    let pcap = common::scratch("cip_security_qemu.pcapng");
    let rig = Rig::start_qemu(Path::new(&elf), Some(&pcap)).unwrap_or_else(|e| panic!("{e}"));
    let ns = rig.ns();
    let log = || rig.board_log_tail(30);

    let s = s_client(ns, &["-tls1_2"]);
    assert!(
        s.contains("Cipher is ECDHE-ECDSA-AES128-SHA256"),
        "{s}\n{}",
        log()
    );
    assert!(s.contains("Protocol  : TLSv1.2"), "{s}");
    let cert = common::scratch("cip_security_qemu.device-cert.pem");
    std::fs::write(&cert, presented_certificate(&s)).expect("scratch is writable");
    let s = s_client(ns, &["-tls1_2", "-cipher", "ECDHE-ECDSA-AES256-SHA384"]);
    assert!(s.contains("Cipher is ECDHE-ECDSA-AES256-SHA384"), "{s}");
    let s = s_client(ns, &["-tls1_2", "-cipher", "ECDHE-ECDSA-AES128-GCM-SHA256"]);
    assert!(s.contains("Cipher is (NONE)"), "{s}");
    let s = s_client(ns, &["-tls1_3"]);
    assert!(s.contains("Cipher is (NONE)"), "{s}");

    let step = json!({"do": "tls_identity", "ciphers": "ECDHE-ECDSA-AES128-SHA256",
        "server_ca": cert.display().to_string()});
    let input = json!({"host": BOARD_IP.to_string(), "steps": [step]});
    let out = peers::run(ns, "cip_security.py", &input, TIMEOUT)
        .unwrap_or_else(|e| panic!("cip_security peer: {e}\nboard log:\n{}", log()));
    assert_eq!(out[0]["ok"], true, "{out}\n{}", log());
    assert_eq!(out[0]["version"], "TLSv1.2", "{out}");
    assert_eq!(out[0]["product_name"], common::NAME, "{out}");
    assert_eq!(out[0]["connected_name"], common::NAME, "{out}");

    // The configuration sequence over 44818 allows AES-128-GCM and AES-128-CBC only: the
    // next handshakes offer those.
    let req = |service: u8, class: u16, attribute: Option<u8>, data: &str| {
        let mut step = json!({"do": "request", "service": service, "class": class,
            "instance": 1, "data": data});
        if let Some(a) = attribute {
            step["attribute"] = json!(a);
        }
        step
    };
    let steps = json!([
        req(0x4B, 0x5D, None, ""),
        req(0x4B, 0x5E, None, ""),
        req(0x10, 0x5E, Some(4), "02c02bc023"),
        req(0x4D, 0x5E, None, "00000000"),
        req(0x4D, 0x5D, None, ""),
    ]);
    let input = json!({"host": BOARD_IP.to_string(), "steps": steps});
    let out = peers::run(ns, "cip_security.py", &input, TIMEOUT)
        .unwrap_or_else(|e| panic!("cip_security peer: {e}\nboard log:\n{}", log()));
    for (i, reply) in out.as_array().expect("a list").iter().enumerate() {
        assert_eq!(reply["status"], 0, "step {i}: {out}");
    }
    let s = s_client(ns, &["-tls1_2", "-cipher", "ECDHE-ECDSA-AES128-GCM-SHA256"]);
    assert!(s.contains("Cipher is ECDHE-ECDSA-AES128-GCM-SHA256"), "{s}");
    let s = s_client(ns, &["-tls1_2", "-cipher", "ECDHE-ECDSA-AES256-SHA384"]);
    assert!(s.contains("Cipher is (NONE)"), "{s}");

    let log = rig.board_log();
    assert!(log.contains("tls: mbedTLS listening on 2221"), "{log}");
    assert!(!log.contains("PANIC"), "the board panicked:\n{log}");
    common::finish(rig);
}
