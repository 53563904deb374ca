//! [`Node`]: one device on the kernel's sockets at its own address: its [`Adapter`], its
//! sockets, the deadlines of its clock, Class 1 production, delayed replies and TCP, and
//! what it does when one of its sockets is ready or one of its deadlines is due. The loop of
//! [`super::fleet`] drives any number of them, each only when something of its own happens.

use std::net::Ipv4Addr;
use std::os::fd::AsRawFd;

use enip_stack::config::MAX_SESSIONS;
use enip_stack::nv::SharedStore;
use enip_stack::objects::TcpIpState;
use enip_stack::{Adapter, Device, Instant};

use super::io::Io;
use super::netif::Interface;
use super::poll::Epoll;
use super::session::Interest;
use super::tcp::Tcp;
use super::udp::Udp;
use crate::runner::{on_reset, seed};

/// Where each socket of a node sits among its keys: the fixed ones, then the listener and
/// the sessions.
const IO: u32 = 0;
const UDP: u32 = 1;
const BROADCAST: u32 = 2;
const LISTENER: u32 = 3;
const TLS_LISTENER: u32 = 4;
const SESSIONS: u32 = 5;
/// Keys per node: node `i`'s sockets have keys `i * SLOTS + slot`.
pub const SLOTS: u64 = SESSIONS as u64 + MAX_SESSIONS as u64;
// The ready sockets of a node are kept as bits of a `u32`.
const _: () = assert!(SLOTS <= 32);

/// How late past its I/O deadline a node must be woken for the loop to count it a stall of
/// the process, µs.
const STALL_US: u64 = 2_000;
/// O->T datagrams read at most after a stall, before the deadline's work.
const STALL_DRAIN: usize = 64;

/// What a node is made of before it opens its sockets.
pub struct Spec<D> {
    /// Its name in the log (none for a lone device: its lines are not prefixed).
    pub label: Option<&'static str>,
    /// The local address it serves at.
    pub ip: Ipv4Addr,
    /// The device.
    pub device: D,
    /// Its non-volatile store.
    pub store: SharedStore,
    /// EtherNet/IP over TLS on 2221 and the CIP Security objects (`--tls`).
    pub tls: Option<crate::options::TlsOptions>,
}

/// One device on its own address, and the state of its share of the loop.
pub struct Node<D: Device> {
    /// Its name in the log.
    pub label: Option<&'static str>,
    adapter: Adapter<D>,
    ip: Ipv4Addr,
    iface: Interface,
    tcp: Tcp,
    udp: Udp,
    io: Io,
    /// When the device's own clock next wants to run.
    device_due: Option<Instant>,
    /// What the epoll set was last told of each TCP slot's descriptor (a level-triggered
    /// set needs telling only of a change).
    watched: [Option<Interest>; SLOTS as usize],
    /// The deadline the loop holds for this node, if any.
    pub queued: Option<Instant>,
    /// A socket of it is ready and it is on the loop's list to wake.
    pub woken: bool,
    /// Sockets found readable since last served, one bit per slot.
    readable: u32,
    /// Sockets found writable since last served.
    writable: u32,
}

impl<D: Device> Node<D> {
    /// Opens the sockets of `spec` at its address, or says why it cannot.
    pub fn open(spec: Spec<D>) -> Result<Self, String> {
        let Spec {
            label,
            ip,
            device,
            mut store,
            tls,
        } = spec;
        let iface = Interface::holding(ip)?;
        warn_if_stored_elsewhere(&mut store, ip);
        let name = device.identity().product_name;
        #[cfg(feature = "tls")]
        let tls = tls_server(ip, tls.as_ref(), name)?;
        #[cfg(not(feature = "tls"))]
        no_tls(tls.as_ref(), name)?;
        let opened = (|| {
            let tcp = Tcp::open(
                ip,
                #[cfg(feature = "tls")]
                tls,
            )?;
            Ok::<_, std::io::Error>((tcp, Udp::open(ip, iface.index)?, Io::open(ip)?))
        })();
        let (mut tcp, udp, io) = opened.map_err(|e| format!("cannot listen on {ip}: {e}"))?;
        let mut adapter = Adapter::new(device, iface.config, seed());
        if let Err(e) = adapter.attach_store(Box::leak(Box::new(store))) {
            log::error!("non-volatile store unreadable ({e}): factory TCP/IP settings");
        }
        #[cfg(feature = "tls")]
        if let Some(t) = tcp.tls() {
            adapter.enable_security(true);
            t.material().report(&mut adapter);
            match t.material().csr_signer() {
                Ok(signer) => adapter.attach_csr_signer(Box::leak(Box::new(signer))),
                Err(e) => log::error!("certificates for Create_CSR and the File object: {e}"),
            }
        }
        #[cfg(feature = "tls")]
        let closed =
            tcp.tls().is_some() && adapter.security(Instant::from_micros(0)).plain_tcp_closed;
        #[cfg(feature = "tls")]
        tcp.set_plain_closed(closed, &mut adapter, Instant::from_micros(0));
        // Explicit messaging's DSCP, as the device starts (QoS: it applies from a start);
        // Class 1 datagrams get their connection's as they go ([`Io::produce`]).
        let dscp = adapter.explicit_dscp();
        tcp.set_dscp(dscp);
        if let Err(e) = udp.set_dscp(dscp) {
            log::warn!("udp {ip}: dscp {dscp}: {e}");
        }
        let mut node = Node {
            label,
            adapter,
            ip,
            iface,
            tcp,
            udp,
            io,
            device_due: Some(Instant::from_micros(0)),
            watched: [None; SLOTS as usize],
            queued: None,
            woken: false,
            readable: 0,
            writable: 0,
        };
        node.io.track_multicast(&node.adapter);
        Ok(node)
    }

