//! TAP interop suite: the `enip-host` board on a TAP device inside a network namespace each
//! test creates, exercised by peers nobody here wrote (pycomm3, cpppo), by raw UDP/TCP
//! encapsulation clients, by Class 1 originators (the PyPI `ethernetip` package, npm
//! `st-ethernet-ip`, our scanner for listen-only on multicast), and by a battery of hostile
//! inputs; every test captures with
//! tshark and checks the capture dissects cleanly.
//!
//! Needs root (namespaces, TAP), `ip`, `tshark` and a Python with pycomm3 and cpppo:
//!
//! ```text
//! cargo build -p enip-host
//! ENIP_HOST_BIN=target/debug/enip-host ENIP_PEER_PYTHON=/path/to/venv/bin/python \
//!   cargo test -p host-tests --test tap_interop -- --ignored --test-threads=1
//! ```
//!
//! `ENIP_HOST_BIN` (relative to the workspace root unless absolute) defaults to
//! `target/debug/enip-host`, `ENIP_PEER_PYTHON` to `python3`. Each test has its own
//! namespace, board and capture, kept in `target/tmp/tap_interop/<test>.pcapng`.
//!
//! Capture policy, checked with `tshark -r` and the display filter
//! `_ws.malformed || _ws.expert.severity >= 0x00600000` (warning or worse, tshark 4.0):
//! - tests with well-behaved peers: no frame at all may match, in either direction;
//! - hostile tests send malformed frames on purpose, so only the adapter's own frames that
//!   carry encapsulation or UDP (`ip.src == 198.18.0.2 && (enip || udp)`) are checked. Bare
//!   TCP control segments (the resets refusing a 4th client) are the intended reaction to the
//!   abuse. One expert message is tolerated there: Wireshark shows a CIP response together
//!   with its request's path, so a reply to a request with a reserved logical segment format
//!   is flagged "Unsupported Logical Segment Format" although the reply bytes are fine.

#[path = "tap_interop/ametek_pls.rs"]
mod ametek_pls;
#[path = "tap_interop/class1.rs"]
mod class1;
#[path = "tap_interop/class3.rs"]
mod class3;
#[path = "tap_interop/common.rs"]
mod common;
#[path = "tap_interop/concurrency.rs"]
mod concurrency;
#[path = "tap_interop/example_io_block.rs"]
mod example_io_block;
#[path = "tap_interop/explicit.rs"]
mod explicit;
#[path = "tap_interop/fault_io.rs"]
mod fault_io;
#[path = "tap_interop/faults.rs"]
mod faults;
#[path = "tap_interop/faults_link_flap.rs"]
mod faults_link_flap;
#[path = "tap_interop/faults_reset.rs"]
mod faults_reset;
#[path = "tap_interop/faults_soak.rs"]
mod faults_soak;
#[path = "tap_interop/hostile_cip.rs"]
mod hostile_cip;
#[path = "tap_interop/hostile_framing.rs"]
mod hostile_framing;
#[path = "tap_interop/kollmorgen_akd.rs"]
mod kollmorgen_akd;
#[path = "tap_interop/parker_ipa.rs"]
mod parker_ipa;
#[path = "tap_interop/position_servo.rs"]
mod position_servo;
#[path = "tap_interop/position_servo_connections.rs"]
mod position_servo_connections;
#[path = "tap_interop/position_servo_qemu.rs"]
mod position_servo_qemu;
#[path = "tap_interop/tcpip_nv.rs"]
mod tcpip_nv;
#[path = "tap_interop/udp.rs"]
mod udp;
