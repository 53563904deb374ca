//! The adapter on the kernel's TCP/IP stack (`--bind A.B.C.D`): the same sans-IO
//! [`Adapter`] as on a TAP, driven from kernel sockets by one single-threaded event loop.
//!
//! Each turn of the loop does what is due (the device's clock, T->O production, delayed
//! ListIdentity replies, TCP deadlines), then waits in one `ppoll` ([`poll`]) until a socket
//! is ready or the next deadline, and serves what became ready. Sockets are non-blocking;
//! datagrams are received into one buffer and built into another, both allocated once;
//! nothing is allocated per Class 1 cycle. Files: [`tcp`] (sessions on 44818), [`udp`]
//! (UDP 44818), [`io`] (Class 1 on 2222), [`netif`] (the interface's configuration).

mod io;
mod netif;
mod poll;
mod session;
mod socket;
mod tcp;
mod udp;

use std::net::Ipv4Addr;
use std::process::exit;

use enip_stack::config::MAX_SESSIONS;
use enip_stack::objects::TcpIpState;
use enip_stack::{Adapter, Device, Instant};

use crate::netlink::Watch;
use crate::runner::{on_reset, seed};
use enip_stack::nv::SharedStore;
use io::Io;
use netif::Interface;
use poll::{Clock, PollSet};
use tcp::Tcp;
use udp::Udp;

/// Bytes of each datagram buffer: a whole Ethernet payload.
const DATAGRAM_LEN: usize = 1536;

