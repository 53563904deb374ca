//! CIP Security (issue 24) with peers nobody here wrote: `enip-host --bind 127.0.0.1 --tls`
//! in a namespace of its own, certificates made here with the `openssl` CLI (a plant CA, a
//! scanner's certificate it signed, an expired one, and a rogue CA's), then
//!
//! - on plaintext 44818: ListIdentity carries the CIP Security item (0x86), and the three
//!   objects answer Get_Attributes_All;
//! - pycomm3 over Python's `ssl` reads Identity over TLS 1.2 on 2221, unconnected and over a
//!   Class 3 connection; `openssl s_client` sees TLS 1.2 with ECDHE-ECDSA-AES128-SHA256, and
//!   is refused TLS 1.3 and a suite not allowed (AES-GCM, until a configuration allows it);
//!   a plaintext RegisterSession on 2221 gets no EtherNet/IP reply; two plaintext sessions
//!   and one over TLS take the 3 sessions, and a fourth is refused on either port;
//! - pycomm3's own ListIdentity parses the reply that carries the CIP Security item;
//! - Certificate Management Create_CSR on a created instance: the CSR uploaded from the File
//!   object instance the reply names verifies with `openssl req -verify`, carries the subject
//!   asked for and the device certificate's public key; instance 1's attributes 3 and 4
//!   name the File instances holding the device certificate in use and the `--tls-ca` CA,
//!   whose uploads have those certificates' fingerprints;
//! - the configuration sequence over 44818 (Begin_Config, allowed suites with AES-GCM,
//!   client verification with expiry checked against the plant CA, Apply_Config,
//!   End_Config), after which Begin_Config over plaintext is refused (0x0F); then the scanner's certificate is let in with AES-GCM, and no certificate,
//!   the expired one and the rogue CA's are refused; the settings survive a restart on the
//!   same `--nv-file`;
//! - over TLS, TCP/IP Set_Port_Admin_State closes 44818: plaintext sessions are refused;
//! - tshark, given the clients' key log, decrypts the capture: the ENIP frames on 2221
//!   dissect, and every ENIP frame of the capture is free of malformed packets and warnings.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use host_tests::capture::Capture;
use host_tests::netns::Namespace;
use host_tests::peers;
use host_tests::process::{run_bounded, LoggedChild, SIGTERM};
use serde_json::{json, Value};

use crate::common;

/// How long a peer or a command may take.
const TIMEOUT: Duration = Duration::from_secs(60);
/// How long the program may take to listen.
const START: Duration = Duration::from_secs(15);
const HOST: &str = "127.0.0.1";

