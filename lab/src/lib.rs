//! The test lab shared by `host-tests` and `xtask`: a private network namespace with a TAP
//! link (198.18.0.0/24) where nothing reaches the machine's real networks, child processes
//! with bounded waits and logged output, the boards' launchers (the host board `enip-host`,
//! a program built on `enip_host::run`, the emulated board in QEMU), tshark captures with
//! their checks, what a running board costs (`/proc`), and where the independent peers
//! (Python venv, npm prefix, scripts) live.
//!
//! Host-only: it runs `ip`, `tshark`, `qemu-system-arm` and the peers, and needs root for
//! the namespaces.

#![forbid(unsafe_code)]

pub mod capture;
pub mod diagnostics;
pub mod netns;
pub mod paths;
pub mod peers;
pub mod process;
pub mod rig;
pub mod scanner;
pub mod usage;
