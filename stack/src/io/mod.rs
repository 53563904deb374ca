//! Connections: the fixed connection table shared by Class 1 implicit I/O and Class 3
//! connected explicit messaging, Forward_Open validation, production and consumption.

pub(crate) mod connection;
pub(crate) mod consume;
pub(crate) mod explicit;
pub(crate) mod open;
pub(crate) mod produce;
mod schedule;
pub(crate) mod table;
mod timing;

pub use connection::{Connection, Consumer, Producer, Transport};
pub use consume::{Accepted, Discard};
pub use produce::IoDue;
pub use table::ConnectionTable;
