//! The [`Adapter`]: the few entry points a runtime calls with bytes and the current time.
//! The encapsulation commands it answers are in `adapter/encap.rs` beside it, as smoltcp
//! keeps each protocol's handling beside its `Interface`, and LLDP in `adapter/lldp.rs`.

mod acd;
mod encap;
mod lldp;

pub use lldp::MAX_LLDPDU;

use core::net::{Ipv4Addr, SocketAddrV4};

use crate::cip::context::RequestContext;
use crate::device::{CloseReason, Device, InputChanges};
use crate::encap::list_identity::DelayedReplies;
use crate::encap::session::{Feed, Sessions};
use crate::io::consume::{self, Accepted, Discard};
use crate::io::open::Origin;
use crate::io::produce::{self, IoDue};
use crate::io::ConnectionTable;
use crate::net::NetworkConfig;
use crate::nv::{NvError, NvStore};
use crate::objects::{Ctx, LinkCounters, ObjectState};
use crate::rng::Rng;
use crate::time::{Duration, Instant};
use crate::wire::encap::HEADER_LEN;

/// Index of one of the runtime's TCP sockets on port 44818 (below the adapter's `SESSIONS`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SocketId(pub u8);

/// What [`Adapter::tcp_receive`] did with received bytes, and what the runtime does next:
/// send the reply, then perform the Reset (if any), then close (if told to).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TcpOutcome {
    /// Bytes of the input consumed; call again with the rest. More than 0 whenever the input
    /// was not empty, unless `close` is set.
    pub consumed: usize,
    /// Bytes of reply written at the start of the reply buffer (0: nothing to send).
    pub reply_len: usize,
    /// Close the TCP connection once the reply is sent.
    pub close: bool,
    /// An Identity Reset the request accepted, of this type: once the reply has gone out, the
    /// runtime closes every connection ([`Adapter::close_all`] with [`CloseReason::Reset`])
    /// and performs it.
    pub reset: Option<u8>,
}

/// An EtherNet/IP adapter for device `D`, with the capacities its maker chose at compile time
/// (the defaults are those of [`crate::config`], for a small MCU):
///
/// - `SESSIONS`: encapsulation sessions, one per TCP socket on port 44818 (1 to 254);
/// - `CONNECTIONS`: slots of the CIP connection table, Class 1 and Class 3 (1 to 254);
/// - `FRAME`: the largest encapsulation frame received or sent, header included: each
///   session's reassembly buffer, and the size the runtime's reply buffers should have (at
///   least [`MIN_FRAME`], which carries a 504-byte Class 3 message);
/// - `LIST_IDENTITY`: broadcast ListIdentity replies that can wait their random delay at
///   once (at least 1).
///
/// They are checked against each other when the adapter is built
/// ([`Adapter::with_capacities`]): a choice out of range is a compile error. See the device
/// guide ([`crate::guide`]).
pub struct Adapter<
    D: Device,
    const SESSIONS: usize = { crate::config::MAX_SESSIONS },
    const CONNECTIONS: usize = { crate::config::MAX_CONNECTIONS },
    const FRAME: usize = { crate::config::MAX_ENCAP_FRAME },
    const LIST_IDENTITY: usize = { crate::config::MAX_PENDING_LIST_IDENTITY },
> {
    /// Everything that answers a frame.
    inner: Inner<D, CONNECTIONS, LIST_IDENTITY>,
    /// One encapsulation session per TCP socket, each framing its socket's byte stream. Kept
    /// apart from `inner` (as smoltcp keeps `InterfaceInner` apart from what borrows it) so
    /// that a frame reassembled in a session's buffer is answered from there, not copied out
    /// first: the frame and its session are borrowed from here while `inner` answers.
    sessions: Sessions<SESSIONS, FRAME>,
}

/// The smallest `FRAME` an [`Adapter`] accepts: the encapsulation header, a SendUnitData's
/// items and a 504-byte Class 3 message with its sequence count.
pub const MIN_FRAME: usize = HEADER_LEN + 22 + crate::config::MAX_EXPLICIT_CONNECTED;

