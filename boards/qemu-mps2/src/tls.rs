//! EtherNet/IP over TLS on 2221 in the `tls` image: the mbedTLS path of `enip-tls-mbedtls`
//! with the certificate `build.rs` baked in, run beside the plaintext sockets.
//!
//! QEMU's mps2-an386 has no random number generator: the RNG here is a xorshift generator
//! seeded from the MAC and the LAN9118's free-running counter, which is NOT secure. A real
//! board hands its TRNG to [`enip_tls_mbedtls::setup`] instead.

use core::cell::Cell;
use core::future::Future;

use critical_section::Mutex;
use embassy_net::Stack;
use enip_firmware::SharedAdapter;
use enip_stack::{Device, SocketId};
use enip_tls_mbedtls::TlsBuffers;
use static_cell::ConstStaticCell;

use enip_firmware::Diagnosed;

/// The device certificate (DER).
static CERT: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/tls_cert.der"));
/// The device private key (DER).
static KEY: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/tls_key.der"));
/// The trusted CA (DER; empty: no client certificates asked for).
static CA: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/tls_ca.der"));

/// The TLS session's socket and reply buffers.
static BUFFERS: ConstStaticCell<TlsBuffers<{ enip_stack::config::MAX_ENCAP_FRAME }>> =
    ConstStaticCell::new(TlsBuffers::new());
/// The RNG's state.
static STATE: Mutex<Cell<u64>> = Mutex::new(Cell::new(0));

/// The adapter session the TLS connection uses: the last one, shared with the last 44818
/// socket (see the README: a TLS session and a third plaintext one at once collide).
const TLS_SESSION: SocketId = SocketId(enip_stack::config::MAX_SESSIONS as u8 - 1);

/// Runs `plaintext` (the runtime on 44818) with TLS on 2221 beside it, or alone if mbedTLS
/// refused its setup (certificate, key, CA, RNG seeded with `seed`); the suites offered are
/// those EtherNet/IP Security allows when each session starts.
pub async fn beside<D: Device, F: Future>(
    net: Stack<'static>,
    adapter: &'static SharedAdapter<Diagnosed<D>>,
    seed: u64,
    plaintext: F,
) -> F::Output {
    critical_section::with(|cs| STATE.borrow(cs).set(seed | 1));
    if let Err(e) = enip_tls_mbedtls::setup(rng, CERT, KEY, CA) {
        log::warn!("tls: mbedTLS setup failed: {e:?}");
        return plaintext.await;
    }
    log::info!(
        "tls: mbedTLS listening on 2221 ({} byte arena)",
        enip_tls_mbedtls::arena_bytes()
    );
    enip_firmware::with_adapter(adapter, |a| a.enable_security(true));
    let tls = enip_tls_mbedtls::serve(
        net,
        adapter,
        TLS_SESSION,
        0,
        BUFFERS.take(),
        &super::on_reset,
    );
    embassy_futures::join::join(plaintext, tls).await.0
}

/// The insecure stand-in RNG (xorshift64*), see the module comment.
fn rng(out: &mut [u8]) -> bool {
    critical_section::with(|cs| {
        let cell = STATE.borrow(cs);
        let mut x = cell.get();
        for chunk in out.chunks_mut(8) {
            x ^= x >> 12;
            x ^= x << 25;
            x ^= x >> 27;
            let word = x.wrapping_mul(0x2545_F491_4F6C_DD1D).to_le_bytes();
            chunk.copy_from_slice(word.get(..chunk.len()).unwrap_or(&[]));
        }
        cell.set(x);
    });
    true
}
