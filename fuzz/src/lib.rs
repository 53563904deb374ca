//! Support code shared by the fuzz targets and the seed generator: a small test device, the
//! byte-script format the adapter targets read, the invariants they check, and builders for
//! valid frames (the seed corpus).
#![deny(missing_docs)]

pub mod device;
pub mod device_lists;
pub mod frames;
pub mod io_script;
pub mod link_seeds;
pub mod profile;
pub mod script;
pub mod store;
pub mod tcp_script;

pub use device::TestDevice;
