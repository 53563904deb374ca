//! EtherNet/IP over TLS on TCP 2221 (CIP Security, Confidentiality profile) for the
//! microcontroller boards, through mbedTLS 2.28 compiled by `build.rs` with the minimal
//! configuration in `c/enip_mbedtls_config.h`: TLS 1.2 server only, ECDHE-ECDSA with
//! AES-128/256 CBC-SHA256/384 and GCM, P-256, DER certificates, every allocation from one
//! static arena ([`arena_bytes`]), entropy from the board's RNG ([`setup`]).
//!
//! [`serve`] is the runtime's side: it accepts on 2221, runs the handshake and hands the
//! decrypted bytes to the adapter exactly as the plaintext socket on 44818 does, encrypting
//! the replies. The crate is chip-independent; the board gives it the RNG and the socket.
#![no_std]

mod ffi;
mod io;
mod serve;
mod session;

pub use ffi::Rng;
pub use serve::{serve, TlsBuffers, TLS_PORT};
pub use session::TlsSession;

/// Why TLS failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Error {
    /// An mbedTLS error code (negative).
    Tls(i32),
    /// The TCP connection ended or could not be written.
    Closed,
}

/// Installs the board's RNG and the device's certificate and private key (DER), with the
/// trusted CA (DER; empty: client certificates are not asked for). The suites offered are
/// ECDHE-ECDSA-AES128-CBC-SHA256 and AES256-CBC-SHA384 (the factory default) until
/// [`offer`] says otherwise. Once only.
pub fn setup(rng: Rng, cert: &[u8], key: &[u8], ca: &[u8]) -> Result<(), Error> {
    critical_section::with(|cs| ffi::RNG.borrow(cs).set(Some(rng)));
    // SAFETY: the slices are valid for their lengths; mbedTLS copies what it keeps.
    let ret = unsafe {
        ffi::enip_tls_setup(
            cert.as_ptr(),
            cert.len(),
            key.as_ptr(),
            key.len(),
            ca.as_ptr(),
            ca.len(),
        )
    };
    if ret == 0 {
        Ok(())
    } else {
        Err(Error::Tls(ret))
    }
}

/// Offers, from the next handshake on, those of `suites` (IANA numbers, EtherNet/IP Security
/// attribute 4) that are built in, in their order; returns how many (0: handshakes fail).
pub fn offer(suites: &[u16]) -> usize {
    // SAFETY: the slice is valid for its length; the shim copies what it keeps.
    let n = unsafe { ffi::enip_tls_offer(suites.as_ptr(), suites.len()) };
    usize::try_from(n).unwrap_or(0)
}

/// Bytes of the static arena every mbedTLS allocation comes from.
pub fn arena_bytes() -> usize {
    // SAFETY: returns a constant.
    unsafe { ffi::enip_tls_arena_bytes() }
}

/// TLS sessions the shim holds at once.
pub fn slots() -> usize {
    // SAFETY: returns a constant.
    unsafe { ffi::enip_tls_slots() }
}
