//! Shared helpers for the integration tests: a raw EtherNet/IP client for hostile inputs,
//! the project's scanner, and the set-up of the cycle benchmarks. The TAP rig (namespace,
//! TAP, boards, capture, peers) is the lab crate's, re-exported here under the paths the tests
//! use.

pub mod cycle;
pub mod enip;
pub mod faults;
pub mod scanner;
pub mod stop_file;

pub use enip_lab::{capture, netns, paths, peers, process, rig, usage};
