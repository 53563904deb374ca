//! Connections: the fixed connection table shared by Class 1 implicit I/O and Class 3
//! connected explicit messaging, Forward_Open validation, production and consumption.

pub mod connection;
pub mod consume;
pub mod explicit;
pub mod open;
pub mod produce;
mod schedule;
pub mod status;
pub mod table;
mod timing;

pub use connection::{Connection, Consumer, Kind, Producer, Transport, Trigger};
pub use table::ConnectionTable;
