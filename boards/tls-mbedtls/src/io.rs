//! A session's record buffers between mbedTLS and the TCP socket: received bytes waiting for
//! mbedTLS, and record bytes mbedTLS produced waiting to be written.

/// Bytes held each way.
pub const IO_LEN: usize = 512;

/// The record bytes of one session in flight between mbedTLS and its socket.
pub struct Io {
    rx: [u8; IO_LEN],
    rx_at: usize,
    rx_len: usize,
    tx: [u8; IO_LEN],
    tx_len: usize,
}

impl Io {
    /// Empty buffers.
    pub const fn new() -> Self {
        Self {
            rx: [0; IO_LEN],
            rx_at: 0,
            rx_len: 0,
            tx: [0; IO_LEN],
            tx_len: 0,
        }
    }

    /// Appends as much of `data` as fits for sending; returns the bytes taken.
    pub fn queue(&mut self, data: &[u8]) -> usize {
        let room = self.tx.get_mut(self.tx_len..).unwrap_or(&mut []);
        let n = room.len().min(data.len());
        room[..n].copy_from_slice(&data[..n]);
        self.tx_len += n;
        n
    }

    /// Moves received bytes into `out`; returns how many.
    pub fn take(&mut self, out: &mut [u8]) -> usize {
        let held = self.rx.get(self.rx_at..self.rx_len).unwrap_or(&[]);
        let n = held.len().min(out.len());
        out[..n].copy_from_slice(&held[..n]);
        self.rx_at += n;
        n
    }

    /// The bytes waiting to be sent.
    pub fn pending(&self) -> &[u8] {
        self.tx.get(..self.tx_len).unwrap_or(&[])
    }

    /// `n` pending bytes were sent.
    pub fn sent(&mut self, n: usize) {
        let n = n.min(self.tx_len);
        self.tx.copy_within(n..self.tx_len, 0);
        self.tx_len -= n;
    }

    /// Room for received bytes (after dropping those already taken), or `None` if mbedTLS has
    /// not taken any of a full buffer yet.
    pub fn room(&mut self) -> Option<&mut [u8]> {
        if self.rx_at == self.rx_len {
            self.rx_at = 0;
            self.rx_len = 0;
        }
        let room = self.rx.get_mut(self.rx_len..).filter(|r| !r.is_empty())?;
        Some(room)
    }

    /// `n` bytes were received into [`Io::room`].
    pub fn received(&mut self, n: usize) {
        self.rx_len = (self.rx_len + n).min(IO_LEN);
    }
}

impl Default for Io {
    fn default() -> Self {
        Self::new()
    }
}
