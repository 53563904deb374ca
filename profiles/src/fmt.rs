//! Optional logging: forwards to `defmt` or `log` when one of those features is on, and
//! compiles to nothing (no formatting cost) when both are off. Both on is a compile error.
#![allow(unused_macros)]

#[cfg(all(feature = "defmt", feature = "log"))]
compile_error!(
    "enip-profiles: features `defmt` and `log` are both enabled; choose one of them (or neither, for no logging)"
);

macro_rules! log_at {
    ($level:ident, $s:literal $(, $x:expr)* $(,)?) => {{
        #[cfg(feature = "log")]
        ::log::$level!($s $(, $x)*);
        #[cfg(feature = "defmt")]
        ::defmt::$level!($s $(, $x)*);
        #[cfg(not(any(feature = "log", feature = "defmt")))]
        { let _ = ($( & $x ),*); }
    }};
}

macro_rules! info {
    ($($t:tt)*) => { log_at!(info, $($t)*) };
}

macro_rules! warn {
    ($($t:tt)*) => { log_at!(warn, $($t)*) };
}
