//! One encapsulation session's connection on port 44818, or on 2221 over TLS ([`Slot`]):
//! completes a TLS handshake first (bounded by [`HANDSHAKE`]), then reads into its own
//! buffer only when its previous reply has gone out, hands the bytes to the adapter frame by
//! frame, writes each reply, performs an Identity Reset once its reply is out, and on a close
//! shuts its side down and waits (bounded) for the peer's FIN. The timeouts are the embedded
//! runtime's ([`enip_stack::tcp`]).

use std::io;
use std::net::{SocketAddrV4, TcpStream};
use std::os::fd::{AsRawFd, RawFd};
use std::time::Duration;

use enip_stack::config::MAX_ENCAP_FRAME;
use enip_stack::device::CloseReason;
use enip_stack::tcp::{LINGER, WRITE_TIMEOUT};
use enip_stack::{Adapter, Device, Instant, SocketId, TcpOutcome};
use socket2::SockRef;

use super::link::{Handshake, Link};

/// Bytes read from a connection at once: a whole TLS record's plaintext, so that none waits
/// in the TLS layer where polling the socket cannot see it.
const RX_LEN: usize = 16 * 1024;
/// Longest a TLS handshake may take.
const HANDSHAKE: Duration = Duration::from_secs(10);

/// One session's buffers (allocated once) and connection.
pub struct Slot {
    id: SocketId,
    rx: Box<[u8; RX_LEN]>,
    /// Unconsumed received bytes: `rx[rx_start..rx_end]`.
    rx_start: usize,
    rx_end: usize,
    reply: Box<[u8; MAX_ENCAP_FRAME]>,
    /// Reply bytes not yet taken by the kernel: `reply[out_start..out_end]`.
    out_start: usize,
    out_end: usize,
    conn: Option<Conn>,
}

/// A connection in a slot.
struct Conn {
    stream: Link,
    state: State,
    /// When the adapter's inactivity timeout is to be checked.
    idle_check: Option<Instant>,
}

/// Where a connection is in its life.
#[derive(Clone, Copy)]
enum State {
    /// The TLS handshake runs until `until`; it waits for the socket to be writable
    /// (`write`) or readable.
    Handshake { until: Instant, write: bool },
    /// Serving frames; `then` is the outcome of the frame whose reply is pending (its Reset
    /// and close follow the reply), and `write_deadline` when that reply must be out.
    Open {
        then: TcpOutcome,
        write_deadline: Option<Instant>,
    },
    /// Our FIN is sent; reading until the peer's, at most until `until`.
    Closing { until: Instant },
}

/// How far a reply got.
enum Flush {
    /// All of it is with the kernel.
    Done,
    /// The kernel took part of it; the rest waits for room.
    Pending,
    /// The connection failed.
    Failed,
}

/// What the loop watches of one descriptor, and for what.
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct Interest {
    /// The descriptor.
    pub fd: RawFd,
    /// Wait until readable.
    pub read: bool,
    /// Wait until writable.
    pub write: bool,
}

impl Conn {
    fn is_open(&self) -> bool {
        matches!(self.state, State::Open { .. })
    }

    fn deadline(&self) -> Option<Instant> {
        match self.state {
            State::Open {
                write_deadline: Some(at),
                ..
            } => Some(at),
            State::Open { .. } => self.idle_check,
            State::Closing { until } | State::Handshake { until, .. } => Some(until),
        }
    }
}

impl Slot {
    /// The free slot of session `id`, its buffers allocated.
    pub fn new(id: SocketId) -> Self {
        Slot {
            id,
            rx: Box::new([0; RX_LEN]),
            rx_start: 0,
            rx_end: 0,
            reply: Box::new([0; MAX_ENCAP_FRAME]),
            out_start: 0,
            out_end: 0,
            conn: None,
        }
    }

    /// Whether no connection is in the slot.
    pub fn is_free(&self) -> bool {
        self.conn.is_none()
    }

