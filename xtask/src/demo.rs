//! `cargo xtask demo`: the host board in a private network namespace, and a scanner reading
//! its identity and live input data.
//!
//! Layout: namespace `enip-demo` holds TAP `enipdemo0` with 198.18.0.1/24 (the scanner's
//! side); `enip-host`, started inside the namespace, opens that TAP as its NIC and is
//! 198.18.0.2/24. Nothing leaves the namespace. Everything is torn down on success, failure
//! and Ctrl-C.

use std::fs;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::thread::sleep;
use std::time::{Duration, Instant};

use crate::setup;
use crate::util::{self, err, interrupted, run, run_quiet, Result};

/// The namespace the demo creates (and deletes).
const NETNS: &str = "enip-demo";
/// The TAP device inside it.
const TAP: &str = "enipdemo0";
/// The namespace side of the link.
const SCANNER_CIDR: &str = "198.18.0.1/24";
/// The adapter's address.
const ADAPTER_IP: &str = "198.18.0.2";
/// The device profile the host board runs.
const PROFILE: &str = "generic";
/// The longest the scanner may take before the demo gives up.
const SCANNER_TIMEOUT: Duration = Duration::from_secs(60);

/// The scanner: pycomm3 explicit messaging (unconnected) against the adapter.
const SCANNER: &str = r#"
import socket, struct, sys, time
from pycomm3 import CIPDriver, Services

ip = sys.argv[1]
deadline = time.monotonic() + 15
while True:  # bounded: wait at most 15 s for the adapter to listen
    try:
        socket.create_connection((ip, 44818), timeout=0.5).close()
        break
    except OSError:
        if time.monotonic() > deadline:
            sys.exit(f"adapter at {ip}:44818 did not come up")
        time.sleep(0.25)

def get(d, cls, inst, attr):
    # Attribute ids as bytes: pycomm3 drops an integer attribute 0 otherwise.
    r = d.generic_message(service=Services.get_attribute_single, class_code=cls,
                          instance=inst, attribute=bytes([attr]), connected=False,
                          unconnected_send=False, route_path=False, name=f"{cls}/{inst}/{attr}")
    if r.error:
        sys.exit(f"Get_Attribute_Single {cls:#x}/{inst}/{attr} failed: {r.error}")
    return r.value

with CIPDriver(ip) as d:
    print(f"scanner: session open with {ip}")
    u16 = lambda b: struct.unpack("<H", b[:2])[0]
    rows = [
        ("Vendor ID", lambda b: f"{u16(b)}"),
        ("Device type", lambda b: f"{u16(b):#06x}"),
        ("Product code", lambda b: f"{u16(b)}"),
        ("Revision", lambda b: f"{b[0]}.{b[1]:03d}"),
        ("Status", lambda b: f"{u16(b):#06x}"),
        ("Serial number", lambda b: f"{struct.unpack('<I', b[:4])[0]:#010x}"),
        ("Product name", lambda b: b[1:1 + b[0]].decode("ascii", "replace")),
    ]
    print("Identity (class 0x01, instance 1):")
    for attr, (name, fmt) in enumerate(rows, start=1):
        print(f"  {attr}  {name:<14} {fmt(get(d, 0x01, 1, attr))}")
    print("Input assembly 100 (explicit Get_Attribute_Single of attribute 3, once a second):")
    for i in range(5):
        data = get(d, 0x04, 100, 3)
        print(f"  t={i}s  {len(data):3d} bytes  {data.hex(' ')}")
        time.sleep(1)
    # CLASS 1 VIEW: a Forward_Open exclusive-owner connection and the live T->O stream
    # (RPI, sequence counts, data) go here once the stack has Class 1 I/O.
print("scanner: done")
"#;

/// Runs the demo; the namespace and every child are gone when it returns.
pub fn run_demo() -> Result {
    if !util::is_root() {
        return err("demo: network namespaces need root; run it as root (or with sudo)");
    }
    util::catch_interrupts();
    if !util::have("ip") {
        setup::apt_install(&["iproute2"])?;
    }
    setup::python_peers()?;
    run(util::cargo().args(["build", "-p", "enip-host"]))?;
    let host_bin = util::target_dir().join("debug/enip-host");
    let log_dir = util::target_dir().join("demo");
    fs::create_dir_all(&log_dir)?;
    let log = log_dir.join("enip-host.log");

    let mut demo = Demo { host: None };
    let result = demo.run(&host_bin, &log);
    drop(demo); // tears down, as it also would on a panic
    if result.is_err() {
        print_log(&log);
    }
    result
}