/// Runs the `openssl` CLI in `dir`; panics unless it succeeds.
fn openssl(dir: &Path, args: &[&str]) {
    let mut cmd = Command::new("openssl");
    cmd.current_dir(dir).args(args);
    let out = run_bounded(cmd, None, TIMEOUT).expect("openssl runs");
    assert!(
        out.status.success(),
        "openssl {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A P-256 key and a request for `cn`.
fn request(dir: &Path, name: &str, cn: &str) {
    let subj = format!("/CN={cn}");
    let key = format!("{name}.key");
    let csr = format!("{name}.csr");
    let args = [
        "req",
        "-new",
        "-newkey",
        "ec",
        "-pkeyopt",
        "ec_paramgen_curve:P-256",
    ];
    openssl(
        dir,
        &[
            &args[..],
            &["-nodes", "-keyout", &key, "-out", &csr, "-subj", &subj],
        ]
        .concat(),
    );
}

/// A self-signed CA `name`.
fn ca(dir: &Path, name: &str) {
    let (key, pem, subj) = (
        format!("{name}.key"),
        format!("{name}.pem"),
        format!("/CN={name}"),
    );
    let args = [
        "req",
        "-x509",
        "-newkey",
        "ec",
        "-pkeyopt",
        "ec_paramgen_curve:P-256",
    ];
    let rest = [
        "-nodes", "-keyout", &key, "-out", &pem, "-days", "30", "-subj", &subj,
    ];
    openssl(dir, &[&args[..], &rest[..]].concat());
}

/// `name`.pem signed by CA `by`, valid 30 days from now.
fn signed(dir: &Path, name: &str, by: &str, serial: &str) {
    request(dir, name, name);
    let (csr, pem) = (format!("{name}.csr"), format!("{name}.pem"));
    let (ca_pem, ca_key) = (format!("{by}.pem"), format!("{by}.key"));
    openssl(
        dir,
        &[
            "x509",
            "-req",
            "-in",
            &csr,
            "-CA",
            &ca_pem,
            "-CAkey",
            &ca_key,
            "-set_serial",
            serial,
            "-days",
            "30",
            "-out",
            &pem,
        ],
    );
}

/// `name`.pem signed by CA `by`, valid for one day in 2020.
fn expired(dir: &Path, name: &str, by: &str) {
    request(dir, name, name);
    std::fs::write(dir.join("index.txt"), "").expect("ca database");
    std::fs::write(dir.join("serial"), "10\n").expect("ca serial");
    let conf = format!(
        "[ca]\ndefault_ca = d\n[d]\ndatabase = {0}/index.txt\nnew_certs_dir = {0}\n\
         serial = {0}/serial\ndefault_md = sha256\npolicy = p\n[p]\ncommonName = supplied\n",
        dir.display()
    );
    std::fs::write(dir.join("ca.cnf"), conf).expect("ca config");
    let (csr, pem) = (format!("{name}.csr"), format!("{name}.pem"));
    let (ca_pem, ca_key) = (format!("{by}.pem"), format!("{by}.key"));
    openssl(
        dir,
        &[
            "ca",
            "-config",
            "ca.cnf",
            "-batch",
            "-notext",
            "-cert",
            &ca_pem,
            "-keyfile",
            &ca_key,
            "-in",
            &csr,
            "-out",
            &pem,
            "-startdate",
            "20200101000000Z",
            "-enddate",
            "20200102000000Z",
        ],
    );
}

/// The certificates of the test, in a fresh directory.
fn pki() -> PathBuf {
    let dir = common::scratch("cip_security");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    ca(&dir, "plant-ca");
    ca(&dir, "rogue-ca");
    signed(&dir, "scanner", "plant-ca", "2");
    signed(&dir, "rogue", "rogue-ca", "3");
    expired(&dir, "stale", "plant-ca");
    dir
}

/// `enip-host --bind 127.0.0.1 --tls` in `ns`, listening.
fn start_host(ns: &Namespace, nv: &Path, dir: &Path) -> LoggedChild {
    let mut cmd = ns.command(common::host_bin());
    cmd.args(["--bind", HOST, "--tls", "--nv-file"])
        .arg(nv)
        .arg("--tls-ca")
        .arg(dir.join("plant-ca.pem"))
        .env("RUST_LOG", "info");
    let mut host = LoggedChild::spawn("enip-host --tls", cmd).expect("start enip-host");
    host.wait_for_line("TLS on 2221", START)
        .unwrap_or_else(|e| panic!("{e}"));
    host
}

/// Runs the peer's `steps`; its outcomes.
fn peer(ns: &Namespace, host: &LoggedChild, steps: Value) -> Vec<Value> {
    let input = json!({"host": HOST, "steps": steps});
    let out = peers::run(ns, "cip_security.py", &input, TIMEOUT)
        .unwrap_or_else(|e| panic!("cip_security peer: {e}\nhost log:\n{}", host.tail(30)));
    out.as_array().expect("a list of outcomes").clone()
}

/// `openssl s_client` to 2221 with `args`: its output.
fn s_client(ns: &Namespace, dir: &Path, args: &[&str]) -> String {
    let mut cmd = ns.command("openssl");
    cmd.args(["s_client", "-connect", "127.0.0.1:2221", "-keylogfile"])
        .arg(dir.join("keylog.txt"))
        .args(args);
    let out = run_bounded(cmd, Some(b"Q\n"), TIMEOUT).expect("s_client runs");
    format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

/// A raw request step.
fn req(service: u8, class: u16, attribute: Option<u8>, data: &str) -> Value {
    let instance = if service == 0x08 { 0 } else { 1 };
    let mut step = json!({"do": "request", "service": service, "class": class,
        "instance": instance, "data": data});
    if let Some(a) = attribute {
        step["attribute"] = json!(a);
    }
    step
}

/// A TLS identity step with the scanner's certificate `client` (none: "").
fn tls(dir: &Path, ciphers: &str, client: &str) -> Value {
    let d = |f: &str| dir.join(f).display().to_string();
    let mut step = json!({"do": "tls_identity", "ciphers": ciphers,
        "server_ca": d("../cip_security.nv.device-cert.pem"), "keylog": d("keylog.txt")});
    if !client.is_empty() {
        step["client_cert"] = json!(d(&format!("{client}.pem")));
        step["client_key"] = json!(d(&format!("{client}.key")));
    }
    step
}

/// Frames of `pcap` (decrypted with the key log) that `filter` selects.
fn tshark(pcap: &Path, keylog: &Path, filter: &str) -> Vec<String> {
    let mut cmd = Command::new("tshark");
    cmd.args(["-n", "-r"])
        .arg(pcap)
        .arg("-o")
        .arg(format!("tls.keylog_file:{}", keylog.display()))
        .args([
            "-Y",
            filter,
            "-T",
            "fields",
            "-e",
            "frame.number",
            "-e",
            "_ws.col.Info",
        ]);
    let out = run_bounded(cmd, None, TIMEOUT).expect("tshark runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(str::to_string)
        .collect()
}

/// A raw request step to `instance`.
fn req_at(service: u8, class: u16, instance: u8, data: &str) -> Value {
    json!({"do": "request", "service": service, "class": class, "instance": instance,
        "data": data})
}

/// Certificate Management Create_CSR over 44818 on a created instance, the CSR uploaded
/// from the File object instance the reply names (Initiate_Upload, Upload_Transfer): it
/// verifies with `openssl req -verify`, carries the subject asked for and the public key of
/// the device certificate the TLS server presents.
fn csr_through_the_service(ns: &Namespace, host: &LoggedChild, dir: &Path) {
    let field = |s: &str| format!("{:02x}{}", s.len(), hex(s.as_bytes()));
    let subject: String = ["dev-7", "Plant", "Line 2", "", "", "DE", "", "7"]
        .iter()
        .map(|f| field(f))
        .collect();
    let steps = vec![
        req_at(0x08, 0x5F, 0, &field("csr")),
        req_at(0x4B, 0x5F, 1, &subject),
        req_at(0x4B, 0x5F, 2, &subject),
    ];
    let out = peer(ns, host, Value::Array(steps));
    let statuses: Vec<&Value> = out.iter().map(|o| &o["status"]).collect();
    assert_eq!(statuses, [0, 0x0C, 0], "{out:?}");
    assert_eq!(out[0]["data"], "0200", "the created instance: {out:?}");
    assert_eq!(out[2]["data"], "02203724c8", "{out:?}");
    let csr = upload(ns, host, 0xC8);
    std::fs::write(dir.join("device.csr"), &csr).expect("write the CSR");
    let text = |args: &[&str]| {
        let out = Command::new("openssl")
            .args(args)
            .current_dir(dir)
            .output()
            .expect("openssl runs");
        assert!(out.status.success(), "{args:?}: {out:?}");
        format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        )
    };
    let verified = text(&["req", "-in", "device.csr", "-verify", "-noout", "-subject"]);
    assert!(
        verified.contains("verify OK") || verified.contains("verification OK"),
        "{verified}"
    );
    assert!(
        verified.contains("CN = dev-7") || verified.contains("CN=dev-7"),
        "{verified}"
    );
    assert!(
        verified.contains("C = DE") || verified.contains("C=DE"),
        "{verified}"
    );
    let csr_key = text(&["req", "-in", "device.csr", "-pubkey", "-noout"]);
    let cert = dir.join("../cip_security.nv.device-cert.pem");
    let cert_key = text(&[
        "x509",
        "-in",
        &cert.display().to_string(),
        "-pubkey",
        "-noout",
    ]);
    assert!(csr_key.contains("BEGIN PUBLIC KEY"), "{csr_key}");
    assert_eq!(csr_key, cert_key, "the CSR carries the device's public key");
}

/// The bytes of File object instance `file`, uploaded over 44818 in transfers of 240.
fn upload(ns: &Namespace, host: &LoggedChild, file: u8) -> Vec<u8> {
    let mut steps = vec![req_at(0x4B, 0x37, file, "f0")];
    steps.extend((0..8).map(|n| req_at(0x4F, 0x37, file, &format!("{n:02x}"))));
    let out = peer(ns, host, Value::Array(steps));
    assert_eq!(out[0]["status"], 0, "Initiate_Upload: {out:?}");
    let size = unhex(out[0]["data"].as_str().unwrap());
    let size = u32::from_le_bytes(size[..4].try_into().unwrap()) as usize;
    let mut bytes = Vec::new();
    for o in &out[1..] {
        let d = unhex(o["data"].as_str().unwrap_or(""));
        assert_eq!(o["status"], 0, "{out:?}");
        if matches!(d[1], 2 | 4) {
            bytes.extend_from_slice(&d[2..d.len() - 2]);
            break;
        }
        bytes.extend_from_slice(&d[2..]);
    }
    assert_eq!(bytes.len(), size, "{out:?}");
    bytes
}

/// Certificate Management instance 1's attributes 3 and 4 name the File instances that
/// hold the device certificate the TLS server presents and the CA `--tls-ca` gave, status
/// verified; uploaded, they are those certificates.
fn certificates_through_the_objects(ns: &Namespace, host: &LoggedChild, dir: &Path) {
    let out = peer(ns, host, json!([req_at(0x01, 0x5F, 1, "")]));
    assert_eq!(out[0]["status"], 0, "{out:?}");
    let all = out[0]["data"].as_str().expect("Get_Attributes_All");
    // Name, state 3 (verified), device certificate: status 1 and the path to 0xC9; CA
    // certificate: status 1 and the path to 0xCA; encoding 0.
    assert!(all.ends_with("030102203724c90102203724ca00"), "{all}");
    let fingerprint = |file: &Path| {
        let out = Command::new("openssl")
            .args(["x509", "-noout", "-fingerprint", "-sha256", "-in"])
            .arg(file)
            .output()
            .expect("openssl runs");
        assert!(out.status.success(), "{out:?}");
        String::from_utf8_lossy(&out.stdout).to_string()
    };
    for (file, name, want) in [
        (
            0xC9,
            "device-cert-upload.pem",
            dir.join("../cip_security.nv.device-cert.pem"),
        ),
        (0xCA, "ca-cert-upload.pem", dir.join("plant-ca.pem")),
    ] {
        let pem = upload(ns, host, file);
        std::fs::write(dir.join(name), &pem).expect("write the certificate");
        assert_eq!(fingerprint(&dir.join(name)), fingerprint(&want), "{name}");
    }
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

fn unhex(s: &str) -> Vec<u8> {
    (0..s.len() / 2)
        .map(|i| u8::from_str_radix(&s[2 * i..2 * i + 2], 16).expect("hex"))
        .collect()
}

#[test]
#[ignore = "needs root, the Python peers, openssl and tshark"]
fn tls_on_2221_and_the_security_objects_with_independent_peers() {
    let dir = pki();
    let nv = common::fresh_nv_file("cip_security.nv");
    let _ = std::fs::remove_file(common::scratch("cip_security.nv.device-cert.pem"));
    let ns = Namespace::create().expect("namespace");
    let pcap = common::scratch("cip_security.pcapng");
    let capture = Capture::start(&ns, "lo", &pcap).expect("tshark captures");
    let mut host = start_host(&ns, &nv, &dir);

    // Plaintext 44818: the ListIdentity item and the objects.
    let out = peer(
        &ns,
        &host,
        json!([
            {"do": "list_identity"},
            req(0x01, 0x5D, None, ""),
            req(0x01, 0x5E, None, ""),
            req(0x01, 0x5F, None, ""),
            {"do": "plaintext"},
            {"do": "pycomm3_list_identity"},
            req(0x0E, 0xF5, Some(14), ""),
        ]),
    );
    let items = out[0]["items"].as_array().expect("items");
    assert_eq!(items[1], json!([0x86, "020000000f"]), "{out:?}");
    assert_eq!(out[1]["data"], "000200", "{out:?}");
    assert!(
        out[2]["data"]
            .as_str()
            .unwrap()
            .starts_with("000000000004c023c024c02bc02c02c023c024"),
        "{out:?}"
    );
    assert_eq!(out[3]["status"], 0, "{out:?}");
    assert_eq!(out[4]["enip_reply"], false, "{out:?}");
    assert_eq!(out[5]["product_name"], common::NAME, "{out:?}");
    assert_eq!(out[6]["status"], 0, "TCP/IP attribute 14: {out:?}");
    csr_through_the_service(&ns, &host, &dir);
    certificates_through_the_objects(&ns, &host, &dir);

    // TLS: pycomm3 over Python's ssl, and openssl s_client.
    let out = peer(
        &ns,
        &host,
        json!([tls(&dir, "ECDHE-ECDSA-AES128-SHA256", "")]),
    );
    assert_eq!(out[0]["ok"], true, "{out:?}");
    assert_eq!(out[0]["version"], "TLSv1.2");
    assert_eq!(out[0]["cipher"], "ECDHE-ECDSA-AES128-SHA256");
    assert_eq!(out[0]["product_name"], common::NAME);
    assert_eq!(out[0]["connected_name"], common::NAME, "{out:?}");
    // The 3 sessions are shared by both ports.
    let mut step = tls(&dir, "ECDHE-ECDSA-AES128-SHA256", "");
    step["do"] = json!("capacity");
    let out = peer(&ns, &host, json!([step]));
    let want = json!({"fourth_tls_refused": true, "fourth_plain_refused": true, "tls_again": true});
    assert_eq!(out[0], want, "{out:?}");
    let s = s_client(&ns, &dir, &["-tls1_2"]);
    assert!(s.contains("Cipher is ECDHE-ECDSA-AES128-SHA256"), "{s}");
    assert!(s.contains("Protocol  : TLSv1.2"), "{s}");
    let s = s_client(
        &ns,
        &dir,
        &["-tls1_2", "-cipher", "ECDHE-ECDSA-AES128-GCM-SHA256"],
    );
    assert!(s.contains("handshake failure"), "{s}");
    let s = s_client(&ns, &dir, &["-tls1_3"]);
    assert!(s.contains("Cipher is (NONE)"), "{s}");

    // The configuration sequence over 44818.
    let path_to_1 = "0102205f2401";
    let out = peer(
        &ns,
        &host,
        json!([
            req(0x4B, 0x5D, None, ""),
            req(0x4B, 0x5E, None, ""),
            req(0x10, 0x5E, Some(4), "02c02bc023"),
            req(0x10, 0x5E, Some(7), path_to_1),
            req(0x10, 0x5E, Some(9), "01"),
            req(0x10, 0x5E, Some(11), "01"),
            req(0x10, 0x5E, Some(4), "010033"),
            req(0x4D, 0x5E, None, "00000000"),
            req(0x4D, 0x5D, None, ""),
            req(0x0E, 0x5D, Some(1), ""),
            // Configured: no reconfiguration over plaintext.
            req(0x4B, 0x5E, None, ""),
        ]),
    );
    let statuses: Vec<&Value> = out.iter().map(|o| &o["status"]).collect();
    assert_eq!(statuses, [0, 0, 0, 0, 0, 0, 9, 0, 0, 0, 0x0F], "{out:?}");
    assert_eq!(out[9]["data"], "02");

    let gcm = "ECDHE-ECDSA-AES128-GCM-SHA256";
    let refusals = |host: &LoggedChild| {
        let out = peer(
            &ns,
            host,
            json!([
                tls(&dir, gcm, "scanner"),
                tls(&dir, gcm, ""),
                tls(&dir, gcm, "stale"),
                tls(&dir, gcm, "rogue"),
            ]),
        );
        assert_eq!(out[0]["ok"], true, "{out:?}");
        assert_eq!(out[0]["cipher"], gcm);
        for (o, what) in out[1..]
            .iter()
            .zip(["no certificate", "expired", "wrong CA"])
        {
            assert_eq!(o["ok"], false, "{what}: {o}");
        }
    };
    refusals(&host);
    let log = host.output();
    assert!(
        log.contains("certificate has expired") || log.contains("certificate expired"),
        "{log}"
    );

    // A restart on the same store keeps the configuration.
    host.stop(SIGTERM, Duration::from_secs(5));
    let host = start_host(&ns, &nv, &dir);
    refusals(&host);
    let out = peer(&ns, &host, json!([{"do": "list_identity"}]));
    assert_eq!(out[0]["items"][1], json!([0x86, "020002020f"]), "{out:?}");
    // Over TLS, the scanner closes 44818 to explicit messaging (TCP/IP Set_Port_Admin_State):
    // a plaintext session is refused from then on, TLS is served.
    let mut close = tls(&dir, gcm, "scanner");
    close["do"] = json!("tls_message");
    for (k, v) in [("service", 0x4C), ("class", 0xF5), ("instance", 1)] {
        close[k] = json!(v);
    }
    close["data"] = json!("0112af0600");
    let out = peer(
        &ns,
        &host,
        json!([{"do": "plain_register"}, close, {"do": "plain_register"}, tls(&dir, gcm, "scanner")]),
    );
    assert_eq!(out[0]["served"], true, "{out:?}");
    assert_eq!(out[1]["error"], Value::Null, "{out:?}");
    assert_eq!(out[2]["served"], false, "{out:?}");
    assert_eq!(out[3]["ok"], true, "{out:?}");
    // And stays closed after a restart.
    drop(host);
    let host = start_host(&ns, &nv, &dir);
    let out = peer(
        &ns,
        &host,
        json!([{"do": "plain_register"}, tls(&dir, gcm, "scanner")]),
    );
    assert_eq!(out[0]["served"], false, "{out:?}");
    assert_eq!(out[1]["ok"], true, "{out:?}");
    drop(host);

    let pcap = capture.stop();
    let keylog = dir.join("keylog.txt");
    let secure = tshark(&pcap, &keylog, "tcp.port == 2221 && enip");
    assert!(secure.len() >= 8, "ENIP over TLS not decrypted: {secure:?}");
    assert!(!tshark(&pcap, &keylog, "enip.security_profiles").is_empty());
    assert!(!tshark(&pcap, &keylog, "cip.eip_security.state").is_empty());
    let bad = tshark(
        &pcap,
        &keylog,
        "enip && (_ws.malformed || _ws.expert.severity >= 0x00600000)",
    );
    assert!(
        bad.is_empty(),
        "frames that do not dissect cleanly: {bad:#?}"
    );
}