/// Runs `device` on the kernel's sockets at `ip` until SIGINT or SIGTERM; a start-up error
/// (no interface with that address, a port in use) is printed and exits 1.
pub fn run<D: Device>(device: D, ip: Ipv4Addr, mut store: SharedStore, program: &str) -> ! {
    let fail = |e: String| -> ! {
        eprintln!("{program}: {e}");
        exit(1)
    };
    // Subscribed before the first read, so no change after it goes unnoticed (a veth's
    // carrier comes up a moment after the link is set up).
    let watch = Watch::open().unwrap_or_else(|e| fail(format!("cannot watch interfaces: {e}")));
    let iface = Interface::holding(ip).unwrap_or_else(|e| fail(e));
    warn_if_stored_elsewhere(&mut store, ip);
    let opened =
        (|| Ok::<_, std::io::Error>((Tcp::open(ip)?, Udp::open(ip, iface.index)?, Io::open(ip)?)))(
        );
    let (mut tcp, udp, io) = opened.unwrap_or_else(|e| fail(format!("cannot listen on {ip}: {e}")));
    let name = device.identity().product_name;
    let mut adapter = Adapter::new(device, iface.config, seed());
    if let Err(e) = adapter.attach_store(Box::leak(Box::new(store))) {
        log::error!("non-volatile store unreadable ({e}): factory TCP/IP settings");
    }
    // Explicit messaging's DSCP, as the device starts (QoS: it applies from a start); Class 1
    // datagrams get their connection's as they go ([`Io::produce`]).
    let dscp = adapter.explicit_dscp();
    tcp.set_dscp(dscp);
    if let Err(e) = udp.set_dscp(dscp) {
        log::warn!("udp {ip}: dscp {dscp}: {e}");
    }
    eprintln!(
        "{program}: listening on {ip} (kernel sockets on {}, link up {}, device {name:?})",
        iface.name, iface.config.link_up
    );
    let mut runtime = Runtime {
        adapter,
        clock: Clock,
        ip,
        iface,
        tcp,
        udp,
        io,
        watch,
        rx: Box::new([0; DATAGRAM_LEN]),
        tx: Box::new([0; DATAGRAM_LEN]),
        device_due: Some(Instant::from_micros(0)),
        poll: PollSet::new(),
        tcp_changed: true,
    };
    runtime.watch_fixed();
    runtime.io.track_multicast(&runtime.adapter);
    let mut now = runtime.clock.now();
    loop {
        match runtime.turn(now) {
            Ok(next) => now = next,
            Err(e) => fail(format!("waiting for sockets: {e}")),
        }
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

/// The adapter, its sockets, and the buffers of the loop.
struct Runtime<D: Device> {
    adapter: Adapter<D>,
    clock: Clock,
    ip: Ipv4Addr,
    iface: Interface,
    tcp: Tcp,
    udp: Udp,
    io: Io,
    watch: Watch,
    /// Every received datagram.
    rx: Box<[u8; DATAGRAM_LEN]>,
    /// Every datagram built: replies and T->O data.
    tx: Box<[u8; DATAGRAM_LEN]>,
    /// When the device's own clock next wants to run.
    device_due: Option<Instant>,
    poll: PollSet,
    /// The listener or a session changed since the poll set was last told.
    tcp_changed: bool,
}

/// Where each socket sits in the poll set: the fixed ones, then the listener and the
/// sessions.
const IO: usize = 0;
const UDP: usize = 1;
const BROADCAST: usize = 2;
const WATCH: usize = 3;
const LISTENER: usize = 4;
const SESSIONS: usize = 5;

impl<D: Device> Runtime<D> {
    /// One turn at `now`: what is due, one wait, what became ready; returns the instant
    /// the wait ended (the next turn's `now`).
    fn turn(&mut self, now: Instant) -> std::io::Result<Instant> {
        let connections = self.adapter.connections().len();
        let deadline = self.run_due(now);
        if self.tcp_changed {
            self.watch_tcp();
        }
        self.poll.wait(deadline.map(|at| poll::until(now, at)))?;
        let now = self.clock.now();
        let mut settings_may_change = self.serve_ready(now);
        settings_may_change |= self.adapter.connections().len() != connections;
        if settings_may_change {
            self.io.track_multicast(&self.adapter);
        }
        Ok(now)
    }

    /// Runs the device's clock, produces T->O data, sends delayed replies and checks TCP
    /// deadlines, as far as each is due at `now`; returns when the next of them is due.
    fn run_due(&mut self, now: Instant) -> Option<Instant> {
        let due = |at: Option<Instant>| at.is_some_and(|at| at <= now);
        if due(self.device_due) {
            self.device_due = self.adapter.poll_device(now);
        }
        let mut io = self.adapter.io_deadline();
        if due(io) {
            self.io
                .produce(&mut self.adapter, now, self.tx.as_mut_slice());
            io = self.adapter.io_deadline();
        }
        let mut udp = self.adapter.udp_deadline();
        if due(udp) {
            self.udp
                .send_due(&mut self.adapter, now, self.tx.as_mut_slice());
            udp = self.adapter.udp_deadline();
        }
        let mut tcp = self.tcp.next_deadline();
        if due(tcp) {
            self.tcp.check_deadlines(&mut self.adapter, now);
            self.tcp_changed = true;
            tcp = self.tcp.next_deadline();
        }
        [io, udp, self.device_due, tcp].into_iter().flatten().min()
    }

    /// Puts the sockets that live as long as the runtime in the poll set.
    fn watch_fixed(&mut self) {
        use std::os::fd::AsRawFd;
        let p = &mut self.poll;
        p.set(IO, Some(self.io.socket.as_raw_fd()), true, false);
        p.set(UDP, Some(self.udp.unicast.as_raw_fd()), true, false);
        p.set(BROADCAST, Some(self.udp.broadcast.as_raw_fd()), true, false);
        p.set(WATCH, Some(self.watch.fd()), true, false);
        self.watch_tcp();
    }

    /// Puts the listener and the sessions, as they are now, in the poll set.
    fn watch_tcp(&mut self) {
        self.poll.set(LISTENER, self.tcp.listener_fd(), true, false);
        for index in 0..MAX_SESSIONS {
            let i = self.tcp.interest(index);
            self.poll.set(
                SESSIONS + index,
                i.as_ref().map(|i| i.fd),
                i.as_ref().is_some_and(|i| i.read),
                i.as_ref().is_some_and(|i| i.write),
            );
        }
        self.tcp_changed = false;
    }

    /// Serves every socket the wait found ready; returns whether encapsulation frames were
    /// handled or the interface changed (either may change the multicast settings).
    fn serve_ready(&mut self, now: Instant) -> bool {
        let p = &self.poll;
        let (rx, tx) = (self.rx.as_mut_slice(), self.tx.as_mut_slice());
        // Class 1 first: it is the traffic with deadlines.
        if p.readable(IO) {
            self.io.consume(&mut self.adapter, now, rx);
        }
        if p.readable(UDP) {
            self.udp.serve_unicast(&mut self.adapter, now, rx, tx);
        }
        if p.readable(BROADCAST) {
            self.udp.serve_broadcast(&mut self.adapter, now, rx, tx);
        }
        let mut changed = false;
        for index in 0..MAX_SESSIONS {
            let (readable, writable) = (p.readable(SESSIONS + index), p.writable(SESSIONS + index));
            if readable || writable {
                self.tcp_changed = true;
                changed |=
                    self.tcp
                        .serve(index, readable, writable, &mut self.adapter, now, on_reset);
            }
        }
        if p.readable(LISTENER) {
            self.tcp.accept(&mut self.adapter, now);
            self.tcp_changed = true;
        }
        if p.readable(WATCH) {
            self.watch.drain(rx);
            changed |= self.refresh_interface();
        }
        changed
    }

    /// Reads the interface again after a netlink notification; true if it changed.
    fn refresh_interface(&mut self) -> bool {
        let now = self.iface.refreshed(self.ip);
        if now == self.iface {
            return false;
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
        true
    }
}
