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

mod acd;
mod ametek_pls;
mod ametek_pls_inputs;
mod chaos;
mod chaos_faults;
mod chaos_io;
mod chaos_plan;
mod cip_security;
mod cip_security_qemu;
mod class1;
mod class3;
mod common;
mod concurrency;
mod electronic_key;
mod embedded_qemu;
mod ethernet_link;
mod example_io_block;
mod explicit;
mod fault_io;
mod faults;
mod faults_link_flap;
mod faults_reset;
mod faults_soak;
mod fleet;
mod floods;
mod floods_datagrams;
mod floods_load;
mod hostile_cip;
mod hostile_framing;
mod hostile_tcp;
mod kollmorgen_akd;
mod lldp;
mod parker_ipa;
mod pipelining;
mod position_servo;
mod position_servo_connections;
mod position_servo_qemu;
mod qos;
mod scan_nmap;
mod tcpip_nv;
mod udp;
