//! The example I/O block (`examples/io-block`, run by `examples/io-block-host` with one call
//! to `enip_host::run`) on the TAP: pycomm3 reads its identity and its vendor class, and a
//! Forward_Open with a configuration it refuses gets the extended status the device chose.

use std::path::PathBuf;
use std::time::Duration;

use enip_stack::wire::forward_open::{ForwardOpenRepr, NetworkParams, Triad};
use host_tests::peers;
use host_tests::rig::{Rig, BOARD_IP};
use host_tests::scanner::Session;
use serde_json::json;

use crate::common;

/// The example's binary: `ENIP_EXAMPLE_BIN` (relative to the workspace root unless
/// absolute), else the workspace's debug build.
fn example_bin() -> PathBuf {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let bin = std::env::var_os("ENIP_EXAMPLE_BIN").unwrap_or("target/debug/io-block-host".into());
    root.join(bin)
}

/// An exclusive owner of outputs 150 / inputs 100 with configuration `config` for 151.
fn forward_open<'a>(serial: u16, path: &'a [u8]) -> ForwardOpenRepr<'a> {
    ForwardOpenRepr {
        large: false,
        priority_tick: 0x0A,
        timeout_ticks: 0x0E,
        o_t_connection_id: 0,
        t_o_connection_id: 0x10B0_0000 + u32::from(serial),
        triad: Triad {
            connection_serial: serial,
            vendor_id: 0xBEEF,
            originator_serial: 0x1B10,
        },
        timeout_multiplier: 2,
        o_t_rpi: 10_000,
        o_t_params: NetworkParams::from_u16(0x4800 | (2 + 4 + 2)),
        t_o_rpi: 10_000,
        t_o_params: NetworkParams::from_u16(0x4800 | (2 + 2)),
        transport: 0x01,
        path,
    }
}

/// The connection path with configuration data `config` (4 bytes, 2 words).
fn path(config: [u8; 4]) -> Vec<u8> {
    let mut p = vec![0x20, 0x04, 0x24, 151, 0x2C, 150, 0x2C, 100, 0x80, 2];
    p.extend(config);
    p
}

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn example_io_block_on_the_tap() {
    let bin = example_bin();
    assert!(
        bin.exists(),
        "{} missing: cargo build -p io-block-host",
        bin.display()
    );
    let pcap = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("tap_interop")
        .join("example_io_block.pcapng");
    let rig = Rig::start_program(&bin, Some(&pcap)).unwrap_or_else(|e| panic!("rig: {e}"));
    let r = peers::run(
        rig.ns(),
        "io_block.py",
        &json!({"host": BOARD_IP.to_string()}),
        Duration::from_secs(60),
    )
    .unwrap_or_else(|e| panic!("{e}\nlog:\n{}", rig.board_log()));
    let ok = |k: &str, data: &str| {
        assert_eq!(
            (r[k]["status"].as_u64(), r[k]["data"].as_str()),
            (Some(0), Some(data)),
            "{k}: {r}"
        )
    };
    let name = "enip-rs 16-channel I/O block";
    ok(
        "product_name",
        &format!("{:02x}{}", name.len(), hex(name.as_bytes())),
    );
    ok("vendor_id", "ffff");
    ok("set_name", "");
    ok("name", &format!("05{}", hex(b"valve")));
    ok("set_debounce", "");
    ok(
        "channel_all",
        &format!("1400000000{}", format_args!("05{}", hex(b"valve"))),
    );
    ok("class_max_instance", "1000");
    ok("set_outputs", "");
    ok("clear_edges", "");
    ok("edges_3_cleared", "00000000");
    for (k, status) in [
        ("debounce_too_long", 0x09),
        ("edges_read_only", 0x0E),
        ("no_channel_17", 0x16),
    ] {
        assert_eq!(r[k]["status"].as_u64(), Some(status), "{k}: {r}");
    }
    // Channel 3's output looped back: input bit 3 set (bit 15 is the 1 Hz pulse), one edge.
    let inputs = u16::from_str_radix(r["inputs"]["data"].as_str().unwrap_or(""), 16)
        .unwrap_or(0)
        .swap_bytes();
    assert_eq!(inputs & 0x7FFF, 0x0008, "{r}");
    assert_eq!(r["edges_3"]["data"], "01000000", "{r}");

    // The configuration check: a filter of 200 ms (byte 0) is refused with 0x01/0x0110 and
    // the offending byte; a good configuration connects.
    let (refused, accepted) = rig
        .ns()
        .inside(|| -> std::io::Result<_> {
            let mut s = Session::connect(BOARD_IP, common::REPLY)?;
            let bad = path([200, 0, 0, 0]);
            let refused = s.forward_open(&forward_open(1, &bad))?.err();
            let good = path([10, 1, 0, 0]);
            let accepted = s.forward_open(&forward_open(2, &good))?;
            if let Ok(reply) = &accepted {
                s.forward_close(reply.triad)?;
            }
            Ok((refused, accepted.is_ok()))
        })
        .expect("namespace")
        .expect("session");
    let refused = refused.expect("the bad configuration is refused");
    assert_eq!(
        (refused.general, refused.additional),
        (0x01, vec![0x0110, 0])
    );
    assert!(accepted);
    let log = rig.board_log();
    assert!(
        log.contains(
            "refused: the device refused the configuration (general status 0x01, extended 0x0110, 0x0000)"
        ),
        "the refusal is logged with every additional status word: {log}"
    );
    common::finish(rig);
}

/// `io-block-host --eds` (`enip_host::run_device`): an EDS that eds-pie parses without a
/// warning, with the configuration assembly's fields and channel 1's attributes as
/// parameters.
#[test]
#[ignore = "needs the Python peers (eds-pie) and the example's binary"]
fn example_eds_is_clean() {
    let mut cmd = std::process::Command::new(example_bin());
    cmd.arg("--eds");
    let out = host_tests::process::run_bounded(cmd, None, Duration::from_secs(30))
        .expect("io-block-host --eds runs");
    assert!(out.status.success(), "{out:?}");
    let path = std::env::temp_dir().join(format!("io-block-{}.eds", std::process::id()));
    std::fs::write(&path, &out.stdout).expect("a temporary file");
    let r = common::eds_check_file(&path, "io-block-host --eds");
    let _ = std::fs::remove_file(&path);
    assert_eq!(r["assemblies"]["Assem151"], 4, "{r}");
    let eds = String::from_utf8_lossy(&out.stdout);
    assert!(eds.contains("8, Param2, 8, Param3, 16, Param4;"), "{eds}");
    assert!(eds.contains("\"20 70 24 01 30 01\""), "{eds}");
}

fn hex(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02x}")).collect()
}