    /// The line saying where it listens.
    pub fn listening(&self) -> String {
        let name = self.adapter.device().identity().product_name;
        let tls = if self.tcp.tls_listener_fd().is_some() {
            ", TLS on 2221"
        } else {
            ""
        };
        format!(
            "listening on {} (kernel sockets on {}, link up {}, device {name:?}{tls})",
            self.ip, self.iface.name, self.iface.config.link_up
        )
    }

    /// Puts the sockets that live as long as the node in `epoll`, under keys from `base`.
    pub fn register(&mut self, epoll: &Epoll, base: u64) -> std::io::Result<()> {
        epoll.watch(
            self.io.socket.as_raw_fd(),
            base + u64::from(IO),
            true,
            false,
        )?;
        epoll.watch(
            self.udp.unicast.as_raw_fd(),
            base + u64::from(UDP),
            true,
            false,
        )?;
        let broadcast = self.udp.broadcast.as_raw_fd();
        epoll.watch(broadcast, base + u64::from(BROADCAST), true, false)?;
        self.watch_tcp(epoll, base);
        Ok(())
    }

    /// Notes that the socket at `slot` is ready (`slot` below [`SLOTS`]).
    pub fn mark(&mut self, slot: u64, readable: bool, writable: bool) {
        let bit = 1u32.checked_shl(slot as u32).unwrap_or(0);
        if readable {
            self.readable |= bit;
        }
        if writable {
            self.writable |= bit;
        }
    }

    /// Serves what became ready, then runs what is due at `now`; returns when the node next
    /// has something due. `rx` and `tx` are the loop's datagram buffers.
    pub fn wake(
        &mut self,
        epoll: &Epoll,
        base: u64,
        now: Instant,
        rx: &mut [u8],
        tx: &mut [u8],
    ) -> Option<Instant> {
        let connections = self.adapter.connections().len();
        let mut settings_may_change = self.serve_ready(now, rx, tx);
        #[cfg(feature = "tls")]
        if settings_may_change {
            self.follow_port_admin(now);
        }
        let next = self.run_due(now, rx, tx);
        settings_may_change |= self.adapter.connections().len() != connections;
        if settings_may_change {
            self.io.track_multicast(&self.adapter);
        }
        if self.tcp.needs_watch() {
            self.watch_tcp(epoll, base);
        }
        next
    }

    /// Runs the device's clock, produces T->O data, sends delayed replies and checks TCP
    /// deadlines, as far as each is due at `now`; returns when the next of them is due. After
    /// a stall it reads the waiting O->T data into `rx` first.
    fn run_due(&mut self, now: Instant, rx: &mut [u8], tx: &mut [u8]) -> Option<Instant> {
        let due = |at: Option<Instant>| at.is_some_and(|at| at <= now);
        if due(self.device_due) {
            self.device_due = self.adapter.poll_device(now);
        }
        let mut io = self.adapter.io_deadline();
        if io.is_some_and(|at| now.as_micros() > at.as_micros().saturating_add(STALL_US)) {
            // Woken this late, the process was not scheduled: the O->T data that arrived
            // meanwhile goes in before the connections' watchdogs are judged.
            for _ in 0..STALL_DRAIN {
                if !self.io.consume(&mut self.adapter, now, rx) {
                    break;
                }
            }
            io = self.adapter.io_deadline();
        }
        if due(io) {
            self.io.produce(&mut self.adapter, now, tx);
            io = self.adapter.io_deadline();
        }
        let mut udp = self.adapter.udp_deadline();
        if due(udp) {
            self.udp.send_due(&mut self.adapter, now, tx);
            udp = self.adapter.udp_deadline();
        }
        let mut tcp = self.tcp.next_deadline();
        if due(tcp) {
            self.tcp.check_deadlines(&mut self.adapter, now);
            tcp = self.tcp.next_deadline();
        }
        [io, udp, self.device_due, tcp].into_iter().flatten().min()
    }

    /// Closes or opens 44818 as TCP/IP Set_Port_Admin_State last said (only with `--tls`).
    #[cfg(feature = "tls")]
    fn follow_port_admin(&mut self, now: Instant) {
        if self.tcp.tls().is_none() {
            return;
        }
        let closed = self.adapter.security(now).plain_tcp_closed;
        self.tcp.set_plain_closed(closed, &mut self.adapter, now);
    }

