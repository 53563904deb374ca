//! The [`Adapter`]: the few entry points a runtime calls with bytes and the current time.
//! The encapsulation commands it answers are in `adapter/encap.rs` beside it, as smoltcp
//! keeps each protocol's handling beside its `Interface`.

mod encap;

use core::net::{Ipv4Addr, SocketAddrV4};

use crate::cip::context::RequestContext;
use crate::config::MAX_ENCAP_FRAME;
use crate::device::{CloseReason, Device, InputChanges};
use crate::encap::list_identity::DelayedReplies;
use crate::encap::session::{Need, Sessions};
use crate::io::consume::{self, Accepted, Discard};
use crate::io::open::Origin;
use crate::io::produce::{self, IoDue};
use crate::io::ConnectionTable;
use crate::net::NetworkConfig;
use crate::nv::{NvError, NvStore};
use crate::objects::{Ctx, ObjectState};
use crate::rng::Rng;
use crate::time::{Duration, Instant};
use crate::wire::encap::{status, EncapRepr, HEADER_LEN};

/// Index of one of the runtime's [`MAX_SESSIONS`](crate::config::MAX_SESSIONS) TCP sockets
/// on port 44818.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SocketId(pub u8);

/// What [`Adapter::tcp_receive`] did with received bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TcpOutcome {
    /// Bytes of the input consumed; call again with the rest.
    pub consumed: usize,
    /// Bytes of reply written at the start of the reply buffer (0: nothing to send).
    pub reply_len: usize,
    /// Close the TCP connection once the reply is sent.
    pub close: bool,
}

/// An EtherNet/IP adapter for device `D`.
pub struct Adapter<D: Device> {
    pub(crate) device: D,
    pub(crate) objects: ObjectState,
    pub(crate) net: NetworkConfig,
    pub(crate) sessions: Sessions,
    pub(crate) delayed: DelayedReplies,
    pub(crate) connections: ConnectionTable,
    pub(crate) rng: Rng,
    /// Where the TCP/IP settings are saved (none: they last until power-off).
    pub(crate) store: Option<&'static mut dyn NvStore>,
}

impl<D: Device> Adapter<D> {
    /// An adapter for `device` on the interface `net`; `seed` feeds handles and reply delays.
    pub fn new(device: D, net: NetworkConfig, seed: u64) -> Self {
        let mut rng = Rng::new(seed);
        let handle_seed = rng.next_u64() as u32;
        let id_seed = rng.next_u64() as u32;
        Adapter {
            device,
            objects: ObjectState::new(),
            net,
            sessions: Sessions::new(handle_seed),
            delayed: DelayedReplies::new(),
            connections: ConnectionTable::new(id_seed),
            rng,
            store: None,
        }
    }

    /// Keeps the TCP/IP settings (attributes 3, 5, 6, 8, 9 and 13) in `store` from now on: loads
    /// those it holds (see [`crate::objects::tcpip::TcpIpState`] for when they apply) and saves
    /// every Set before answering it (0x19 if that fails). Returns whether settings were
    /// loaded; on a read error the factory defaults hold and the store is still used.
    pub fn attach_store(&mut self, store: &'static mut dyn NvStore) -> Result<bool, NvError> {
        let loaded = crate::objects::tcpip::TcpIpState::stored(store);
        self.store = Some(store);
        let stored = loaded?;
        let found = stored.is_some();
        if let Some(st) = stored {
            let tcpip = &mut self.objects.tcpip;
            tcpip.config_control = st.config_control;
            tcpip.interface = st.interface;
            tcpip.host_name = st.host_name;
            tcpip.inactivity_timeout_s = st.inactivity_timeout_s;
            tcpip.ttl = st.ttl;
            tcpip.mcast = st.mcast;
        }
        Ok(found)
    }

