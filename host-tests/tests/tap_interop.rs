//! TAP interop suite: the `enip-host` board on a TAP device inside a network namespace each
//! test creates, exercised by peers nobody here wrote (pycomm3, cpppo), by raw UDP/TCP
//! encapsulation clients, and by a battery of hostile inputs; every test captures with
//! tshark and checks the capture dissects cleanly.
//!
//! Needs root (namespaces, TAP), `ip`, `tshark` and a Python with pycomm3 and cpppo:
//!
//! ```text
//! ENIP_HOST_BIN=target/debug/enip-host ENIP_PEER_PYTHON=/path/to/venv/bin/python \
//!   cargo test -p host-tests --test tap_interop -- --ignored --test-threads=1
//! ```
//!
//! `ENIP_HOST_BIN` defaults to the workspace's `target/debug/enip-host`, `ENIP_PEER_PYTHON`
//! to `python3`. Captures are kept in `target/tmp/tap_interop/<test>.pcapng`.
//!
//! Capture policy: tests with well-behaved peers require every frame of the capture to be
//! free of malformed packets and of expert info at warning level or above. The hostile tests
//! send malformed frames on purpose, so there only the adapter's own frames
//! (`ip.src == 198.18.0.2`) are checked, and only their UDP and encapsulation layers: TCP
//! expert warnings on the adapter's side (resets of refused or abandoned connections, zero
//! windows) are the intended reaction to the abuse, not a dissection problem.

#[path = "tap_interop/common.rs"]
mod common;
#[path = "tap_interop/concurrency.rs"]
mod concurrency;
#[path = "tap_interop/explicit.rs"]
mod explicit;
#[path = "tap_interop/hostile_cip.rs"]
mod hostile_cip;
#[path = "tap_interop/hostile_framing.rs"]
mod hostile_framing;
#[path = "tap_interop/udp.rs"]
mod udp;
