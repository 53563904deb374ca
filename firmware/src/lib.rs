//! Placeholder: the embassy-net runtime and device profiles land here.
#![no_std]