/// The adapter but for its sessions: the device, the objects and `C` connections; `L`
/// delayed ListIdentity replies.
pub(crate) struct Inner<D: Device, const C: usize, const L: usize> {
    pub(crate) device: D,
    pub(crate) objects: ObjectState,
    pub(crate) net: NetworkConfig,
    pub(crate) delayed: DelayedReplies<L>,
    pub(crate) connections: ConnectionTable<C>,
    pub(crate) rng: Rng,
    /// Where the TCP/IP settings are saved (none: they last until power-off).
    pub(crate) store: Option<&'static mut dyn NvStore>,
    /// Makes CSRs with the device key (Certificate Management Create_CSR).
    #[cfg(feature = "cip-security")]
    pub(crate) csr: Option<&'static mut dyn crate::objects::security::CsrSigner>,
}

impl<D: Device> Adapter<D> {
    /// An adapter for `device` on the interface `net`, with the default capacities
    /// ([`crate::config`]: 3 sessions, 10 connections); `seed` feeds handles and reply
    /// delays. Other capacities: [`Adapter::with_capacities`]. Never inlined: built in its
    /// caller's place, where inlined its fields were built apart and moved one by one (336
    /// bytes of the NUCLEO-F767ZI image).
    #[inline(never)]
    pub fn new(device: D, net: NetworkConfig, seed: u64) -> Self {
        Self::with_capacities(device, net, seed)
    }
}

