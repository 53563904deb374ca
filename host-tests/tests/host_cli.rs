//! `enip-host` start-up errors (no root needed): a missing interface or one that is not a
//! TAP ends the program at once with status 1 and a message naming the interface, instead
//! of a new TAP being created or the program running unreachable; so does `--bind` to an
//! address no interface holds (or a fleet device's, named), and `--bind` with TAP options or
//! a bad device list is a usage error (status 2).
//!
//! ```text
//! cargo build -p enip-host
//! cargo test -p host-tests --test host_cli
//! ```
//!
//! The binary is `ENIP_HOST_BIN` (relative to the workspace root unless absolute), else the
//! `enip-host` built next to this test (the same target directory and profile). Run as root,
//! each child gets a network namespace of its own, so even a faulty build cannot add an
//! interface to the machine's namespace.

use std::io;
use std::os::unix::process::CommandExt;
use std::path::PathBuf;
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use host_tests::process::run_bounded;

/// How long a start-up error may take to end the program.
const EXIT_WITHIN: Duration = Duration::from_secs(1);

/// The `enip-host` binary under test.
fn host_bin() -> PathBuf {
    if let Some(bin) = std::env::var_os("ENIP_HOST_BIN") {
        return PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("..")
            .join(bin);
    }
    // This test runs as <target>/<profile>/deps/host_cli-<hash>.
    let exe = std::env::current_exe().expect("path of the test executable");
    let profile_dir = exe
        .parent()
        .and_then(|deps| deps.parent())
        .expect("test executable under <target>/<profile>/deps");
    profile_dir.join("enip-host")
}

/// Runs `enip-host args`, killing it if it is still running after [`EXIT_WITHIN`].
fn run_host(args: &[&str]) -> Output {
    let bin = host_bin();
    assert!(
        bin.exists(),
        "{} missing: build it with `cargo build -p enip-host` or set ENIP_HOST_BIN",
        bin.display()
    );
    let mut cmd = Command::new(&bin);
    cmd.args(args);
    // SAFETY: the closure runs in the forked child before exec and only makes the
    // async-signal-safe system calls geteuid(2) and unshare(2).
    unsafe {
        cmd.pre_exec(|| {
            // Unprivileged, the child cannot create interfaces, so only root must be isolated.
            if libc::unshare(libc::CLONE_NEWNET) != 0 && libc::geteuid() == 0 {
                return Err(io::Error::last_os_error());
            }
            Ok(())
        });
    }
    let start = Instant::now();
    let out = run_bounded(cmd, None, EXIT_WITHIN)
        .unwrap_or_else(|e| panic!("enip-host {args:?} did not end within {EXIT_WITHIN:?}: {e}"));
    println!(
        "enip-host {args:?}: {} after {:?}\n{}",
        out.status,
        start.elapsed(),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

#[test]
fn a_missing_interface_is_an_error_not_a_new_tap() {
    let out = run_host(&["--tap", "nosuch0", "--ip", "198.18.0.2/24"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "stderr: {stderr}");
    assert!(stderr.contains("nosuch0"), "stderr: {stderr}");
    assert!(
        stderr.contains("ip tuntap add dev nosuch0 mode tap"),
        "no hint how to create the TAP; stderr: {stderr}"
    );
}

#[test]
fn an_interface_that_is_not_a_tap_is_an_error() {
    let out = run_host(&["--tap", "lo", "--ip", "198.18.0.2/24"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "stderr: {stderr}");
    assert!(stderr.contains("\"lo\""), "stderr: {stderr}");
}

#[test]
fn bind_to_an_address_no_interface_has_is_an_error() {
    // In the child's own namespace only `lo` exists, so no interface holds this address.
    let out = run_host(&["--bind", "198.18.0.2"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "stderr: {stderr}");
    assert!(
        stderr.contains("no interface has the address 198.18.0.2"),
        "stderr: {stderr}"
    );
}

#[test]
fn bind_with_tap_options_is_a_usage_error() {
    let out = run_host(&["--bind", "198.18.0.2", "--tap", "enip0"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {stderr}");
    assert!(stderr.contains("--bind"), "stderr: {stderr}");
}

#[test]
fn a_fleet_device_without_its_address_is_named_in_the_error() {
    // In the child's own namespace no interface holds either address: the first device
    // opened fails, named.
    let list = std::env::temp_dir().join(format!("enip-fleet-cli-{}.toml", std::process::id()));
    let text =
        "[[device]]\nname = \"press-7\"\naddress = \"198.18.0.7\"\nprofile = \"parker-ipa\"\n\
                [[device]]\nname = \"press-8\"\naddress = \"198.18.0.8\"\n";
    std::fs::write(&list, text).expect("write the device list");
    let out = run_host(&["--devices", list.to_str().expect("a UTF-8 path")]);
    let _ = std::fs::remove_file(&list);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "stderr: {stderr}");
    assert!(
        stderr.contains("press-7: no interface has the address 198.18.0.7"),
        "stderr: {stderr}"
    );
}

#[test]
fn a_bad_device_list_is_a_usage_error_with_its_line() {
    let list = std::env::temp_dir().join(format!("enip-fleet-bad-{}.toml", std::process::id()));
    std::fs::write(
        &list,
        "[[device]]\naddress = \"198.18.0.7\"\nprofile = \"nope\"\n",
    )
    .expect("write the device list");
    let out = run_host(&["--devices", list.to_str().expect("a UTF-8 path")]);
    let _ = std::fs::remove_file(&list);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {stderr}");
    assert!(
        stderr.contains("unknown profile \"nope\""),
        "stderr: {stderr}"
    );
    let out = run_host(&["--devices", "/nonexistent/plant.toml"]);
    assert_eq!(out.status.code(), Some(2));
}