    /// When [`Self::check_deadline`] next has work, if ever.
    pub fn deadline(&self) -> Option<Instant> {
        self.conn.as_ref().and_then(Conn::deadline)
    }

    /// Asks the adapter again when the open connection's inactivity timeout is due.
    pub fn recheck_idle<D: Device>(&mut self, adapter: &Adapter<D>) {
        if let Some(c) = self.conn.as_mut().filter(|c| c.is_open()) {
            c.idle_check = adapter.tcp_deadline(self.id);
        }
    }

    /// Serves the accepted connection `stream` from `peer` in this (free) slot.
    pub fn start<D: Device>(
        &mut self,
        stream: Link,
        peer: SocketAddrV4,
        adapter: &mut Adapter<D>,
        now: Instant,
    ) {
        if let Err(e) = stream.tcp().set_nonblocking(true) {
            log::warn!("tcp {peer}: {e}");
            return reset(stream.tcp());
        }
        // Replies are whole frames; send each at once.
        let _ = stream.tcp().set_nodelay(true);
        let tls = !matches!(stream, Link::Plain(_));
        log::debug!("tcp socket {}: connection from {peer}", self.id.0);
        adapter.tcp_accept(self.id, peer, now);
        #[cfg(feature = "tls")]
        adapter.set_session_secure(self.id, tls);
        self.rx_start = 0;
        self.rx_end = 0;
        self.out_start = 0;
        self.out_end = 0;
        let state = if tls {
            State::Handshake {
                until: now.add(micros(HANDSHAKE)),
                write: false,
            }
        } else {
            open()
        };
        self.conn = Some(Conn {
            stream,
            state,
            idle_check: adapter.tcp_deadline(self.id),
        });
    }

    /// What the connection waits for: a read, or room for the rest of its reply.
    pub fn interest(&self) -> Option<Interest> {
        let write = self.waits_to_write()?;
        Some(Interest {
            fd: self.conn.as_ref()?.stream.tcp().as_raw_fd(),
            read: !write,
            write,
        })
    }

    /// Whether the connection waits for room to write (else to read); `None` if the slot is
    /// free.
    pub fn waits_to_write(&self) -> Option<bool> {
        let conn = self.conn.as_ref()?;
        Some(match conn.state {
            State::Handshake { write, .. } => write,
            _ => self.out_start < self.out_end,
        })
    }

    /// Serves the connection after its descriptor became readable and/or writable; returns
    /// whether frames were handled (or the connection closed on a failed write).
    pub fn serve<D: Device>(
        &mut self,
        readable: bool,
        writable: bool,
        adapter: &mut Adapter<D>,
        now: Instant,
        on_reset: fn(u8),
    ) -> bool {
        let Some(conn) = self.conn.as_mut() else {
            return false;
        };
        match conn.state {
            State::Handshake { .. } => self.handshake(adapter, now, on_reset),
            State::Closing { .. } => {
                if readable {
                    self.drain_closing();
                }
                false
            }
            State::Open { then, .. } if self.out_start < self.out_end => {
                if !writable {
                    return false;
                }
                match self.flush(now) {
                    Flush::Done => {
                        self.after_reply(then, adapter, now, on_reset);
                        self.handle(adapter, now, on_reset);
                        true
                    }
                    Flush::Pending => false,
                    Flush::Failed => {
                        self.close(adapter, now);
                        true
                    }
                }
            }
            State::Open { .. } => {
                if !readable || !self.receive(adapter, now) {
                    return false;
                }
                if !self.handle(adapter, now, on_reset) {
                    self.ack_now();
                }
                true
            }
        }
    }

