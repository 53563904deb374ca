//! Shared helpers for the integration tests: the TAP rig (namespace, TAP, board, capture),
//! independent peers, and a raw EtherNet/IP client for hostile inputs.

pub mod capture;
pub mod enip;
pub mod faults;
pub mod netns;
pub mod peers;
pub mod process;
pub mod rig;
pub mod scanner;
