//! Connections: the fixed connection table shared by Class 1 implicit I/O and Class 3
//! connected explicit messaging, Forward_Open validation, production and consumption.

pub(crate) mod connection;
pub(crate) mod consume;
pub(crate) mod explicit;
pub(crate) mod open;
// `produce_due` is left unused by `Adapter::poll_io`, now built on `io_due` and `write_io`;
// it goes with the rewrite of this module's files under way, and this line with it.
#[expect(
    dead_code,
    reason = "produce::produce_due, superseded by Adapter::poll_io"
)]
pub(crate) mod produce;
mod schedule;
pub(crate) mod table;

pub use connection::{Connection, Consumer, Producer, Transport};
pub use consume::{Accepted, Discard};
pub use produce::IoDue;
pub use table::ConnectionTable;
