//! The encapsulation TCP sessions on port 44818: a listener and one slot per session the
//! stack has room for ([`MAX_SESSIONS`]).
//!
//! While every slot is taken the listener is closed, so the kernel refuses a surplus client
//! with a reset, as the embedded runtime does with no socket listening; it listens again as
//! soon as a slot is free. A client whose handshake the kernel completed just before the
//! close waits (at most [`WAIT`]) for a slot, then is reset. Each slot reads into its own buffer only when its previous reply
//! has gone out, hands the bytes to the adapter, writes the reply, and on a close shuts its
//! side down and waits (bounded) for the peer's FIN before the slot is free again.

use std::io::{self, Read, Write};
use std::net::{Ipv4Addr, Shutdown, SocketAddr, SocketAddrV4, TcpListener, TcpStream};
use std::os::fd::{AsRawFd, RawFd};
use std::time::Duration;

use enip_stack::config::{ENCAP_PORT, MAX_ENCAP_FRAME, MAX_SESSIONS};
use enip_stack::device::CloseReason;
use enip_stack::{Adapter, Device, Instant, SocketId};
use socket2::SockRef;

use super::socket::{tcp_listener, BACKLOG};

/// Bytes read from a connection at once.
const RX_LEN: usize = 2048;
/// Longest wait for a reply to be taken by the kernel before the connection is reset.
const WRITE_TIMEOUT: Duration = Duration::from_secs(5);
/// Longest wait of a connection accepted while every slot was taken.
const WAIT: Duration = Duration::from_secs(1);
/// Longest wait for the peer's FIN after ours.
const LINGER: Duration = Duration::from_secs(2);

/// The listener and the session slots.
pub struct Tcp {
    addr: SocketAddrV4,
    /// Listening while a slot is free.
    listener: Option<TcpListener>,
    slots: [Slot; MAX_SESSIONS],
    /// Connections accepted while every slot was taken, until a slot frees or they time out.
    waiting: [Option<Waiting>; MAX_SESSIONS],
    /// The earliest deadline of a connection, as of the last change.
    deadline: Option<Instant>,
}

/// A connection waiting for a free slot.
struct Waiting {
    stream: TcpStream,
    peer: SocketAddrV4,
    /// When it is reset if no slot freed.
    until: Instant,
}

/// One session's buffers (allocated once) and connection.
struct Slot {
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
    stream: TcpStream,
    state: State,
    /// When the adapter's inactivity timeout is to be checked.
    idle_check: Option<Instant>,
}

/// Where a connection is in its life.
#[derive(Clone, Copy)]
enum State {
    /// Serving frames; `then` is what to do once the pending reply is out, and
    /// `write_deadline` when that reply must be out.
    Open {
        then: After,
        write_deadline: Option<Instant>,
    },
    /// Our FIN is sent; reading until the peer's, at most until `until`.
    Closing { until: Instant },
}

/// What follows a reply.
#[derive(Clone, Copy, PartialEq, Eq)]
enum After {
    /// Serve the next frame.
    Continue,
    /// Close the connection.
    Close,
    /// Perform an Identity Reset of this type (then close the connection if `close`).
    Reset { kind: u8, close: bool },
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
pub struct Interest {
    /// The descriptor.
    pub fd: RawFd,
    /// Wait until readable.
    pub read: bool,
    /// Wait until writable.
    pub write: bool,
}

impl Tcp {
    /// Listens on port 44818 of `ip`.
    pub fn open(ip: Ipv4Addr) -> io::Result<Self> {
        let addr = SocketAddrV4::new(ip, ENCAP_PORT);
        let mut index = 0u8;
        let slots = [(); MAX_SESSIONS].map(|()| {
            let id = SocketId(index);
            index += 1;
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
        });
        Ok(Tcp {
            addr,
            listener: Some(tcp_listener(addr)?),
            slots,
            waiting: [const { None }; MAX_SESSIONS],
            deadline: None,
        })
    }

    /// The listener, while one listens.
    pub fn listener_fd(&self) -> Option<RawFd> {
        self.listener.as_ref().map(AsRawFd::as_raw_fd)
    }

    /// What the connection in slot `index` waits for, if there is one.
    pub fn interest(&self, index: usize) -> Option<Interest> {
        self.slots.get(index)?.interest()
    }

