//! Chooses the QEMU machine (cargo features `an385`, `an386`, `an500`, `an505`), links with
//! its memory map and bakes in the network settings, profile and Address Conflict Detection
//! and test-image choices (with feature `tls`, the TLS certificate).

include!("../build-support/board_build.rs");

use std::path::Path;
use std::process::{Command, Stdio};

/// The machines: feature, the target it builds for, and its memory map. The first is the
/// default, which gives way to any other.
const MACHINES: [(&str, &str, &str); 4] = [
    ("an386", "thumbv7em-none-eabihf", "memory.x"),
    ("an385", "thumbv7m-none-eabi", "memory.x"),
    ("an500", "thumbv7em-none-eabihf", "memory.x"),
    ("an505", "thumbv8m.main-none-eabihf", "memory-an505.x"),
];

fn main() {
    let memory_x = machine();
    link_with_own_memory_map(memory_x);
    network_settings("198.18.0.2/24");
    profile_from_features();
    acd_setting();
    test_faults_setting();
    if env::var_os("CARGO_FEATURE_TLS").is_some() {
        tls_material();
    }
}

/// The `tls` image's device certificate and key (DER) in `OUT_DIR`: `ENIP_TLS_CERT_DER` and
/// `ENIP_TLS_KEY_DER` if set, otherwise a self-signed ECDSA P-256 pair the `openssl` CLI
/// makes here (a stand-in for the factory certificate a real device is provisioned with);
/// `ENIP_TLS_CA_DER` (optional) is the CA client certificates are checked against.
fn tls_material() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("OUT_DIR"));
    for var in ["ENIP_TLS_CERT_DER", "ENIP_TLS_KEY_DER", "ENIP_TLS_CA_DER"] {
        println!("cargo:rerun-if-env-changed={var}");
    }
    let (cert, key) = match (
        env::var_os("ENIP_TLS_CERT_DER"),
        env::var_os("ENIP_TLS_KEY_DER"),
    ) {
        (Some(cert), Some(key)) => (PathBuf::from(cert), PathBuf::from(key)),
        _ => self_signed(&out),
    };
    copy(&cert, &out.join("tls_cert.der"));
    copy(&key, &out.join("tls_key.der"));
    match env::var_os("ENIP_TLS_CA_DER") {
        Some(ca) => copy(Path::new(&ca), &out.join("tls_ca.der")),
        None => fs::write(out.join("tls_ca.der"), []).expect("write tls_ca.der"),
    }
}

/// A self-signed P-256 certificate and its key, made by the `openssl` CLI in `dir`.
fn self_signed(dir: &Path) -> (PathBuf, PathBuf) {
    let (pem_key, pem_cert) = (dir.join("tls_key.pem"), dir.join("tls_cert.pem"));
    let (cert, key) = (dir.join("self_cert.der"), dir.join("self_key.der"));
    openssl(
        &[
            "req",
            "-x509",
            "-newkey",
            "ec",
            "-pkeyopt",
            "ec_paramgen_curve:P-256",
            "-nodes",
            "-days",
            "3650",
            "-subj",
            "/CN=enip-qemu-mps2",
            "-keyout",
        ],
        &[&pem_key, Path::new("-out"), &pem_cert],
    );
    openssl(
        &["x509", "-outform", "DER", "-in"],
        &[&pem_cert, Path::new("-out"), &cert],
    );
    openssl(
        &["pkey", "-outform", "DER", "-in"],
        &[&pem_key, Path::new("-out"), &key],
    );
    (cert, key)
}

/// Runs `openssl` with `args` then `paths`, or fails the build.
fn openssl(args: &[&str], paths: &[&Path]) {
    let status = Command::new("openssl")
        .args(args)
        .args(paths)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .expect(
            "the tls feature needs the openssl CLI (or ENIP_TLS_CERT_DER and ENIP_TLS_KEY_DER)",
        );
    assert!(status.success(), "openssl {args:?} failed");
}

/// Copies `from` to `to`, or fails the build.
fn copy(from: &Path, to: &Path) {
    println!("cargo:rerun-if-changed={}", from.display());
    fs::copy(from, to).unwrap_or_else(|e| panic!("{}: {e}", from.display()));
}

/// Sets the `mps2_machine` cfg to the chosen machine and returns its memory map; fails the
/// build on two non-default machines or a target the machine's core does not run.
fn machine() -> &'static str {
    let values: Vec<String> = MACHINES
        .iter()
        .map(|(m, _, _)| format!("\"{m}\""))
        .collect();
    println!(
        "cargo::rustc-check-cfg=cfg(mps2_machine, values({}))",
        values.join(", ")
    );
    let enabled = |m: &str| env::var_os(format!("CARGO_FEATURE_{}", m.to_uppercase())).is_some();
    let others: Vec<_> = MACHINES[1..]
        .iter()
        .filter(|(m, _, _)| enabled(m))
        .collect();
    let (name, target, memory_x) = match others.as_slice() {
        [] => MACHINES[0],
        [one] => **one,
        _ => panic!("enable one machine feature (an385, an386, an500, an505), not several"),
    };
    let building_for = env::var("TARGET").unwrap_or_default();
    assert!(
        building_for == target,
        "the {name} machine builds for --target {target}, not {building_for}"
    );
    println!("cargo::rustc-cfg=mps2_machine=\"{name}\"");
    memory_x
}