    /// Puts the listener and the sessions, as they are now, in `epoll` (a closed one left by
    /// itself): only what changed since the set was last told.
    fn watch_tcp(&mut self, epoll: &Epoll, base: u64) {
        if self.tcp.watched() {
            self.watched = [None; SLOTS as usize];
        }
        let listening = |fd| Interest {
            fd,
            read: true,
            write: false,
        };
        let interests = [
            (LISTENER, self.tcp.listener_fd().map(listening)),
            (TLS_LISTENER, self.tcp.tls_listener_fd().map(listening)),
        ]
        .into_iter()
        .chain(
            (0..MAX_SESSIONS)
                .zip(SESSIONS..)
                .map(|(index, slot)| (slot, self.tcp.interest(index))),
        );
        for (slot, interest) in interests {
            let Some(want) = interest else {
                continue;
            };
            let Some(watched) = self.watched.get_mut(slot as usize) else {
                continue;
            };
            if *watched == Some(want) {
                continue;
            }
            *watched = None;
            match epoll.watch(want.fd, base + u64::from(slot), want.read, want.write) {
                Ok(()) => *watched = Some(want),
                Err(e) => log::error!("tcp {}: cannot wait on a socket: {e}", self.ip),
            }
        }
    }

    /// Serves every socket found ready; returns whether encapsulation frames were handled
    /// (which may change the multicast settings).
    fn serve_ready(&mut self, now: Instant, rx: &mut [u8], tx: &mut [u8]) -> bool {
        let (readable, writable) = (self.readable, self.writable);
        if readable | writable == 0 {
            return false;
        }
        (self.readable, self.writable) = (0, 0);
        let is = |mask: u32, slot: u32| mask & (1 << slot) != 0;
        // Class 1 first: it is the traffic with deadlines.
        if is(readable, IO) {
            self.io.consume(&mut self.adapter, now, rx);
        }
        if is(readable, UDP) {
            self.udp.serve_unicast(&mut self.adapter, now, rx, tx);
        }
        if is(readable, BROADCAST) {
            self.udp.serve_broadcast(&mut self.adapter, now, rx, tx);
        }
        let mut changed = false;
        for (index, slot) in (0..MAX_SESSIONS).zip(SESSIONS..) {
            let (r, w) = (is(readable, slot), is(writable, slot));
            if r || w {
                changed |= self
                    .tcp
                    .serve(index, r, w, &mut self.adapter, now, on_reset);
            }
        }
        for (key, tls) in [(LISTENER, false), (TLS_LISTENER, true)] {
            if is(readable, key) {
                self.tcp.accept(&mut self.adapter, now, tls);
            }
        }
        changed
    }

    /// Reads the interface again after a netlink notification, and applies a change.
    pub fn refresh_interface(&mut self) {
        let now = self.iface.refreshed(self.ip);
        if now == self.iface {
            return;
        }
        let old = *self.adapter.network();
        if old.ip != now.config.ip || old.link_up != now.config.link_up {
            log::info!(
                "interface {}: ip {}, link up {}",
                now.name,
                now.config.ip,
                now.config.link_up
            );
        }
        self.adapter.set_network(enip_stack::NetworkConfig {
            dhcp: old.dhcp,
            link_speed_mbps: old.link_speed_mbps,
            ..now.config
        });
        self.iface = now;
        self.io.track_multicast(&self.adapter);
    }
}

/// A static interface configuration stored by a scanner cannot be applied to the kernel's
/// interface: says so when it names another address.
fn warn_if_stored_elsewhere(store: &mut SharedStore, ip: Ipv4Addr) {
    let stored = TcpIpState::stored(store).ok().flatten();
    if let Some(i) = stored.as_ref().and_then(|st| st.static_interface()) {
        if i.ip != ip {
            log::warn!(
                "the stored TCP/IP configuration names {}; on kernel sockets the adapter \
                 serves at {ip} (set the kernel's address to change it)",
                i.ip
            );
        }
    }
}

/// The TLS listener on 2221 of `ip` with the certificates `options` names.
#[cfg(feature = "tls")]
fn tls_server(
    ip: Ipv4Addr,
    options: Option<&crate::options::TlsOptions>,
    name: &str,
) -> Result<Option<super::tcp::TlsServer>, String> {
    let Some(o) = options else {
        return Ok(None);
    };
    let material = super::tls::Material::load(o, o.factory_cert.as_deref(), name)?;
    super::tcp::TlsServer::open(ip, material)
        .map(Some)
        .map_err(|e| format!("cannot listen on {ip}:2221: {e}"))
}

/// Without the `tls` feature there is no TLS listener: `--tls` is an error.
#[cfg(not(feature = "tls"))]
fn no_tls(options: Option<&crate::options::TlsOptions>, _name: &str) -> Result<(), String> {
    match options {
        Some(_) => Err("--tls: this program is built without the `tls` feature".into()),
        None => Ok(()),
    }
}