    /// The device profile.
    pub fn device(&self) -> &D {
        &self.device
    }
    /// The device profile, mutably.
    pub fn device_mut(&mut self) -> &mut D {
        &mut self.device
    }
    /// Takes the device back, ending the adapter.
    pub fn into_device(self) -> D {
        self.device
    }
    /// Runs one Message Router request (service, path, data) as an unconnected request
    /// with no session, and writes the Message Router response into `reply`; returns its
    /// length. For a device's own tests and local tools: the same objects and rules a
    /// scanner's request meets.
    pub fn execute(&mut self, request: &[u8], now: Instant, reply: &mut [u8]) -> usize {
        let mut ctx = self.ctx(RequestContext::unconnected(None, now), None);
        let mut w = crate::wire::Writer::new(reply);
        // Fails only if not even an error header fits; then nothing was written.
        let _ = crate::objects::router::respond(&mut ctx, request, &mut w, 0);
        let len = w.len();
        self.after_explicit_request();
        len
    }
    /// The stack's object state (TCP/IP settings, counters).
    pub fn objects(&self) -> &ObjectState {
        &self.objects
    }
    /// The connection table.
    pub fn connections(&self) -> &ConnectionTable {
        &self.connections
    }
    /// The interface configuration.
    pub fn network(&self) -> &NetworkConfig {
        &self.net
    }
    /// Reports a new interface configuration (DHCP lease, link change).
    pub fn set_network(&mut self, net: NetworkConfig) {
        self.net = net;
    }
    /// The Reset the Identity object accepted, if any; the runtime performs it after the
    /// reply has gone out.
    pub fn take_reset(&mut self) -> Option<u8> {
        self.objects.pending_reset.take()
    }

    /// A TCP connection from `peer` was accepted on `socket`.
    pub fn tcp_accept(&mut self, socket: SocketId, peer: SocketAddrV4, now: Instant) {
        debug!("tcp accept on socket {}", socket.0);
        self.sessions.reset(usize::from(socket.0), Some(peer), now);
    }

    /// The TCP connection on `socket` closed (by either side): its session ends.
    pub fn tcp_close(&mut self, socket: SocketId, now: Instant) {
        if let Some(peer) = self
            .sessions
            .get(usize::from(socket.0))
            .and_then(|s| s.peer)
        {
            info!("tcp connection from {} closed (socket {})", peer, socket.0);
        }
        self.sessions.reset(usize::from(socket.0), None, now);
        self.connections.close_session(socket.0, &mut self.device);
    }

    /// When the connection on `socket` has been idle for the encapsulation inactivity timeout
    /// (TCP/IP attribute 13) and must be closed; `None` if the timeout is off. Traffic on the
    /// CIP connections its Forward_Opens opened (Class 1 O->T data included) counts as activity,
    /// so a session is not closed under a running I/O connection.
    pub fn tcp_deadline(&self, socket: SocketId) -> Option<Instant> {
        let secs = self.objects.tcpip.inactivity_timeout_s;
        let slot = self.sessions.get(usize::from(socket.0))?;
        if secs == 0 || slot.peer.is_none() {
            return None;
        }
        let last = match self.connections.last_activity_of_session(socket.0) {
            Some(io) => io.max(slot.last_activity),
            None => slot.last_activity,
        };
        Some(last.add(Duration::from_secs(u64::from(secs))))
    }