    /// Moves the TLS handshake on; once complete, serves what already arrived. Returns
    /// whether frames were handled (or the connection closed).
    fn handshake<D: Device>(
        &mut self,
        adapter: &mut Adapter<D>,
        now: Instant,
        on_reset: fn(u8),
    ) -> bool {
        let Some(conn) = self.conn.as_mut() else {
            return false;
        };
        match conn.stream.handshake() {
            Handshake::Done => {
                log::debug!(
                    "tcp socket {}: TLS session: {}",
                    self.id.0,
                    conn.stream.describe().unwrap_or_default()
                );
                conn.state = open();
                if self.receive(adapter, now) && !self.handle(adapter, now, on_reset) {
                    self.ack_now();
                }
                true
            }
            Handshake::Waiting(w) => {
                if let State::Handshake { write, .. } = &mut conn.state {
                    *write = w;
                }
                false
            }
            Handshake::Failed(why) => {
                log::info!("tcp socket {}: TLS handshake failed: {why}", self.id.0);
                adapter.tcp_close(self.id, now);
                reset(conn.stream.tcp());
                self.conn = None;
                true
            }
        }
    }

    /// Reads what arrived into the empty receive buffer; false if nothing did (a closed or
    /// failed connection is closed here).
    fn receive<D: Device>(&mut self, adapter: &mut Adapter<D>, now: Instant) -> bool {
        let Some(conn) = self.conn.as_mut() else {
            return false;
        };
        match conn.stream.read(self.rx.as_mut_slice()) {
            Ok(0) => {
                log::debug!("tcp socket {}: closed by the peer", self.id.0);
                self.close(adapter, now);
                false
            }
            Ok(n) => {
                self.rx_start = 0;
                self.rx_end = n;
                true
            }
            Err(e) if e.kind() == io::ErrorKind::WouldBlock => false,
            Err(e) => {
                log::debug!("tcp socket {}: {e}", self.id.0);
                self.close(adapter, now);
                false
            }
        }
    }

    /// Hands the received bytes to the adapter, frame by frame, writing each reply; stops at
    /// a reply the kernel cannot take yet. Returns whether any reply was written.
    fn handle<D: Device>(
        &mut self,
        adapter: &mut Adapter<D>,
        now: Instant,
        on_reset: fn(u8),
    ) -> bool {
        let mut replied = false;
        // Bounded: every round consumes at least one byte or closes.
        for _ in 0..RX_LEN {
            if self.rx_start >= self.rx_end || self.out_start < self.out_end {
                return replied;
            }
            if !self.conn.as_ref().is_some_and(Conn::is_open) {
                return replied;
            }
            let data = self.rx.get(self.rx_start..self.rx_end).unwrap_or(&[]);
            let then = adapter.tcp_receive(self.id, data, now, self.reply.as_mut_slice());
            self.rx_start += then.consumed.min(data.len());
            self.out_start = 0;
            self.out_end = then.reply_len.min(MAX_ENCAP_FRAME);
            replied |= self.out_end > 0;
            match self.flush(now) {
                Flush::Done => self.after_reply(then, adapter, now, on_reset),
                Flush::Pending => {
                    if let Some(Conn {
                        state: State::Open { then: t, .. },
                        ..
                    }) = self.conn.as_mut()
                    {
                        *t = then;
                    }
                    return replied;
                }
                Flush::Failed => {
                    self.close(adapter, now);
                    return replied;
                }
            }
        }
        replied
    }

    /// Acknowledges what was received at once: part of a frame has no reply to carry the
    /// acknowledgement, and a delayed one makes the peer retransmit.
    fn ack_now(&self) {
        if let Some(conn) = self.conn.as_ref().filter(|c| c.is_open()) {
            let _ = SockRef::from(conn.stream.tcp()).set_tcp_quickack(true);
        }
    }

    /// Writes the pending reply.
    fn flush(&mut self, now: Instant) -> Flush {
        let Some(conn) = self.conn.as_mut() else {
            return Flush::Failed;
        };
        while self.out_start < self.out_end {
            let out = self.reply.get(self.out_start..self.out_end).unwrap_or(&[]);
            match conn.stream.write(out) {
                Ok(n) if n > 0 => self.out_start += n,
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => {
                    if let State::Open { write_deadline, .. } = &mut conn.state {
                        write_deadline.get_or_insert(now.add(WRITE_TIMEOUT));
                    }
                    return Flush::Pending;
                }
                _ => {
                    self.out_start = self.out_end;
                    return Flush::Failed;
                }
            }
        }
        if let State::Open { write_deadline, .. } = &mut conn.state {
            *write_deadline = None;
        }
        Flush::Done
    }