    /// Accepts every connection the kernel completed: into a free slot, else into the
    /// waiting queue; closes the listener once every slot is taken.
    pub fn accept<D: Device>(&mut self, adapter: &mut Adapter<D>, now: Instant) {
        // Bounded by what the kernel's backlog can hold.
        for _ in 0..BACKLOG + MAX_SESSIONS {
            let Some(listener) = &self.listener else {
                return;
            };
            match listener.accept() {
                Ok((stream, SocketAddr::V4(peer))) => self.admit(stream, peer, adapter, now),
                Ok(_) => {}
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => break,
                Err(e) => {
                    log::warn!("tcp accept: {e}");
                    break;
                }
            }
        }
        if self.slots.iter().all(|s| s.conn.is_some()) {
            // Every session is taken: the kernel refuses the next client.
            self.listener = None;
        }
        self.settle(adapter, now);
    }

    /// Serves `stream` in a free slot; with none free, lets it wait (a client whose
    /// handshake the kernel completed just before the listener closed), or resets it.
    fn admit<D: Device>(
        &mut self,
        stream: TcpStream,
        peer: SocketAddrV4,
        adapter: &mut Adapter<D>,
        now: Instant,
    ) {
        if let Some(slot) = self.slots.iter_mut().find(|s| s.conn.is_none()) {
            return slot.start(stream, peer, adapter, now);
        }
        match self.waiting.iter_mut().find(|w| w.is_none()) {
            Some(w) => {
                *w = Some(Waiting {
                    stream,
                    peer,
                    until: now.add(micros(WAIT)),
                })
            }
            None => reset(stream),
        }
    }

    /// Serves slot `index` after its descriptor became readable and/or writable; returns
    /// whether frames were handled (which may have changed connections or settings).
    pub fn serve<D: Device>(
        &mut self,
        index: usize,
        readable: bool,
        writable: bool,
        adapter: &mut Adapter<D>,
        now: Instant,
        on_reset: fn(u8),
    ) -> bool {
        let Some(slot) = self.slots.get_mut(index) else {
            return false;
        };
        let served = slot.serve(readable, writable, adapter, now, on_reset);
        if served {
            // A Set of TCP/IP attribute 13 moves every session's inactivity deadline.
            for s in &mut self.slots {
                let id = s.id;
                if let Some(c) = s.conn.as_mut().filter(|c| c.is_open()) {
                    c.idle_check = adapter.tcp_deadline(id);
                }
            }
        }
        self.settle(adapter, now);
        served
    }

    /// Closes connections idle past the inactivity timeout, resets those whose reply or
    /// close did not complete in time.
    pub fn check_deadlines<D: Device>(&mut self, adapter: &mut Adapter<D>, now: Instant) {
        for slot in &mut self.slots {
            slot.check_deadline(adapter, now);
        }
        for w in &mut self.waiting {
            if let Some(gone) = w.take_if(|w| w.until <= now) {
                log::debug!("tcp {}: no session free, reset", gone.peer);
                reset(gone.stream);
            }
        }
        self.settle(adapter, now);
    }

    /// The earliest instant [`Self::check_deadlines`] has work.
    pub fn next_deadline(&self) -> Option<Instant> {
        self.deadline
    }

    /// After any change: gives free slots to waiting connections, listens again if a slot is
    /// still free, and notes the next deadline.
    fn settle<D: Device>(&mut self, adapter: &mut Adapter<D>, now: Instant) {
        self.listen_if_free(adapter, now);
        let waiting = self.waiting.iter().flatten().map(|w| w.until);
        self.deadline = self
            .slots
            .iter()
            .filter_map(|s| s.conn.as_ref().and_then(Conn::deadline))
            .chain(waiting)
            .min();
    }

    /// Gives free slots to waiting connections, then listens again if a slot is still free
    /// and nothing listens.
    fn listen_if_free<D: Device>(&mut self, adapter: &mut Adapter<D>, now: Instant) {
        for slot in self.slots.iter_mut().filter(|s| s.conn.is_none()) {
            let Some(w) = self.waiting.iter_mut().find_map(Option::take) else {
                break;
            };
            slot.start(w.stream, w.peer, adapter, now);
        }
        if self.listener.is_some() || self.slots.iter().all(|s| s.conn.is_some()) {
            return;
        }
        match tcp_listener(self.addr) {
            Ok(l) => self.listener = Some(l),
            Err(e) => log::warn!("tcp {}: listen failed: {e}", self.addr),
        }
    }
}

/// Resets a connection that cannot be served.
fn reset(stream: TcpStream) {
    let _ = SockRef::from(&stream).set_linger(Some(Duration::ZERO));
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
            State::Closing { until } => Some(until),
        }
    }
}

