//! Every integration suite again, with the adapter built at 16 sessions, 64 connections,
//! 1 524-byte frames and 16 delayed ListIdentity replies (`common::LARGE` is true in this
//! crate): the same tests, not copies, so every explicit, Class 1 and hostile-input case
//! holds at a gateway's size as at the MCU default.
// Each suite declares `mod common;`, as it must when it is a crate of its own.
#![allow(clippy::duplicate_mod)]

#[path = "admission.rs"]
mod admission;
#[path = "capacity.rs"]
mod capacity;
#[path = "device_hooks.rs"]
mod device_hooks;
#[path = "electronic_key.rs"]
mod electronic_key;
#[path = "ethernet_link.rs"]
mod ethernet_link;
#[path = "explicit.rs"]
mod explicit;
#[path = "forward_open.rs"]
mod forward_open;
#[path = "lldp_objects.rs"]
mod lldp_objects;
#[path = "object_layouts.rs"]
mod object_layouts;
#[path = "qos_object.rs"]
mod qos_object;
#[path = "status_audit.rs"]
mod status_audit;
#[path = "tcpip_settings.rs"]
mod tcpip_settings;
#[path = "vendor_class.rs"]
mod vendor_class;
#[path = "virtual_time.rs"]
mod virtual_time;
