//! What every TAP test shares: starting the rig, the capture check at the end, the expected
//! identity of the generic profile, and the "is the board still serving" probe.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use host_tests::capture;
use host_tests::enip::{mr_request, path, Client};
use host_tests::netns::Namespace;
use host_tests::rig::Rig;

/// Reply timeout for a single request.
pub const REPLY: Duration = Duration::from_secs(2);
/// Bound for a fresh client to register and get an Identity read answered.
pub const SERVING_BOUND: Duration = Duration::from_secs(1);

/// Identity of the generic profile.
pub const VENDOR: u16 = 1;
/// Device type (generic device, keyable).
pub const DEVICE_TYPE: u16 = 12;
/// Product code.
pub const PRODUCT_CODE: u16 = 65001;
/// Major and minor revision.
pub const REVISION: [u8; 2] = [
    enip_profiles::generic::identity::IDENTITY.revision.0,
    enip_profiles::generic::identity::IDENTITY.revision.1,
];
/// Identity status with no I/O connection (extended device status 3).
pub const STATUS: u16 = 0x0030;
/// Serial number.
pub const SERIAL: u32 = 0x5255_5354;
/// Product name.
pub const NAME: &str = "enip-rs generic";

/// Capture scope for hostile tests: the adapter's own UDP and encapsulation frames.
const ADAPTER_FRAMES: &str = "ip.src == 198.18.0.2 && (enip || udp)";
/// Expert warnings Wireshark puts in a reply about the request it answers (a CIP response
/// shows the request's path), so a hostile request is flagged again in the adapter's reply.
const REQUEST_ECHOES: &[&str] = &["Unsupported Logical Segment Format"];
/// Expert warnings of a correct TCP reacting to the peer's timing: a receiver reporting a
/// segment it got twice (RFC 2883), after the peer retransmitted it (which Wireshark marks
/// only as a note). On a loaded machine a client's tail-loss probe can resend its FIN before
/// the board's process ran; the kernel's TCP under `--bind` then answers with a D-SACK.
const PEER_TIMING: &[&str] = &["D-SACK Sequence"];

/// The board binary: `ENIP_HOST_BIN` (relative to the workspace root unless absolute),
/// else the workspace's debug build.
pub fn host_bin() -> PathBuf {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let bin = std::env::var_os("ENIP_HOST_BIN").unwrap_or("target/debug/enip-host".into());
    root.join(bin)
}

/// `file` in the suite's scratch directory, `target/tmp/tap_interop` (created).
pub fn scratch(file: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("tap_interop");
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    dir.join(file)
}

/// A non-volatile file for `enip-host --nv-file` in the scratch directory, none there yet.
pub fn fresh_nv_file(file: &str) -> PathBuf {
    let path = scratch(file);
    let _ = std::fs::remove_file(&path);
    path
}

/// Starts the rig for test `name`, capturing into `target/tmp/tap_interop/<name>.pcapng`.
pub fn start(name: &str) -> Rig {
    let bin = host_bin();
    assert!(
        bin.exists(),
        "board binary {} missing: build enip-host or set ENIP_HOST_BIN",
        bin.display()
    );
    let pcap = scratch(&format!("{name}.pcapng"));
    Rig::start(&bin, "generic", Some(&pcap)).unwrap_or_else(|e| panic!("rig for {name}: {e}"))
}

/// Stops the rig of a test with well-behaved peers and checks its capture: at least one
/// encapsulation frame, and every frame free of malformed packets and expert warnings but
/// [`PEER_TIMING`]'s.
pub fn finish(rig: Rig) {
    let _ = check_capture(rig, "", PEER_TIMING);
}

/// Stops the rig of a hostile test and checks the adapter's own UDP and encapsulation
/// frames the same way, tolerating only [`REQUEST_ECHOES`].
pub fn finish_hostile(rig: Rig) {
    let _ = check_capture(rig, ADAPTER_FRAMES, REQUEST_ECHOES);
}

/// Like [`finish`], and returns the capture for further counting.
pub fn finish_keeping_capture(rig: Rig) -> PathBuf {
    check_capture(rig, "", PEER_TIMING)
}

fn check_capture(rig: Rig, scope: &str, tolerated: &[&str]) -> PathBuf {
    let pcap = rig
        .finish()
        .unwrap_or_else(|e| panic!("{e}"))
        .expect("the rig captures");
    let enip = capture::count(&pcap, "enip").expect("read capture");
    assert!(enip > 0, "no EtherNet/IP frame in {}", pcap.display());
    let bad = capture::problems(&pcap, scope, tolerated).expect("read capture");
    assert!(
        bad.is_empty(),
        "{} has frames that do not dissect cleanly:\n{}",
        pcap.display(),
        bad.join("\n")
    );
    pcap
}

/// Asserts that a fresh client can register a session and read the Identity product name
/// within [`SERVING_BOUND`]; `after` names the case for the failure message.
pub fn assert_serving(ns: &Namespace, after: &str) {
    let start = Instant::now();
    let result = (|| {
        let mut c = Client::connect(ns, SERVING_BOUND)?;
        c.register(SERVING_BOUND)?;
        c.request(&mr_request(0x0E, &path(1, 1, Some(7)), &[]), SERVING_BOUND)
    })();
    let elapsed = start.elapsed();
    let reply = result.unwrap_or_else(|e| panic!("not serving after {after}: {e}"));
    assert_eq!(reply.general, 0, "identity read after {after}: {reply:?}");
    assert_eq!(&reply.data[1..], NAME.as_bytes(), "after {after}");
    assert!(elapsed <= SERVING_BOUND, "after {after}: took {elapsed:?}");
}

/// Parses `eds/<profile>.eds` with eds-pie; fails on any warning. Returns its summary
/// (protocol, assemblies and sizes, connections).
pub fn eds_check(profile: &str) -> serde_json::Value {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../eds/{profile}.eds"));
    eds_check_file(&path, profile)
}

/// eds-pie's view of the EDS file at `path` (`name` in messages), asserting it found no
/// problem.
pub fn eds_check_file(path: &std::path::Path, name: &str) -> serde_json::Value {
    let mut cmd = std::process::Command::new(host_tests::peers::python());
    cmd.arg(host_tests::peers::script("eds_check.py"));
    let input = serde_json::json!({"path": path}).to_string();
    let out =
        host_tests::process::run_bounded(cmd, Some(input.as_bytes()), Duration::from_secs(60))
            .expect("eds-pie runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let r: serde_json::Value = stdout
        .lines()
        .rev()
        .find_map(|l| serde_json::from_str(l).ok())
        .unwrap_or_else(|| panic!("no JSON from eds-pie: {stdout}"));
    assert_eq!(
        r["problems"],
        serde_json::json!([]),
        "{name}: eds-pie warnings: {r}"
    );
    r
}
