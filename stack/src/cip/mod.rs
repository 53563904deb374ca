//! The CIP vocabulary every layer above the codecs speaks: general and extended status
//! codes, class IDs and service codes, object and attribute definitions, requests (service,
//! path, data) and the context a request arrives in. No object lives here: the standard
//! objects are in [`crate::objects`].

pub mod class_id;
pub mod connection_status;
pub mod context;
pub(crate) mod encoding;
pub mod object;
pub mod request;
pub mod service;
pub mod status;

pub use request::{Path, Request};
pub use status::{CipError, CipResult, General};
