//! `cargo xtask setup`: installs what the tests need, idempotently and quietly when present.

use std::fs;
use std::process::Command;

use enip_lab::peers::{npm_dir, venv_dir, venv_python};

use crate::util::{self, err, have, loud, output, run, run_quiet, Result};

/// The cross target the firmware and boards build for.
pub const THUMB_TARGET: &str = "thumbv7em-none-eabihf";
/// The Cortex-M33 target (NUCLEO-H563ZI).
pub const V8M_TARGET: &str = "thumbv8m.main-none-eabihf";
/// Every cross target a board builds for.
pub const CROSS_TARGETS: [&str; 4] = [THUMB_TARGET, V8M_TARGET, THUMBV6M_TARGET, V7M_TARGET];
/// The Cortex-M3 target (the emulated mps2-an385).
pub const V7M_TARGET: &str = "thumbv7m-none-eabi";
/// The Cortex-M0+ target of the W5500-EVB-Pico (RP2040).
pub const THUMBV6M_TARGET: &str = "thumbv6m-none-eabi";
/// The toolchain `cargo fuzz` needs.
pub const NIGHTLY: &str = "nightly";
/// Python peers for the interop tests, pinned; installed into [`venv_dir`].
pub const PYTHON_PEERS: &[&str] = &[
    "pycomm3==1.2.16",
    "cpppo==5.2.5",
    "ethernetip==1.2.0",
    "dpkt==1.9.8",
    "eds-pie==1.2.0",
    // EIPScanner (C++), bundled with the NATS bridge that is its only Python binding.
    "eip2nats==1.3.2",
];
/// npm peers for the interop tests, pinned; installed into [`npm_dir`].
pub const NPM_PEERS: &[&str] = &["st-ethernet-ip@2.7.5"];
/// Debian packages the tests need, each with a command that shows it is already there.
pub const APT_PACKAGES: &[(&str, &[&str])] = &[
    ("tshark", &["tshark", "--version"]),
    ("qemu-system-arm", &["qemu-system-arm", "--version"]),
    (
        "binutils-arm-none-eabi",
        &["arm-none-eabi-objdump", "--version"],
    ),
    ("iproute2", &["ip", "-V"]),
    ("valgrind", &["valgrind", "--version"]),
    ("python3-venv", &["python3", "-c", "import venv, ensurepip"]),
    // The npm peer (st-ethernet-ip) and the fault tests' real-time priority (`chrt`).
    ("npm", &["npm", "--version"]),
    ("util-linux", &["chrt", "--version"]),
    // The flood tests' board priority (nice -20: `renice`, Debian's bsdutils).
    ("bsdutils", &["renice", "--version"]),
    // Where the eip2nats bridge publishes the T->O data EIPScanner receives.
    ("nats-server", &["nats-server", "--version"]),
    // Layer-2 peers of the conformance tests: an LLDP agent and an ARP prober (RFC 5227).
    ("lldpd", &["lldpd", "-v"]),
    ("arping", &["arping", "--help"]),
    // The SYN floods of the flood tests (issue 28).
    ("hping3", &["hping3", "--version"]),
    // The network scanner of the scan test: port states, OS detection's odd probes, and
    // its `enip-info` script.
    ("nmap", &["nmap", "--version"]),
    // EtherNet/IP over TLS (`enip-host --tls`, issue 24): the openssl crate builds against
    // the system's OpenSSL; the CIP Security test makes its certificates with the CLI.
    ("pkg-config", &["pkg-config", "--version"]),
    ("libssl-dev", &["pkg-config", "--exists", "openssl"]),
    ("openssl", &["openssl", "version"]),
    // The emulated board's TLS image (`enip-tls-mbedtls`, issue 24): mbedTLS compiled for
    // the Cortex-M with the cross C compiler and newlib's headers.
    ("gcc-arm-none-eabi", &["arm-none-eabi-gcc", "--version"]),
    (
        "libnewlib-arm-none-eabi",
        &["test", "-e", "/usr/lib/arm-none-eabi/include/string.h"],
    ),
];

/// Everything: Rust target and toolchains, Debian packages, Python and npm peers.
pub fn all() -> Result {
    rust_target()?;
    if !nightly() {
        loud(
            "the nightly toolchain is missing and could not be installed: fuzzing will be SKIPPED",
        );
    }
    cargo_fuzz()?;
    let missing: Vec<&str> = APT_PACKAGES
        .iter()
        .filter(|(_, probe)| !probe_ok(probe))
        .map(|(pkg, _)| *pkg)
        .collect();
    apt_install(&missing)?;
    python_peers()?;
    npm_peers()?;
    println!("setup: everything is in place");
    Ok(())
}

fn probe_ok(probe: &[&str]) -> bool {
    let (prog, args) = probe.split_first().expect("probe has a program");
    have(prog) && run_quiet(Command::new(prog).args(args)).is_ok()
}

