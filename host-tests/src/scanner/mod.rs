//! A scanner (originator) of our own, usable as a library and through the `scanner` CLI:
//! explicit requests, N connections at a given RPI, I/O exchange with every received packet's
//! arrival time recorded, and interval statistics. Frames come from `enip_stack::originator`.

pub mod exchange;
pub mod fleet;
pub mod session;
pub mod stats;

pub use exchange::{
    exchange, exchange_until, generic_forward_open, open_generic, open_generic_triggered, Opened,
    Record, HEARTBEAT_O_T, INPUT_ONLY_PATH, OWNER_O_T, OWNER_PATH,
};
pub use session::{Response, Session};
pub use stats::{ConnectionStats, Summary};
