//! A scanner (originator) of our own, usable as a library and through the `scanner` CLI:
//! explicit requests, N connections at a given RPI, I/O exchange with every received packet's
//! arrival time recorded, and interval statistics. Frames come from `enip_stack::originator`.

pub mod exchange;
pub mod session;
pub mod stats;

pub use exchange::{exchange, open_generic, Opened, Record};
pub use session::{Response, Session};
pub use stats::{ConnectionStats, Summary};
