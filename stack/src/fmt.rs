//! Optional logging, one copy for the stack and the runtime on it: `debug!`, `info!`, `warn!`
//! and `error!` forward to `defmt` or `log` when one of those features is on, and compile to
//! nothing (no formatting cost) when both are off. Both on is a compile error.
//!
//! The macros are exported, hidden from the documentation, for `enip-firmware`
//! (`#[macro_use(...)] extern crate enip_stack;`). A `#[cfg(feature = ...)]` in a macro is
//! decided in the crate that expands it, so a crate using them has `log` and `defmt` features
//! of its own that turn on the stack's (which holds the `compile_error!`).

#[cfg(all(feature = "defmt", feature = "log"))]
compile_error!(
    "enip-stack: features `defmt` and `log` are both enabled; choose one of them (or neither, for no logging)"
);

/// Logs at `$level` through `log` or `defmt`, whichever feature the expanding crate has on;
/// with neither, only borrows the arguments (nothing is formatted).
#[doc(hidden)]
#[macro_export]
macro_rules! __enip_log {
    ($level:ident, $s:literal $(, $x:expr)* $(,)?) => {{
        #[cfg(feature = "log")]
        ::log::$level!($s $(, $x)*);
        #[cfg(feature = "defmt")]
        ::defmt::$level!($s $(, $x)*);
        #[cfg(not(any(feature = "log", feature = "defmt")))]
        { let _ = ($( & $x ),*); }
    }};
}

/// Logs at debug level (see the `fmt` module).
#[doc(hidden)]
#[macro_export]
macro_rules! debug {
    ($($t:tt)*) => { $crate::__enip_log!(debug, $($t)*) };
}

/// Logs at info level (see the `fmt` module).
#[doc(hidden)]
#[macro_export]
macro_rules! info {
    ($($t:tt)*) => { $crate::__enip_log!(info, $($t)*) };
}

/// Logs at warn level (see the `fmt` module).
#[doc(hidden)]
#[macro_export]
macro_rules! warn {
    ($($t:tt)*) => { $crate::__enip_log!(warn, $($t)*) };
}

/// Logs at error level (see the `fmt` module).
#[doc(hidden)]
#[macro_export]
macro_rules! error {
    ($($t:tt)*) => { $crate::__enip_log!(error, $($t)*) };
}