    /// Feeds bytes received on `socket`. At most one frame is handled per call: the reply (if
    /// any) is in `reply[..reply_len]`; call again with `data[consumed..]` until all is used.
    /// `reply` should hold [`crate::config::MAX_ENCAP_FRAME`] bytes.
    pub fn tcp_receive(
        &mut self,
        socket: SocketId,
        data: &[u8],
        now: Instant,
        reply: &mut [u8],
    ) -> TcpOutcome {
        let index = usize::from(socket.0);
        let Some(slot) = self.sessions.get_mut(index) else {
            return TcpOutcome {
                consumed: data.len(),
                reply_len: 0,
                close: true,
            };
        };
        slot.last_activity = now;
        // Fast path: a whole frame at the front of `data` with nothing buffered is not copied.
        if slot.rx.is_empty() {
            if let Need::Complete(header) = crate::encap::session::frame_need(data) {
                let len = HEADER_LEN + usize::from(header.length);
                let frame = data.get(..len).unwrap_or(&[]);
                let (reply_len, close) = self.tcp_frame(index, &header, frame, now, reply);
                return TcpOutcome {
                    consumed: len,
                    reply_len,
                    close,
                };
            }
        }
        let mut consumed = 0;
        loop {
            let Some(slot) = self.sessions.get_mut(index) else {
                return TcpOutcome {
                    consumed: data.len(),
                    reply_len: 0,
                    close: true,
                };
            };
            match slot.need() {
                Need::Bytes(n) => {
                    let rest = data.get(consumed..).unwrap_or(&[]);
                    if rest.is_empty() {
                        return TcpOutcome {
                            consumed,
                            reply_len: 0,
                            close: false,
                        };
                    }
                    let take = n.min(rest.len());
                    // Cannot fail: `need` never asks beyond the frame capacity.
                    let _ = slot.rx.extend_from_slice(rest.get(..take).unwrap_or(&[]));
                    consumed = consumed.saturating_add(take);
                }
                Need::TooLong => {
                    warn!(
                        "encapsulation length over capacity; closing socket {}",
                        index
                    );
                    let header = EncapRepr::parse_header(&slot.rx).ok();
                    slot.rx.clear();
                    self.objects.link.count_discard();
                    let reply_len = header
                        .and_then(|h| {
                            let reply = &mut crate::wire::Writer::new(reply);
                            h.reply(status::INVALID_LENGTH, 0).emit(reply).ok()
                        })
                        .map_or(0, |_| HEADER_LEN);
                    return TcpOutcome {
                        consumed: data.len(),
                        reply_len,
                        close: true,
                    };
                }
                Need::Complete(header) => {
                    // Handling needs the whole adapter, so the frame moves out of the slot
                    // first: its bytes only, not the buffer's whole capacity.
                    let mut frame = heapless::Vec::<u8, MAX_ENCAP_FRAME>::new();
                    let _ = frame.extend_from_slice(&slot.rx);
                    slot.rx.clear();
                    let (reply_len, close) = self.tcp_frame(index, &header, &frame, now, reply);
                    return TcpOutcome {
                        consumed,
                        reply_len,
                        close,
                    };
                }
            }
        }
    }

    /// Feeds a datagram received on UDP port 44818 from `from`, sent to `to` (used to tell a
    /// broadcast). Returns the length of an immediate reply written to `reply` (0: none).
    pub fn udp_receive(
        &mut self,
        from: SocketAddrV4,
        to: Ipv4Addr,
        data: &[u8],
        now: Instant,
        reply: &mut [u8],
    ) -> usize {
        let broadcast = self.net.is_broadcast(to) || to.is_multicast();
        self.udp_frame(from, broadcast, data, now, reply)
    }

    /// Writes a delayed ListIdentity reply that is due at `now` into `out`; returns its
    /// destination and length. Call until it returns `None`.
    pub fn poll_udp(&mut self, now: Instant, out: &mut [u8]) -> Option<(SocketAddrV4, usize)> {
        let p = self.delayed.take_due(now)?;
        let len = self.list_identity_reply(p.session_handle, p.sender_context, out);
        Some((p.to, len))
    }

    /// Feeds a datagram received on UDP 2222 (Class 1 O->T data) from `from`.
    pub fn io_receive(
        &mut self,
        from: SocketAddrV4,
        data: &[u8],
        now: Instant,
    ) -> Result<Accepted, Discard> {
        let r = consume::consume(&mut self.connections, &mut self.device, from, data, now);
        match r {
            Ok(_) => self.apply_input_changes(),
            Err(_) => self.objects.link.count_discard(),
        }
        r
    }

    /// Runs the device's own behaviour ([`Device::poll`]) at `now`, then triggers the inputs
    /// it says changed; returns when the device next wants to run.
    pub fn poll_device(&mut self, now: Instant) -> Option<Instant> {
        let next = self.device.poll(now);
        self.apply_input_changes();
        next
    }

    /// Closes every connection with `reason` (the runtime calls it with
    /// [`CloseReason::Reset`] before it performs an Identity Reset), telling the device of
    /// each.
    pub fn close_all(&mut self, reason: CloseReason) {
        self.connections.close_all(reason, &mut self.device);
    }

