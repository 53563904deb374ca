//! The shim's calls (`c/shim.c`) and the callbacks it makes into Rust: record I/O through a
//! session's [`Io`] buffers and entropy from the board's RNG.

use core::cell::Cell;
use core::ffi::{c_int, c_uchar, c_void};

use critical_section::Mutex;

use crate::io::Io;

/// mbedTLS: no record bytes available yet (`MBEDTLS_ERR_SSL_WANT_READ`).
pub const WANT_READ: c_int = -0x6900;
/// mbedTLS: no room for record bytes yet (`MBEDTLS_ERR_SSL_WANT_WRITE`).
pub const WANT_WRITE: c_int = -0x6880;
/// mbedTLS: the peer sent close_notify (`MBEDTLS_ERR_SSL_PEER_CLOSE_NOTIFY`).
pub const PEER_CLOSE_NOTIFY: c_int = -0x7880;
/// mbedTLS: the entropy source failed (`MBEDTLS_ERR_ENTROPY_SOURCE_FAILED`).
const ENTROPY_FAILED: c_int = -0x003C;

extern "C" {
    pub fn enip_tls_setup(
        cert: *const c_uchar,
        cert_len: usize,
        key: *const c_uchar,
        key_len: usize,
        ca: *const c_uchar,
        ca_len: usize,
    ) -> c_int;
    pub fn enip_tls_offer(ids: *const u16, n: usize) -> c_int;
    pub fn enip_tls_arena_bytes() -> usize;
    pub fn enip_tls_slots() -> usize;
    pub fn enip_tls_open(index: usize) -> c_int;
    pub fn enip_tls_handshake(index: usize, io: *mut c_void) -> c_int;
    pub fn enip_tls_read(index: usize, io: *mut c_void, buf: *mut c_uchar, len: usize) -> c_int;
    pub fn enip_tls_write(index: usize, io: *mut c_void, buf: *const c_uchar, len: usize) -> c_int;
    pub fn enip_tls_close_notify(index: usize, io: *mut c_void) -> c_int;
    pub fn enip_tls_close(index: usize);
}

/// The board's random number generator: fills its argument, false on failure.
pub type Rng = fn(&mut [u8]) -> bool;

/// The RNG [`crate::setup`] installed.
pub static RNG: Mutex<Cell<Option<Rng>>> = Mutex::new(Cell::new(None));

/// mbedTLS's entropy source (the CTR-DRBG's seed): the board's RNG.
#[no_mangle]
extern "C" fn enip_tls_entropy(_ctx: *mut c_void, out: *mut c_uchar, len: usize) -> c_int {
    let Some(rng) = critical_section::with(|cs| RNG.borrow(cs).get()) else {
        return ENTROPY_FAILED;
    };
    if out.is_null() {
        return ENTROPY_FAILED;
    }
    // SAFETY: mbedTLS passes a buffer of `len` writable bytes.
    let out = unsafe { core::slice::from_raw_parts_mut(out, len) };
    if rng(out) {
        0
    } else {
        ENTROPY_FAILED
    }
}

/// mbedTLS's send callback: queues record bytes in the session's transmit buffer.
#[no_mangle]
extern "C" fn enip_tls_bio_send(io: *mut c_void, buf: *const c_uchar, len: usize) -> c_int {
    if io.is_null() || buf.is_null() {
        return WANT_WRITE;
    }
    // SAFETY: `io` is the `Io` the calling session passed for this call, exclusively borrowed
    // for its duration; `buf` holds `len` readable bytes.
    let (io, data) = unsafe { (&mut *io.cast::<Io>(), core::slice::from_raw_parts(buf, len)) };
    match io.queue(data) {
        0 => WANT_WRITE,
        n => c_int::try_from(n).unwrap_or(c_int::MAX),
    }
}

/// mbedTLS's receive callback: hands over record bytes the session has received.
#[no_mangle]
extern "C" fn enip_tls_bio_recv(io: *mut c_void, buf: *mut c_uchar, len: usize) -> c_int {
    if io.is_null() || buf.is_null() {
        return WANT_READ;
    }
    // SAFETY: as in `enip_tls_bio_send`; `buf` has `len` writable bytes.
    let (io, out) = unsafe {
        (
            &mut *io.cast::<Io>(),
            core::slice::from_raw_parts_mut(buf, len),
        )
    };
    match io.take(out) {
        0 => WANT_READ,
        n => c_int::try_from(n).unwrap_or(c_int::MAX),
    }
}