/// What the demo started; dropping it removes it all.
struct Demo {
    host: Option<Child>,
}

impl Demo {
    fn run(&mut self, host_bin: &Path, log: &Path) -> Result {
        // A namespace left by an earlier run that was killed hard goes first.
        delete_netns();
        run(Command::new("ip").args(["netns", "add", NETNS]))?;
        in_netns(&["ip", "link", "set", "lo", "up"])?;
        in_netns(&["ip", "tuntap", "add", "dev", TAP, "mode", "tap"])?;
        in_netns(&["ip", "addr", "add", SCANNER_CIDR, "dev", TAP])?;
        in_netns(&["ip", "link", "set", TAP, "up"])?;

        let file = fs::File::create(log)?;
        let mut host = Command::new("ip");
        host.args(["netns", "exec", NETNS])
            .arg(host_bin)
            .args(["--tap", TAP, "--ip", &format!("{ADAPTER_IP}/24")])
            .args(["--profile", PROFILE])
            .stdin(Stdio::null())
            .stdout(file.try_clone()?)
            .stderr(file);
        println!("$ {}  (log: {})", util::show(&host), log.display());
        self.host = Some(host.spawn()?);

        let mut scanner = Command::new("ip");
        scanner
            .args(["netns", "exec", NETNS])
            .arg(setup::venv_python())
            .args(["-c", SCANNER, ADAPTER_IP])
            .stdin(Stdio::null());
        println!(
            "$ ip netns exec {NETNS} {} -c <scanner> {ADAPTER_IP}",
            setup::venv_python().display()
        );
        let mut scanner = scanner.spawn()?;
        let result = self.supervise(&mut scanner);
        if scanner.try_wait().ok().flatten().is_none() {
            let _ = scanner.kill();
            let _ = scanner.wait();
        }
        result
    }

    /// Waits for the scanner, bounded in time, while watching the host board stays up.
    fn supervise(&mut self, scanner: &mut Child) -> Result {
        let start = Instant::now();
        loop {
            if let Some(status) = scanner.try_wait()? {
                return if status.success() {
                    Ok(())
                } else {
                    err(format!("scanner failed ({status})"))
                };
            }
            if let Some(host) = self.host.as_mut() {
                if let Some(status) = host.try_wait()? {
                    return err(format!("enip-host exited early ({status})"));
                }
            }
            if interrupted() {
                return err("interrupted");
            }
            if start.elapsed() > SCANNER_TIMEOUT {
                return err(format!("scanner still running after {SCANNER_TIMEOUT:?}"));
            }
            sleep(Duration::from_millis(100));
        }
    }

    /// Stops the host board (SIGTERM, then SIGKILL after 3 s) and deletes the namespace.
    fn teardown(&mut self) {
        if let Some(mut host) = self.host.take() {
            if host.try_wait().ok().flatten().is_none() {
                let _ = run_quiet(Command::new("kill").args(["-TERM", &host.id().to_string()]));
                let start = Instant::now();
                while host.try_wait().ok().flatten().is_none() && start.elapsed().as_secs() < 3 {
                    sleep(Duration::from_millis(50));
                }
                let _ = host.kill();
            }
            let _ = host.wait();
        }
        delete_netns();
        println!("demo: torn down (namespace {NETNS} deleted, host board stopped)");
    }
}

impl Drop for Demo {
    fn drop(&mut self) {
        self.teardown();
    }
}

fn in_netns(args: &[&str]) -> Result {
    run(Command::new("ip").args(["netns", "exec", NETNS]).args(args))
}

/// Deletes the demo namespace and its TAP if they exist.
fn delete_netns() {
    let exists = util::output(Command::new("ip").args(["netns", "list"])).is_some_and(|l| {
        l.lines()
            .any(|n| n.split_whitespace().next() == Some(NETNS))
    });
    if exists {
        let _ =
            run_quiet(Command::new("ip").args(["netns", "exec", NETNS, "ip", "link", "del", TAP]));
        let _ = run_quiet(Command::new("ip").args(["netns", "del", NETNS]));
    }
}

fn print_log(log: &Path) {
    let text = fs::read_to_string(log).unwrap_or_default();
    let lines: Vec<&str> = text.lines().collect();
    println!("--- last lines of {} ---", log.display());
    for l in lines.iter().skip(lines.len().saturating_sub(30)) {
        println!("  | {l}");
    }
}