    /// Closes connections whose watchdog expired, then writes the most overdue T->O datagram
    /// into `out` (at least the largest input assembly plus 20 bytes) and returns its
    /// destination (UDP port 2222 of the originator or multicast group) and length. Call until
    /// it returns `None`, then sleep until [`Self::next_deadline`].
    pub fn poll_io(&mut self, now: Instant, out: &mut [u8]) -> Option<(SocketAddrV4, usize)> {
        self.connections.expire(now, &mut self.device);
        produce::produce_due(&mut self.connections, &mut self.device, now, out)
    }

    /// Closes connections whose watchdog expired, then returns the most overdue T->O
    /// datagram, if one is due: its destination and largest length. Build it with
    /// [`Self::write_io`] straight into a transmit buffer of that length (or drop it with
    /// `write_io(due, now, None)` when there is nowhere to send it); call again until
    /// `None`, as with [`Self::poll_io`].
    pub fn io_due(&mut self, now: Instant) -> Option<IoDue> {
        self.connections.expire(now, &mut self.device);
        produce::next_due(&self.connections, now)
    }

    /// Writes the T->O datagram `due` (from [`Self::io_due`], with no other call between)
    /// into `out`, which holds at least `due.max_len` bytes, and moves its connection to its
    /// next production; returns the datagram's length (the device may fill less than the
    /// connection's size). `out` `None` drops the datagram. Returns 0, changing nothing, if
    /// `out` is too short or the connection is gone.
    pub fn write_io(&mut self, due: IoDue, now: Instant, out: Option<&mut [u8]>) -> usize {
        produce::write(&mut self.connections, &mut self.device, due, now, out)
    }

    /// Tells the stack that input assembly `instance` has new data: change-of-state and
    /// application-triggered connections producing it send as soon as their inhibit time
    /// allows. (A device says the same from inside with [`Device::input_changes`].)
    pub fn trigger_input(&mut self, instance: u16) {
        self.connections.trigger(instance);
    }

    /// The multicast group T->O data goes to while a multicast connection is open.
    pub fn multicast_group(&self) -> Option<Ipv4Addr> {
        self.connections.produces_multicast().then(|| {
            self.objects
                .tcpip
                .multicast_in_use(&self.device, &self.net)
                .0
        })
    }

    /// TTL for multicast T->O datagrams (TCP/IP attribute 8).
    pub fn multicast_ttl(&self) -> u8 {
        self.objects
            .tcpip
            .multicast_in_use(&self.device, &self.net)
            .1
    }

    /// The next instant [`Self::poll_udp`] has a delayed reply to send.
    pub fn udp_deadline(&self) -> Option<Instant> {
        self.delayed.next_due()
    }

    /// The next instant [`Self::poll_io`] has work: a production or a watchdog expiry.
    pub fn io_deadline(&self) -> Option<Instant> {
        self.connections.next_deadline()
    }

    /// The earliest of [`Self::udp_deadline`] and [`Self::io_deadline`].
    pub fn next_deadline(&self) -> Option<Instant> {
        match (self.udp_deadline(), self.io_deadline()) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// The service context for a request.
    pub(crate) fn ctx(&mut self, request: RequestContext, origin: Option<Origin>) -> Ctx<'_, D> {
        Ctx {
            device: &mut self.device,
            state: &mut self.objects,
            net: &self.net,
            connections: &mut self.connections,
            origin,
            reply_t_o_sockaddr: None,
            request,
            store: self.store.as_deref_mut(),
        }
    }

    /// After an explicit request: connections whose assembly size the request changed are
    /// closed, and the inputs the device says changed are triggered.
    pub(crate) fn after_explicit_request(&mut self) {
        self.connections.close_resized(&mut self.device);
        self.apply_input_changes();
    }

    /// Triggers production of the input assemblies the device says changed: a look at the
    /// device's set on every datagram and request, the triggering only when it holds some.
    #[inline]
    fn apply_input_changes(&mut self) {
        if let Some(changes) = self.device.input_changes().filter(|c| !c.is_empty()) {
            trigger_changes(&mut self.connections, changes);
        }
    }
}

/// Triggers production of the input assemblies in `changes`, and clears it.
#[inline(never)]
fn trigger_changes(connections: &mut ConnectionTable, changes: &mut InputChanges) {
    if changes.all() {
        connections.trigger_all();
    } else {
        for instance in changes.iter() {
            connections.trigger(instance);
        }
    }
    changes.clear();
}