/// Adds the Cortex-M targets ([`CROSS_TARGETS`]) to the active toolchain if they are
/// missing, and the linker the embedded boards link with ([`flip_link`]).
pub fn rust_target() -> Result {
    flip_link()?;
    let installed =
        output(Command::new("rustup").args(["target", "list", "--installed"])).unwrap_or_default();
    for target in CROSS_TARGETS {
        if !installed.lines().any(|l| l.trim() == target) {
            run(Command::new("rustup").args(["target", "add", target]))?;
        }
    }
    Ok(())
}

/// Installs `flip-link` from crates.io if it is missing: `.cargo/config.toml` names it as the
/// Cortex-M linker, which puts the stack below the statics so that an overflow faults at the
/// start of RAM instead of overwriting them.
pub fn flip_link() -> Result {
    if have("flip-link") {
        return Ok(());
    }
    run(Command::new("cargo").args(["install", "--locked", "flip-link"]))
}

/// True if the nightly toolchain is there, installing it (minimal profile) if needed.
pub fn nightly() -> bool {
    let has = || {
        output(Command::new("rustup").args(["toolchain", "list"]))
            .is_some_and(|l| l.lines().any(|t| t.starts_with("nightly")))
    };
    if has() {
        return true;
    }
    let r =
        run(Command::new("rustup").args(["toolchain", "install", NIGHTLY, "--profile", "minimal"]));
    if let Err(e) = r {
        println!("warning: {e}");
    }
    has()
}

/// Installs `cargo-fuzz` from crates.io if `cargo fuzz` is not available.
pub fn cargo_fuzz() -> Result {
    if run_quiet(Command::new("cargo").args(["fuzz", "--version"])).is_ok() {
        return Ok(());
    }
    run(Command::new("cargo").args(["install", "--locked", "cargo-fuzz"]))
}

/// Installs Debian `packages` (running `apt-get update` once first); nothing if empty.
pub fn apt_install(packages: &[&str]) -> Result {
    if packages.is_empty() {
        return Ok(());
    }
    if !have("apt-get") {
        return err(format!(
            "missing {packages:?} and there is no apt-get here: install them by hand"
        ));
    }
    let sudo = !util::is_root();
    let apt = |args: &[&str]| {
        let mut c = if sudo {
            let mut c = Command::new("sudo");
            c.arg("-n").arg("apt-get");
            c
        } else {
            Command::new("apt-get")
        };
        c.args(args)
            .env("DEBIAN_FRONTEND", "noninteractive")
            .stdin(std::process::Stdio::null());
        c
    };
    println!("setup: installing Debian packages {packages:?}");
    if have("debconf-set-selections") {
        preseed()?;
    }
    run(&mut apt(&["update", "-q"]))?;
    let mut install = apt(&["install", "-y", "-q"]);
    install.args(packages);
    run(&mut install)
}

/// Answers wireshark-common's question (capture for non-root users) with "no".
fn preseed() -> Result {
    use std::io::Write;
    let mut cmd = if util::is_root() {
        Command::new("debconf-set-selections")
    } else {
        let mut c = Command::new("sudo");
        c.args(["-n", "debconf-set-selections"]);
        c
    };
    let mut child = cmd.stdin(std::process::Stdio::piped()).spawn()?;
    if let Some(stdin) = child.stdin.as_mut() {
        stdin.write_all(b"wireshark-common wireshark-common/install-setuid boolean false\n")?;
    }
    let status = child.wait()?;
    if !status.success() {
        return err("debconf-set-selections failed");
    }
    Ok(())
}

/// Creates the venv and installs [`PYTHON_PEERS`] unless a stamp says they already are.
pub fn python_peers() -> Result {
    let dir = venv_dir();
    let stamp = dir.join(".xtask-installed");
    let wanted = PYTHON_PEERS.join("\n");
    if venv_python().exists() && fs::read_to_string(&stamp).is_ok_and(|s| s == wanted) {
        return Ok(());
    }
    if !venv_python().exists() {
        if !have("python3") {
            apt_install(&["python3", "python3-venv"])?;
        }
        run(Command::new("python3").arg("-m").arg("venv").arg(&dir))?;
    }
    let mut pip = Command::new(venv_python());
    pip.args([
        "-m",
        "pip",
        "install",
        "-q",
        "--disable-pip-version-check",
        "--no-input",
    ])
    .args(PYTHON_PEERS);
    run(&mut pip)?;
    fs::write(&stamp, wanted)?;
    Ok(())
}

/// Installs [`NPM_PEERS`] unless a stamp says they already are; only warns if npm is missing.
pub fn npm_peers() -> Result {
    let dir = npm_dir();
    let stamp = dir.join(".xtask-installed");
    let wanted = NPM_PEERS.join("\n");
    if fs::read_to_string(&stamp).is_ok_and(|s| s == wanted) {
        return Ok(());
    }
    if !have("npm") {
        loud("npm is not installed: the npm peers (st-ethernet-ip) are NOT installed");
        return Ok(());
    }
    fs::create_dir_all(&dir)?;
    let mut npm = Command::new("npm");
    npm.arg("install")
        .arg("--prefix")
        .arg(&dir)
        .args(["--no-audit", "--no-fund", "--loglevel=error"])
        .args(NPM_PEERS)
        .stdin(std::process::Stdio::null());
    run(&mut npm)?;
    fs::write(&stamp, wanted)?;
    Ok(())
}