impl<
        D: Device,
        const SESSIONS: usize,
        const CONNECTIONS: usize,
        const FRAME: usize,
        const LIST_IDENTITY: usize,
    > Adapter<D, SESSIONS, CONNECTIONS, FRAME, LIST_IDENTITY>
{
    /// An adapter for `device` on the interface `net` with the capacities of its type, as
    /// [`Adapter::new`] builds one with the defaults (`Adapter::<D, 16, 64>::with_capacities`);
    /// `seed` feeds handles and reply delays. The capacities are checked here, at compile
    /// time.
    pub fn with_capacities(device: D, net: NetworkConfig, seed: u64) -> Self {
        const {
            assert!(
                SESSIONS >= 1 && SESSIONS < u8::MAX as usize,
                "SESSIONS: 1 to 254 (a session handle's low byte names the socket)"
            );
            assert!(
                CONNECTIONS >= 1 && CONNECTIONS < u8::MAX as usize,
                "CONNECTIONS: 1 to 254 (the production schedule links slots in bytes)"
            );
            assert!(
                FRAME >= MIN_FRAME,
                "FRAME: at least MIN_FRAME, for a 504-byte Class 3 message"
            );
            assert!(
                FRAME <= HEADER_LEN + u16::MAX as usize,
                "FRAME: the encapsulation length field is 16 bits"
            );
            assert!(LIST_IDENTITY >= 1, "LIST_IDENTITY: at least 1");
        };
        let mut rng = Rng::new(seed);
        let handle_seed = rng.next_u64() as u32;
        let id_seed = rng.next_u64() as u32;
        let mut objects = ObjectState::new();
        // An interface DHCP configured: the runtime has a DHCP client, and attribute 3 says
        // DHCP until a stored setting says otherwise.
        if net.dhcp {
            objects.tcpip.dhcp_client = true;
            objects.tcpip.config_control = crate::objects::tcpip::CONTROL_DHCP;
        }
        Adapter {
            inner: Inner {
                device,
                objects,
                net,
                delayed: DelayedReplies::new(),
                connections: ConnectionTable::new(id_seed),
                rng,
                store: None,
                #[cfg(feature = "cip-security")]
                csr: None,
            },
            sessions: Sessions::new(handle_seed),
        }
    }

    /// Tells the TCP/IP object whether the runtime can take its address from DHCP (the
    /// embassy boards' `dhcp` feature): capability bit 2, and whether attribute 3 may be set
    /// to DHCP. An interface DHCP configured at [`Adapter::new`] says so already.
    pub fn set_dhcp_client(&mut self, capable: bool) {
        self.inner.objects.tcpip.dhcp_client = capable;
    }

    /// Keeps the TCP/IP settings (attributes 3, 5, 6, 8, 9 and 13) in `store` from now on: loads
    /// those it holds (see [`crate::objects::tcpip::TcpIpState`] for when they apply) and saves
    /// every Set before answering it (0x19 if that fails). Returns whether settings were
    /// loaded; on a read error the factory defaults hold and the store is still used.
    ///
    /// The QoS object's settings are loaded from it too, and put in use (they apply from a
    /// start): attach the store before the first connection opens.
    pub fn attach_store(&mut self, store: &'static mut dyn NvStore) -> Result<bool, NvError> {
        // LLDP settings (LLDP Management attributes 1-3) that cannot be read keep the defaults.
        if let Ok(Some(config)) = crate::objects::LldpConfig::stored(store) {
            self.inner.objects.lldp.config = config;
        }
        if let Ok(Some(qos)) = crate::objects::QosState::stored(store) {
            self.inner.objects.qos = qos;
        }
        let loaded = crate::objects::tcpip::TcpIpState::stored(store);
        self.inner.store = Some(store);
        let stored = loaded?;
        let found = stored.is_some();
        if let Some(st) = stored {
            let tcpip = &mut self.inner.objects.tcpip;
            tcpip.config_control = st.config_control;
            tcpip.interface = st.interface;
            tcpip.host_name = st.host_name;
            tcpip.inactivity_timeout_s = st.inactivity_timeout_s;
            tcpip.start_with_multicast(st.ttl, st.mcast);
        }
        self.load_acd();
        #[cfg(feature = "cip-security")]
        if let Some(store) = self.inner.store.as_deref_mut() {
            crate::objects::security::load(&mut self.inner.objects.security, store);
        }
        Ok(found)
    }

    /// Turns the CIP Security objects (0x5D, 0x5E, 0x5F) and the ListIdentity CIP Security
    /// item on; `tls_port_open`: the runtime listens for EtherNet/IP over TLS on TCP 2221.
    /// Until this is called the adapter answers as one built without `cip-security`.
    #[cfg(feature = "cip-security")]
    pub fn enable_security(&mut self, tls_port_open: bool) {
        let st = &mut self.inner.objects.security;
        st.enabled = true;
        st.tls_port_open = tls_port_open;
    }

    /// True if the runtime serves EtherNet/IP over TLS on TCP [`crate::config::TLS_PORT`]
    /// ([`Self::enable_security`]); false in a stack built without `cip-security`.
    pub fn tls_port_open(&self) -> bool {
        #[cfg(feature = "cip-security")]
        {
            let st = &self.inner.objects.security;
            st.enabled && st.tls_port_open
        }
        #[cfg(not(feature = "cip-security"))]
        false
    }

    /// Makes Certificate Management's Create_CSR work: `signer` makes the requests with the
    /// device key, and the File object (0x37) instance the reply names serves them.
    #[cfg(feature = "cip-security")]
    pub fn attach_csr_signer(
        &mut self,
        signer: &'static mut dyn crate::objects::security::CsrSigner,
    ) {
        self.inner.csr = Some(signer);
    }

    /// The CIP Security objects' state: the TLS settings in use (what a new TLS session is
    /// to use), the certificate instances, the states; configuration sessions that lapsed by
    /// `now` are ended first.
    #[cfg(feature = "cip-security")]
    pub fn security(&mut self, now: Instant) -> &crate::objects::security::SecurityState {
        let st = &mut self.inner.objects.security;
        st.expire(now);
        st
    }

    /// Notes whether the session on `socket` runs over TLS (call it at each
    /// [`Self::tcp_accept`]): a configured security object is reconfigured or reset only over
    /// TLS.
    #[cfg(feature = "cip-security")]
    pub fn set_session_secure(&mut self, socket: SocketId, secure: bool) {
        self.inner
            .objects
            .security
            .set_session_secure(socket.0, secure);
    }

    /// Records what the runtime found of the certificates of Certificate Management instance
    /// `instance` (its device certificate and its CA certificate); false if there is no
    /// such instance.
    #[cfg(feature = "cip-security")]
    pub fn set_certificate_status(
        &mut self,
        instance: u8,
        device: crate::objects::security::CertStatus,
        ca: crate::objects::security::CertStatus,
    ) -> bool {
        let i = usize::from(instance).wrapping_sub(1);
        match self.inner.objects.security.certs.get_mut(i) {
            Some(c) if c.exists => {
                (c.device, c.ca) = (device, ca);
                true
            }
            _ => false,
        }
    }

    /// The device profile.
    pub fn device(&self) -> &D {
        &self.inner.device
    }
    /// The device profile, mutably.
    pub fn device_mut(&mut self) -> &mut D {
        &mut self.inner.device
    }
    /// Takes the device back, ending the adapter.
    pub fn into_device(self) -> D {
        self.inner.device
    }
    /// Runs one Message Router request (service, path, data) as an unconnected request
    /// with no session, and writes the Message Router response into `reply`; returns its
    /// length. For a device's own tests and local tools: the same objects and rules a
    /// scanner's request meets. A Reset it accepted is then in [`Self::take_reset`].
    pub fn execute(&mut self, request: &[u8], now: Instant, reply: &mut [u8]) -> usize {
        let inner = &mut self.inner;
        let mut ctx = inner.ctx(RequestContext::unconnected(None, now), None);
        let mut w = crate::wire::Writer::new(reply);
        // Fails only if not even an error header fits; then nothing was written.
        let _ = crate::objects::router::respond(&mut ctx, request, &mut w, 0);
        let len = w.len();
        inner.after_explicit_request();
        len
    }
    /// The Identity Reset a request run by [`Self::execute`] accepted, if any, for the caller
    /// to perform. (Over TCP, [`TcpOutcome::reset`] reports it.)
    pub fn take_reset(&mut self) -> Option<u8> {
        self.inner.objects.pending_reset.take()
    }
    /// Identity attribute 5, Status, as a scanner reads it: the device's own bits and the
    /// connections' (owned, extended device status), for a runtime's Module Status
    /// indicator.
    pub fn identity_status(&self) -> u16 {
        let inner = &self.inner;
        crate::objects::identity::status(
            inner.device.status_bits(),
            inner.connections.identity_status(),
        )
    }
    /// The stack's object state (TCP/IP settings, counters).
    pub fn objects(&self) -> &ObjectState {
        &self.inner.objects
    }
    /// The DSCP explicit messaging goes out with (QoS attribute 8 as the device started):
    /// for the runtime to mark TCP and UDP 44818 packets with.
    pub fn explicit_dscp(&self) -> u8 {
        self.inner.objects.qos.active.explicit()
    }
    /// The connection table.
    pub fn connections(&self) -> &ConnectionTable<CONNECTIONS> {
        &self.inner.connections
    }
    /// The interface configuration.
    pub fn network(&self) -> &NetworkConfig {
        &self.inner.net
    }
    /// Reports a new interface configuration (DHCP lease, link change); a new address is
    /// announced by LLDP.
    pub fn set_network(&mut self, net: NetworkConfig) {
        if (net.ip, net.mac) != (self.inner.net.ip, self.inner.net.mac) {
            self.inner.objects.lldp.local_changed();
        }
        self.inner.net = net;
    }
    /// Adds the frames the runtime counted on the interface since its last call to the
    /// Ethernet Link object's counters (attributes 4 and 5).
    pub fn add_link_counters(&mut self, counted: &LinkCounters) {
        self.inner.objects.link.counters.add(counted);
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
        let inner = &mut self.inner;
        inner.connections.close_session(socket.0, &mut inner.device);
    }

    /// When the connection on `socket` has been idle for the encapsulation inactivity timeout
    /// (TCP/IP attribute 13) and must be closed; `None` if the timeout is off. Traffic on the
    /// CIP connections its Forward_Opens opened (Class 1 O->T data included) counts as activity,
    /// so a session is not closed under a running I/O connection.
    pub fn tcp_deadline(&self, socket: SocketId) -> Option<Instant> {
        let secs = self.inner.objects.tcpip.inactivity_timeout_s;
        let slot = self.sessions.get(usize::from(socket.0))?;
        if secs == 0 || slot.peer.is_none() {
            return None;
        }
        let last = match self.inner.connections.last_activity_of_session(socket.0) {
            Some(io) => io.max(slot.last_activity),
            None => slot.last_activity,
        };
        Some(last.add(Duration::from_secs(u64::from(secs))))
    }

    /// Feeds bytes received on `socket`. At most one frame is handled per call: the reply (if
    /// any) is in `reply[..reply_len]`, and the outcome says what follows it; call again with
    /// `data[consumed..]` until all is used. `reply` should hold
    /// `FRAME` bytes.
    pub fn tcp_receive(
        &mut self,
        socket: SocketId,
        data: &[u8],
        now: Instant,
        reply: &mut [u8],
    ) -> TcpOutcome {
        let inner = &mut self.inner;
        let mut outcome = match self.sessions.receive(usize::from(socket.0), data, now) {
            Some((
                Feed::Frame {
                    header,
                    frame,
                    consumed,
                },
                session,
            )) => TcpOutcome {
                consumed,
                ..inner.tcp_frame(session, &header, frame, now, reply)
            },
            Some((Feed::Buffered, _)) => TcpOutcome {
                consumed: data.len(),
                ..TcpOutcome::default()
            },
            Some((Feed::Skipped { consumed }, _)) => TcpOutcome {
                consumed,
                ..TcpOutcome::default()
            },
            Some((Feed::TooLong { header, consumed }, _)) => {
                encap::too_long(socket, &header, consumed, reply)
            }
            None => TcpOutcome {
                consumed: data.len(),
                close: true,
                ..TcpOutcome::default()
            },
        };
        // The Reset the frame's request accepted (or one an `execute` left untaken).
        outcome.reset = inner.objects.pending_reset.take();
        outcome
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
        let broadcast = self.inner.net.is_broadcast(to) || to.is_multicast();
        self.inner.udp_frame(from, broadcast, data, now, reply)
    }

    /// Writes a delayed ListIdentity reply that is due at `now` into `out`; returns its
    /// destination and length. Call until it returns `None`.
    pub fn poll_udp(&mut self, now: Instant, out: &mut [u8]) -> Option<(SocketAddrV4, usize)> {
        let p = self.inner.delayed.take_due(now)?;
        let len = self
            .inner
            .list_identity_reply(p.session_handle, p.sender_context, now, out);
        Some((p.to, len))
    }

    /// Feeds a datagram received on UDP 2222 (Class 1 O->T data) from `from`.
    pub fn io_receive(
        &mut self,
        from: SocketAddrV4,
        data: &[u8],
        now: Instant,
    ) -> Result<Accepted, Discard> {
        let inner = &mut self.inner;
        let r = consume::consume(&mut inner.connections, &mut inner.device, from, data, now);
        if r.is_ok() {
            inner.apply_input_changes();
        }
        r
    }

    /// Runs the device's own behaviour ([`Device::poll`]) at `now`, then triggers the inputs
    /// it says changed; returns when the device next wants to run.
    pub fn poll_device(&mut self, now: Instant) -> Option<Instant> {
        let next = self.inner.device.poll(now);
        self.inner.apply_input_changes();
        next
    }

    /// Closes every connection with `reason` (the runtime calls it with
    /// [`CloseReason::Reset`] before it performs an Identity Reset), telling the device of
    /// each.
    pub fn close_all(&mut self, reason: CloseReason) {
        let inner = &mut self.inner;
        inner.connections.close_all(reason, &mut inner.device);
    }

    /// Closes connections whose watchdog expired, then writes the most overdue T->O datagram
    /// into `out` (at least the largest input assembly plus 20 bytes) and returns its
    /// destination (UDP port 2222 of the originator or multicast group) and length. Call until
    /// it returns `None`, then sleep until [`Self::next_deadline`]. The same as
    /// [`Self::io_due`] then [`Self::write_io`] into `out`; `None`, changing nothing, if `out`
    /// is too short for the datagram due.
    pub fn poll_io(&mut self, now: Instant, out: &mut [u8]) -> Option<(SocketAddrV4, usize)> {
        let due = self.io_due(now)?;
        let len = self.write_io(due, now, Some(out));
        (len > 0).then_some((due.to, len))
    }

    /// Closes connections whose watchdog expired, then returns the most overdue T->O
    /// datagram, if one is due: its destination and largest length. Build it with
    /// [`Self::write_io`] straight into a transmit buffer of that length (or drop it with
    /// `write_io(due, now, None)` when there is nowhere to send it); call again until
    /// `None`, as with [`Self::poll_io`].
    pub fn io_due(&mut self, now: Instant) -> Option<IoDue> {
        let inner = &mut self.inner;
        inner.connections.expire(now, &mut inner.device);
        produce::next_due(&inner.connections, now)
    }

    /// Writes the T->O datagram `due` (from [`Self::io_due`], with no other call between)
    /// into `out`, which holds at least `due.max_len` bytes, and moves its connection to its
    /// next production; returns the datagram's length (the device may fill less than the
    /// connection's size). `out` `None` drops the datagram. Returns 0, changing nothing, if
    /// `out` is too short or the connection is gone.
    pub fn write_io(&mut self, due: IoDue, now: Instant, out: Option<&mut [u8]>) -> usize {
        let inner = &mut self.inner;
        produce::write(&mut inner.connections, &mut inner.device, due, now, out)
    }

    /// Tells the stack that input assembly `instance` has new data: change-of-state and
    /// application-triggered connections producing it send as soon as their inhibit time
    /// allows. (A device says the same from inside with [`Device::input_changes`].)
    pub fn trigger_input(&mut self, instance: u16) {
        self.inner.connections.trigger(instance);
    }

    /// The multicast group T->O data goes to while a multicast connection is open.
    pub fn multicast_group(&self) -> Option<Ipv4Addr> {
        let inner = &self.inner;
        inner.connections.produces_multicast().then(|| {
            inner
                .objects
                .tcpip
                .multicast_in_use(&inner.device, &inner.net)
                .0
        })
    }

    /// TTL for multicast T->O datagrams (TCP/IP attribute 8).
    pub fn multicast_ttl(&self) -> u8 {
        let inner = &self.inner;
        inner
            .objects
            .tcpip
            .multicast_in_use(&inner.device, &inner.net)
            .1
    }

    /// The next instant [`Self::poll_udp`] has a delayed reply to send.
    pub fn udp_deadline(&self) -> Option<Instant> {
        self.inner.delayed.next_due()
    }

    /// The next instant [`Self::poll_io`] has work: a production or a watchdog expiry.
    #[inline]
    pub fn io_deadline(&self) -> Option<Instant> {
        self.inner.connections.next_deadline()
    }

    /// The earliest of [`Self::udp_deadline`] and [`Self::io_deadline`].
    pub fn next_deadline(&self) -> Option<Instant> {
        match (self.udp_deadline(), self.io_deadline()) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }
}

impl<D: Device, const C: usize, const L: usize> Inner<D, C, L> {
    /// The service context for a request.
    pub(crate) fn ctx(&mut self, request: RequestContext, origin: Option<Origin>) -> Ctx<'_, D, C> {
        Ctx {
            device: &mut self.device,
            state: &mut self.objects,
            net: &self.net,
            connections: &mut self.connections,
            origin,
            reply_t_o_sockaddr: None,
            request,
            store: self.store.as_deref_mut(),
            #[cfg(feature = "cip-security")]
            csr: self.csr.as_deref_mut(),
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
fn trigger_changes<const C: usize>(
    connections: &mut ConnectionTable<C>,
    changes: &mut InputChanges,
) {
    if changes.all() {
        connections.trigger_all();
    } else {
        for instance in changes.iter() {
            connections.trigger(instance);
        }
    }
    changes.clear();
}
