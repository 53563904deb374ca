//! [`TlsSession`]: one TLS connection over an embassy-net TCP socket, driven asynchronously
//! around mbedTLS's non-blocking calls (a call that wants record bytes returns, the socket is
//! read, the call is made again).

use core::ffi::{c_int, c_void};

use embassy_net::tcp::TcpSocket;

use crate::ffi::{self, PEER_CLOSE_NOTIFY, WANT_READ, WANT_WRITE};
use crate::io::Io;
use crate::Error;

/// A TLS server connection on session slot `slot` of the shim.
pub struct TlsSession<'a, 's> {
    slot: usize,
    socket: &'a mut TcpSocket<'s>,
    io: Io,
}

impl<'a, 's> TlsSession<'a, 's> {
    /// A fresh TLS session on slot `slot` over the accepted `socket`.
    pub fn new(slot: usize, socket: &'a mut TcpSocket<'s>) -> Result<Self, Error> {
        // SAFETY: the shim checks the slot; it is set up anew for this connection.
        let ret = unsafe { ffi::enip_tls_open(slot) };
        if ret != 0 {
            return Err(Error::Tls(ret));
        }
        Ok(Self {
            slot,
            socket,
            io: Io::new(),
        })
    }

    /// Runs the handshake to its end.
    pub async fn handshake(&mut self) -> Result<(), Error> {
        let slot = self.slot;
        // SAFETY: `io` is this session's buffers, borrowed for the call only.
        self.drive(|io| unsafe { ffi::enip_tls_handshake(slot, io) })
            .await
            .map(|_| ())
    }

    /// Reads decrypted application bytes into `buf`; `Ok(0)` is the peer's close_notify.
    pub async fn read(&mut self, buf: &mut [u8]) -> Result<usize, Error> {
        let slot = self.slot;
        let (ptr, len) = (buf.as_mut_ptr(), buf.len());
        // SAFETY: `buf` is valid for `len` bytes for the whole call.
        match self
            .drive(|io| unsafe { ffi::enip_tls_read(slot, io, ptr, len) })
            .await
        {
            Err(Error::Tls(PEER_CLOSE_NOTIFY)) => Ok(0),
            other => other,
        }
    }

    /// Encrypts and sends all of `data`.
    pub async fn write_all(&mut self, mut data: &[u8]) -> Result<(), Error> {
        let slot = self.slot;
        while !data.is_empty() {
            let (ptr, len) = (data.as_ptr(), data.len());
            // SAFETY: `data` is valid for `len` bytes for the whole call.
            let n = self
                .drive(|io| unsafe { ffi::enip_tls_write(slot, io, ptr, len) })
                .await?;
            data = data.get(n..).unwrap_or(&[]);
        }
        self.flush().await
    }

    /// Sends close_notify (best effort).
    pub async fn close_notify(&mut self) {
        let slot = self.slot;
        // SAFETY: as in `handshake`.
        let _ = self
            .drive(|io| unsafe { ffi::enip_tls_close_notify(slot, io) })
            .await;
    }

    /// Makes `call` until it stops wanting I/O, reading and writing the socket between calls.
    async fn drive(&mut self, mut call: impl FnMut(*mut c_void) -> c_int) -> Result<usize, Error> {
        // Each turn reads or writes the socket or ends: a peer that stalls is bounded by the
        // caller's timeouts (`serve`'s handshake, write and inactivity deadlines).
        loop {
            let ret = call(core::ptr::from_mut(&mut self.io).cast());
            self.flush().await?;
            match ret {
                n if n >= 0 => return Ok(usize::try_from(n).unwrap_or(0)),
                WANT_WRITE => {}
                WANT_READ => self.fill().await?,
                e => return Err(Error::Tls(e)),
            }
        }
    }

    /// Writes out every record byte mbedTLS has queued.
    async fn flush(&mut self) -> Result<(), Error> {
        while !self.io.pending().is_empty() {
            match self.socket.write(self.io.pending()).await {
                Ok(n) if n > 0 => self.io.sent(n),
                _ => return Err(Error::Closed),
            }
        }
        Ok(())
    }

    /// Reads what the socket has into the receive buffer.
    async fn fill(&mut self) -> Result<(), Error> {
        let Some(room) = self.io.room() else {
            return Ok(());
        };
        match self.socket.read(room).await {
            Ok(n) if n > 0 => {
                self.io.received(n);
                Ok(())
            }
            _ => Err(Error::Closed),
        }
    }
}

impl Drop for TlsSession<'_, '_> {
    fn drop(&mut self) {
        // SAFETY: frees this slot's SSL context back to the arena.
        unsafe { ffi::enip_tls_close(self.slot) }
    }
}