    /// Does what follows a reply that went out: the Reset, then the close, `then` asks for.
    fn after_reply<D: Device>(
        &mut self,
        then: TcpOutcome,
        adapter: &mut Adapter<D>,
        now: Instant,
        on_reset: fn(u8),
    ) {
        if let Some(Conn {
            state: State::Open { then: t, .. },
            ..
        }) = self.conn.as_mut()
        {
            *t = TcpOutcome::default();
        }
        if let Some(kind) = then.reset {
            log::info!(
                "identity reset type {kind} requested on tcp socket {}",
                self.id.0
            );
            adapter.close_all(CloseReason::Reset);
            on_reset(kind);
        }
        if then.close {
            self.close(adapter, now);
        }
    }

    /// Ends the session and sends our FIN; the slot frees once the peer's FIN arrives or
    /// [`LINGER`] passes.
    fn close<D: Device>(&mut self, adapter: &mut Adapter<D>, now: Instant) {
        let Some(conn) = self.conn.as_mut() else {
            return;
        };
        if !matches!(conn.state, State::Closing { .. }) {
            adapter.tcp_close(self.id, now);
        }
        conn.stream.shutdown();
        conn.state = State::Closing {
            until: now.add(LINGER),
        };
        self.out_start = self.out_end;
        self.rx_start = self.rx_end;
    }

    /// Discards what arrives after our FIN; frees the slot at the peer's FIN or an error.
    fn drain_closing(&mut self) {
        let Some(conn) = self.conn.as_mut() else {
            return;
        };
        match conn.stream.read(self.rx.as_mut_slice()) {
            Ok(n) if n > 0 => {}
            Err(e) if e.kind() == io::ErrorKind::WouldBlock => {}
            _ => {
                self.conn = None;
                log::debug!("tcp socket {}: closed", self.id.0);
            }
        }
    }

    /// Closes the connection if its inactivity timeout passed, resets it if its reply or its
    /// close did not complete in time.
    pub fn check_deadline<D: Device>(&mut self, adapter: &mut Adapter<D>, now: Instant) {
        let Some(conn) = self.conn.as_mut() else {
            return;
        };
        match conn.state {
            State::Handshake { until, .. } if until <= now => {
                log::info!("tcp socket {}: TLS handshake not done in time", self.id.0);
                adapter.tcp_close(self.id, now);
                reset(conn.stream.tcp());
                self.conn = None;
            }
            State::Closing { until } if until <= now => {
                // The peer never finished: reset rather than wait.
                reset(conn.stream.tcp());
                self.conn = None;
                log::debug!("tcp socket {}: closed (reset)", self.id.0);
            }
            State::Open {
                write_deadline: Some(at),
                ..
            } if at <= now => {
                log::warn!("tcp socket {}: reply not sent in time", self.id.0);
                self.close(adapter, now);
            }
            State::Open { .. } if conn.idle_check.is_some_and(|at| at <= now) => {
                conn.idle_check = adapter.tcp_deadline(self.id);
                if conn.idle_check.is_some_and(|at| at <= now) {
                    log::debug!("tcp socket {}: inactivity timeout", self.id.0);
                    self.close(adapter, now);
                }
            }
            _ => {}
        }
    }
}

/// Resets a connection that cannot be served (at its close, now or when dropped).
pub fn reset(stream: &TcpStream) {
    let _ = SockRef::from(stream).set_linger(Some(Duration::ZERO));
}

/// A connection's state when it starts serving frames.
fn open() -> State {
    State::Open {
        then: TcpOutcome::default(),
        write_deadline: None,
    }
}

/// A standard duration as the stack's.
pub fn micros(d: Duration) -> enip_stack::time::Duration {
    enip_stack::time::Duration::from_micros(d.as_micros() as u64)
}
