//! `enip-host-runtime`: what runs async code on a Linux host, in one thread and without
//! locks: the embassy-time driver, an executor ([`run`]) and a
//! [`block_on`], both waiting in one `ppoll` on the file descriptors their futures watch
//! ([`Readable`]) with the earliest alarm as its timeout.
//!
//! Every program and test on the host that uses embassy-time links this crate (a
//! dependency that is never named is not linked: a test that uses only embassy-time names it
//! with `use enip_host_runtime as _;`), and nothing enables embassy-time's `std` driver: a
//! program has exactly one time driver.
//!
//! An alarm belongs to the thread that schedules it, that is the thread polling the timer,
//! and fires only while that thread runs [`run`] or [`block_on`]: each thread has its own
//! alarms and watched descriptors, so tests may run loops on parallel threads. A wake from
//! another thread ends the loop's wait through an eventfd; a wake on the loop's own thread
//! costs one atomic store.

mod block_on;
mod clock;
mod executor;
mod park;
mod ppoll;
mod reactor;
mod time_driver;
mod wakeup;

pub use block_on::block_on;
pub use clock::now_micros;
pub use executor::run;
pub use ppoll::ppoll;
pub use reactor::Readable;
