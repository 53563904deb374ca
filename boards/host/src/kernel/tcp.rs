//! The encapsulation TCP sessions on port 44818 (and, with `--tls`, on 2221 over TLS): a
//! listener per port and one slot per session the stack has room for ([`MAX_SESSIONS`]).
//!
//! The two ports share the slots: the stack's sessions are its capacity (3 by default, each
//! with its reassembly buffer), whichever port a client comes in on, as a device with one
//! session table and two listening ports has it; a fourth client is refused on either port.
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

use super::link::Link;
use super::session::{micros, reset, Interest, Slot};
use super::socket::{set_dscp, tcp_listener, BACKLOG};
#[cfg(feature = "tls")]
use super::tls;

/// The TCP port of EtherNet/IP over TLS.
#[cfg(feature = "tls")]
pub use enip_stack::config::TLS_PORT;

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
    /// EtherNet/IP over TLS on 2221 (`--tls`).
    #[cfg(feature = "tls")]
    tls: Option<TlsServer>,
    /// 44818 is closed to explicit messaging (TCP/IP Set_Port_Admin_State): no listener
    /// there; the sessions already open go on.
    plain_closed: bool,
    /// A descriptor was opened (a listener, a slot's connection) since [`Self::watched`]:
    /// one may reuse a closed one's number.
    renewed: bool,
    /// The listener or what a session waits for may have changed since [`Self::watched`].
    rewatch: bool,
}

/// The TLS port's listener and what its sessions are set up with.
#[cfg(feature = "tls")]
pub struct TlsServer {
    /// Listening while a slot is free.
    listener: Option<TcpListener>,
    /// The device's certificates.
    material: tls::Material,
    /// The context of the settings in use, and their generation.
    context: Option<(u32, openssl::ssl::SslContext)>,
}

#[cfg(feature = "tls")]
impl TlsServer {
    /// Listens on 2221 of `ip`, with `material`.
    pub fn open(ip: Ipv4Addr, material: tls::Material) -> io::Result<Self> {
        Ok(TlsServer {
            listener: Some(tcp_listener(SocketAddrV4::new(ip, TLS_PORT))?),
            material,
            context: None,
        })
    }

    /// The device's certificates, for the adapter to be told of.
    pub fn material(&self) -> &tls::Material {
        &self.material
    }

    /// A TLS session for `stream` with the settings in use now (the context made anew when
    /// a configuration was applied); `None` if they cannot make one (logged).
    fn wrap<D: Device>(
        &mut self,
        stream: TcpStream,
        adapter: &mut Adapter<D>,
        now: Instant,
    ) -> Option<Link> {
        let st = adapter.security(now);
        if self
            .context
            .as_ref()
            .is_none_or(|(g, _)| *g != st.generation)
        {
            match tls::context(st, &self.material) {
                Ok(ctx) => self.context = Some((st.generation, ctx)),
                Err(e) => {
                    log::error!("TLS settings unusable: {e}");
                    self.context = None;
                }
            }
        }
        let (_, ctx) = self.context.as_ref()?;
        let ssl = openssl::ssl::Ssl::new(ctx)
            .map_err(|e| log::warn!("tls: {e}"))
            .ok()?;
        let tls = openssl::ssl::SslStream::new(ssl, stream)
            .map_err(|e| log::warn!("tls: {e}"))
            .ok()?;
        Some(Link::Tls(Box::new(tls)))
    }
}

/// A connection waiting for a free slot.
struct Waiting {
    stream: Link,
    peer: SocketAddrV4,
    /// When it is reset if no slot freed.
    until: Instant,
}

