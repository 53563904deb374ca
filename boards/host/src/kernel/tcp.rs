//! The encapsulation TCP sessions on port 44818: a listener and one slot per session the
//! stack has room for ([`MAX_SESSIONS`]).
//!
//! While every slot is taken the listener is closed, so the kernel refuses a surplus client
//! with a reset, as the embedded runtime does with no socket listening; it listens again as
//! soon as a slot is free. A client whose handshake the kernel completed just before the
//! close waits (at most [`WAIT`]) for a slot, then is reset. Each slot's connection is
//! served by [`super::session`].

use std::io;
use std::net::{Ipv4Addr, SocketAddr, SocketAddrV4, TcpListener, TcpStream};
use std::os::fd::{AsRawFd, RawFd};
use std::time::Duration;

use enip_stack::config::{ENCAP_PORT, MAX_SESSIONS};
use enip_stack::{Adapter, Device, Instant, SocketId};

use super::session::{micros, reset, Interest, Slot};
use super::socket::{set_dscp, tcp_listener, BACKLOG};

/// Longest wait of a connection accepted while every slot was taken.
const WAIT: Duration = Duration::from_secs(1);

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
    /// The DSCP of explicit messaging (QoS attribute 8), set on every listener.
    dscp: u8,
}

/// A connection waiting for a free slot.
struct Waiting {
    stream: TcpStream,
    peer: SocketAddrV4,
    /// When it is reset if no slot freed.
    until: Instant,
}

impl Tcp {
    /// Listens on port 44818 of `ip`.
    pub fn open(ip: Ipv4Addr) -> io::Result<Self> {
        let addr = SocketAddrV4::new(ip, ENCAP_PORT);
        let mut index = 0u8;
        let slots = [(); MAX_SESSIONS].map(|()| {
            let id = SocketId(index);
            index += 1;
            Slot::new(id)
        });
        Ok(Tcp {
            addr,
            listener: Some(tcp_listener(addr)?),
            slots,
            waiting: [const { None }; MAX_SESSIONS],
            deadline: None,
            dscp: 0,
        })
    }

    /// Marks the sessions' packets with `dscp` from now on (the listener's and the next
    /// listeners' connections).
    pub fn set_dscp(&mut self, dscp: u8) {
        self.dscp = dscp;
        if let Some(l) = &self.listener {
            if let Err(e) = set_dscp(l, dscp) {
                log::warn!("tcp {}: dscp {dscp}: {e}", self.addr);
            }
        }
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
        if self.slots.iter().all(|s| !s.is_free()) {
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
        if let Some(slot) = self.slots.iter_mut().find(|s| s.is_free()) {
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
        let timeout = adapter.objects().tcpip.inactivity_timeout_s;
        let served = slot.serve(readable, writable, adapter, now, on_reset);
        if served && adapter.objects().tcpip.inactivity_timeout_s != timeout {
            // A Set of TCP/IP attribute 13 moves every session's inactivity deadline. (Other
            // traffic only moves deadlines later: each slot's check is a lower bound, asked
            // again when it comes.)
            for s in &mut self.slots {
                s.recheck_idle(adapter);
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
            .filter_map(Slot::deadline)
            .chain(waiting)
            .min();
    }

    /// Gives free slots to waiting connections, then listens again if a slot is still free
    /// and nothing listens.
    fn listen_if_free<D: Device>(&mut self, adapter: &mut Adapter<D>, now: Instant) {
        for slot in self.slots.iter_mut().filter(|s| s.is_free()) {
            let Some(w) = self.waiting.iter_mut().find_map(Option::take) else {
                break;
            };
            slot.start(w.stream, w.peer, adapter, now);
        }
        if self.listener.is_some() || self.slots.iter().all(|s| !s.is_free()) {
            return;
        }
        match tcp_listener(self.addr) {
            Ok(l) => {
                if let Err(e) = set_dscp(&l, self.dscp) {
                    log::warn!("tcp {}: dscp {}: {e}", self.addr, self.dscp);
                }
                self.listener = Some(l);
            }
            Err(e) => log::warn!("tcp {}: listen failed: {e}", self.addr),
        }
    }
}