impl Slot {
    /// Serves the accepted connection `stream` from `peer` in this (free) slot.
    fn start<D: Device>(
        &mut self,
        stream: TcpStream,
        peer: SocketAddrV4,
        adapter: &mut Adapter<D>,
        now: Instant,
    ) {
        if let Err(e) = stream.set_nonblocking(true) {
            log::warn!("tcp {peer}: {e}");
            return reset(stream);
        }
        // Replies are whole frames; send each at once.
        let _ = stream.set_nodelay(true);
        log::debug!("tcp socket {}: connection from {peer}", self.id.0);
        adapter.tcp_accept(self.id, peer, now);
        self.rx_start = 0;
        self.rx_end = 0;
        self.out_start = 0;
        self.out_end = 0;
        self.conn = Some(Conn {
            stream,
            state: State::Open {
                then: After::Continue,
                write_deadline: None,
            },
            idle_check: adapter.tcp_deadline(self.id),
        });
    }

    fn interest(&self) -> Option<Interest> {
        let conn = self.conn.as_ref()?;
        let pending = self.out_start < self.out_end;
        Some(Interest {
            fd: conn.stream.as_raw_fd(),
            read: !pending,
            write: pending,
        })
    }

    fn serve<D: Device>(
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
            let outcome = adapter.tcp_receive(self.id, data, now, self.reply.as_mut_slice());
            self.rx_start += outcome.consumed.min(data.len());
            let close = outcome.close || outcome.consumed == 0;
            let then = match adapter.take_reset() {
                Some(kind) => After::Reset { kind, close },
                None if close => After::Close,
                None => After::Continue,
            };
            self.out_start = 0;
            self.out_end = outcome.reply_len.min(MAX_ENCAP_FRAME);
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
            let _ = SockRef::from(&conn.stream).set_tcp_quickack(true);
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
                        write_deadline.get_or_insert(now.add(micros(WRITE_TIMEOUT)));
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

    /// Does what follows a reply that went out.
    fn after_reply<D: Device>(
        &mut self,
        then: After,
        adapter: &mut Adapter<D>,
        now: Instant,
        on_reset: fn(u8),
    ) {
        if let Some(Conn {
            state: State::Open { then: t, .. },
            ..
        }) = self.conn.as_mut()
        {
            *t = After::Continue;
        }
        match then {
            After::Continue => {}
            After::Close => self.close(adapter, now),
            After::Reset { kind, close } => {
                log::info!(
                    "identity reset type {kind} requested on tcp socket {}",
                    self.id.0
                );
                adapter.close_all(CloseReason::Reset);
                on_reset(kind);
                if close {
                    self.close(adapter, now);
                }
            }
        }
    }

    /// Ends the session and sends our FIN; the slot frees once the peer's FIN arrives or
    /// [`LINGER`] passes.
    fn close<D: Device>(&mut self, adapter: &mut Adapter<D>, now: Instant) {
        let Some(conn) = self.conn.as_mut() else {
            return;
        };
        if conn.is_open() {
            adapter.tcp_close(self.id, now);
        }
        let _ = conn.stream.shutdown(Shutdown::Write);
        conn.state = State::Closing {
            until: now.add(micros(LINGER)),
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

    fn check_deadline<D: Device>(&mut self, adapter: &mut Adapter<D>, now: Instant) {
        let Some(conn) = self.conn.as_mut() else {
            return;
        };
        match conn.state {
            State::Closing { until } if until <= now => {
                // The peer never finished: reset rather than wait.
                let _ = SockRef::from(&conn.stream).set_linger(Some(Duration::ZERO));
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

/// A standard duration as the stack's.
fn micros(d: Duration) -> enip_stack::time::Duration {
    enip_stack::time::Duration::from_micros(d.as_micros() as u64)
}