impl Tcp {
    /// Listens on port 44818 of `ip`.
    pub fn open(ip: Ipv4Addr, #[cfg(feature = "tls")] tls: Option<TlsServer>) -> io::Result<Self> {
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
            #[cfg(feature = "tls")]
            tls,
            plain_closed: false,
            renewed: true,
            rewatch: true,
        })
    }

    /// Closes 44818 to new clients (`closed`), or listens there again.
    #[cfg(feature = "tls")]
    pub fn set_plain_closed<D: Device>(
        &mut self,
        closed: bool,
        adapter: &mut Adapter<D>,
        now: Instant,
    ) {
        if closed == self.plain_closed {
            return;
        }
        log::info!(
            "tcp {}: {} to explicit messaging",
            self.addr,
            if closed { "closed" } else { "open" }
        );
        self.plain_closed = closed;
        if closed {
            self.listener = None;
        }
        self.rewatch = true;
        self.settle(adapter, now);
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
        #[cfg(feature = "tls")]
        if let Some(l) = self.tls.as_ref().and_then(|t| t.listener.as_ref()) {
            if let Err(e) = set_dscp(l, dscp) {
                log::warn!("tcp {}:{TLS_PORT}: dscp {dscp}: {e}", self.addr.ip());
            }
        }
    }

    /// The TLS port's server, if `--tls`.
    #[cfg(feature = "tls")]
    pub fn tls(&self) -> Option<&TlsServer> {
        self.tls.as_ref()
    }

    /// The TLS listener, while one listens.
    pub fn tls_listener_fd(&self) -> Option<RawFd> {
        #[cfg(feature = "tls")]
        return self
            .tls
            .as_ref()
            .and_then(|t| t.listener.as_ref())
            .map(AsRawFd::as_raw_fd);
        #[cfg(not(feature = "tls"))]
        None
    }

    /// The listener, while one listens.
    pub fn listener_fd(&self) -> Option<RawFd> {
        self.listener.as_ref().map(AsRawFd::as_raw_fd)
    }

    /// Whether the epoll set is to be told something: a descriptor was opened, or what a
    /// session waits for changed, since [`Self::watched`].
    pub fn needs_watch(&self) -> bool {
        self.renewed || self.rewatch
    }

    /// Notes that the epoll set was told of every descriptor; returns whether one was opened
    /// since the last call (what the set was told of a descriptor number may now concern
    /// another one).
    pub fn watched(&mut self) -> bool {
        self.rewatch = false;
        core::mem::take(&mut self.renewed)
    }

    /// What the connection in slot `index` waits for, if there is one.
    pub fn interest(&self, index: usize) -> Option<Interest> {
        self.slots.get(index)?.interest()
    }

    /// Accepts every connection the kernel completed: into a free slot, else into the
    /// waiting queue; closes the listener once every slot is taken.
    pub fn accept<D: Device>(&mut self, adapter: &mut Adapter<D>, now: Instant, tls: bool) {
        // Bounded by what the kernel's backlog can hold.
        for _ in 0..BACKLOG + MAX_SESSIONS {
            #[cfg(feature = "tls")]
            let listener = match tls {
                true => self.tls.as_ref().and_then(|t| t.listener.as_ref()),
                false => self.listener.as_ref(),
            };
            #[cfg(not(feature = "tls"))]
            let listener = self.listener.as_ref().filter(|_| !tls);
            let Some(listener) = listener else {
                break;
            };
            match listener.accept() {
                Ok((stream, SocketAddr::V4(peer))) => {
                    let link = self.link(stream, tls, adapter, now);
                    if let Some(link) = link {
                        self.admit(link, peer, adapter, now);
                    }
                }
                Ok(_) => {}
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => break,
                Err(e) => {
                    log::warn!("tcp accept: {e}");
                    break;
                }
            }
        }
        if self.slots.iter().all(|s| !s.is_free()) {
            // Every session is taken: the kernel refuses the next client, on either port.
            self.listener = None;
            #[cfg(feature = "tls")]
            if let Some(t) = &mut self.tls {
                t.listener = None;
            }
        }
        self.rewatch = true;
        self.settle(adapter, now);
    }

    /// The session stream of an accepted connection: itself, or TLS over it.
    fn link<D: Device>(
        &mut self,
        stream: TcpStream,
        tls: bool,
        adapter: &mut Adapter<D>,
        now: Instant,
    ) -> Option<Link> {
        if !tls {
            return Some(Link::Plain(stream));
        }
        #[cfg(feature = "tls")]
        if let Some(t) = &mut self.tls {
            return t.wrap(stream, adapter, now);
        }
        let _ = (adapter, now);
        reset(&stream);
        None
    }

    /// Serves `stream` in a free slot; with none free, lets it wait (a client whose
    /// handshake the kernel completed just before the listener closed), or resets it.
    fn admit<D: Device>(
        &mut self,
        stream: Link,
        peer: SocketAddrV4,
        adapter: &mut Adapter<D>,
        now: Instant,
    ) {
        if let Some(slot) = self.slots.iter_mut().find(|s| s.is_free()) {
            self.renewed = true;
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
            None => reset(stream.tcp()),
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
        let before = (slot.deadline(), slot.waits_to_write());
        let served = slot.serve(readable, writable, adapter, now, on_reset);
        let after = (slot.deadline(), slot.waits_to_write());
        self.rewatch |= after.1 != before.1;
        if served && adapter.objects().tcpip.inactivity_timeout_s != timeout {
            // A Set of TCP/IP attribute 13 moves every session's inactivity deadline. (Other
            // traffic only moves deadlines later: each slot's check is a lower bound, asked
            // again when it comes.)
            for s in &mut self.slots {
                s.recheck_idle(adapter);
            }
        } else if after == before {
            // Only this slot changed, and neither its deadline nor whether it is free or
            // waits to write: the next deadline stays, and no waiting connection or listener
            // is concerned.
            return served;
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
                reset(gone.stream.tcp());
            }
        }
        self.rewatch = true;
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
            self.renewed = true;
        }
        if self.slots.iter().all(|s| !s.is_free()) {
            return;
        }
        #[cfg(feature = "tls")]
        if let Some(t) = self.tls.as_mut().filter(|t| t.listener.is_none()) {
            let addr = SocketAddrV4::new(*self.addr.ip(), TLS_PORT);
            match tcp_listener(addr) {
                Ok(l) => {
                    if let Err(e) = set_dscp(&l, self.dscp) {
                        log::warn!("tcp {addr}: dscp {}: {e}", self.dscp);
                    }
                    t.listener = Some(l);
                    self.renewed = true;
                }
                Err(e) => log::warn!("tcp {addr}: listen failed: {e}"),
            }
        }
        if self.listener.is_some() || self.plain_closed {
            return;
        }
        match tcp_listener(self.addr) {
            Ok(l) => {
                if let Err(e) = set_dscp(&l, self.dscp) {
                    log::warn!("tcp {}: dscp {}: {e}", self.addr, self.dscp);
                }
                self.listener = Some(l);
                self.renewed = true;
            }
            Err(e) => log::warn!("tcp {}: listen failed: {e}", self.addr),
        }
    }
}
