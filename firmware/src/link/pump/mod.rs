//! The link task's loop: it owns the board's Ethernet driver. Each wake-up it reads the
//! received frames, hands O->T datagrams and LLDPDUs straight to the adapter and every other
//! frame to the network stack, sends the stack's frames, writes each T->O datagram that is
//! due straight into the driver's transmit buffer behind its headers, and sends the LLDPDU
//! that is due (`link/lldp.rs`); Address Conflict Detection ([`super::acd`]) sees every ARP
//! message, sends its own, and holds the rest back until the address may be used. It sleeps
//! until the adapter's next production, watchdog expiry or LLDPDU, the next probe or
//! announcement, a frame, or another task's wake-up.

mod others;
use core::convert::Infallible;
use core::future::poll_fn;
use core::task::{Context, Poll, Waker};

use embassy_net_driver::{Checksum, Driver, HardwareAddress, LinkState, RxToken, TxToken};
use enip_stack::acd::ARP_FRAME_LEN;
use enip_stack::config::MAX_CONNECTIONS;
use enip_stack::{Instant, IoDue, NetworkConfig};
use smoltcp::phy::{Checksum as Sums, ChecksumCapabilities};

use super::acd::Guard;
use super::alarm::{LinkAlarm, TimeQueue};
use super::counted::Counted;
use super::flood_guard::FloodGuard;
use super::frame::{self, send_copy, ARP_REQUEST_LEN, HEADERS_LEN};
use super::frames::LinkFrames;
use super::io_port::IoPort;
use super::lldp;
use super::neighbors::{next_hop, Neighbors};
use super::route::{Headers, LastRoute, UNICAST_TTL};
use super::stack_hold::StackHold;
use super::stack_sums::LinkChecksums;
use super::tcp_link::TcpLink;
use crate::clock::{earliest, now, to_embassy};

/// Passes of receive, send and produce in one wake-up at most (then the task yields to the
/// others and runs again).
const PASSES: usize = 4;
/// Frames read from the driver in one round: the O->T data of the default ten connections
/// arriving together, and two more, before the pass produces what is due (with eight, such a
/// burst took two passes, about 20 instructions a cycle more at ten connections).
const RX_BURST: usize = 12;

/// [`run`]'s and [`run_with_link_checksums`]'s body: a `Pump` polled at every wake-up. A
/// macro, not an async function both await: that one's future would hold the driver (the
/// LAN9118's with its frame buffers) beside the caller's own copy of its argument.
macro_rules! pump_forever {
    ($stack_sums:literal, $driver:ident, $frames:ident, $io:ident, $alarm:expr) => {{
        let mut pump = Pump::<$stack_sums>::new(&$driver, $io, $alarm);
        let mut driver = Counted::new(&mut $driver, pump.mac);
        let never: Infallible = poll_fn(|cx| {
            pump.poll(cx, &mut driver, $frames, $io);
            if !$frames.rx.is_empty() {
                driver.hand_over(|counted| $io.add_link_counters(counted));
            }
            Poll::Pending
        })
        .await;
        match never {}
    }};
}

/// Runs the link task forever: `driver` is the board's, `frames` the queues shared with the
/// [`super::NetDriver`] given to embassy-net, `io` the adapter. The task wakes at its
/// deadlines through embassy-time ([`TimeQueue`]).
pub async fn run<D: Driver>(mut driver: D, frames: &LinkFrames, io: &dyn IoPort) -> ! {
    pump_forever!(false, driver, frames, io, &TimeQueue)
}

/// Like [`run`], and the link task verifies and fills the network stack's checksums in its
/// place (`stack_sums`); `proof` says the stack was told so
/// ([`super::NetDriver::with_link_checksums`]). Its own `Pump` type: a board that does not
/// ask compiles none of it. The task wakes at its deadlines through `alarm` (the board's own,
/// or [`TimeQueue`]).
pub async fn run_with_link_checksums<D: Driver>(
    mut driver: D,
    frames: &LinkFrames,
    io: &dyn IoPort,
    proof: LinkChecksums,
    alarm: &dyn LinkAlarm,
) -> ! {
    let LinkChecksums(()) = proof;
    pump_forever!(true, driver, frames, io, alarm)
}

/// The link task's state between wake-ups; it does the network stack's checksums if
/// `STACK_SUMS`.
struct Pump<'a, const STACK_SUMS: bool> {
    mac: [u8; 6],
    /// Checksums software verifies on receive and fills on send (what the driver leaves):
    /// the Class 1 frames' and, if `STACK_SUMS`, the stack's.
    sums: ChecksumCapabilities,
    neighbors: Neighbors,
    /// The headers of the last T->O datagram's route.
    last_route: LastRoute,
    /// Address Conflict Detection of the interface address.
    guard: Guard,
    /// The adapter's next production or watchdog expiry as last learned: until then (and
    /// unless [`Self::io_stale`]) a pass does not ask the adapter what is due.
    io_next: Option<Instant>,
    /// Another task may have brought [`Self::io_next`] forward (`IoPort::deadline_moved`):
    /// the next pass asks the adapter.
    io_stale: bool,
    /// A T->O datagram is due but the driver had no room: its wake-up comes from the driver.
    blocked: bool,
    /// The adapter's LLDP deadline as last asked (`lldp::service`).
    lldp_next: Option<Instant>,
    /// The LLDP deadline may have moved: asked again at the next pass.
    lldp_stale: bool,
    /// Drops flood frames on their way to the stack.
    flood_guard: FloodGuard,
    /// The task's waker as given to the wake-ups kept across polls (the stack's frames, the
    /// adapter's deadline); given again only if it changed.
    waker: Option<Waker>,
    /// How long the task waits for the stack to take a frame from its full queue.
    stack_hold: StackHold,
    /// Wakes the task at its next deadline.
    alarm: &'a dyn LinkAlarm,
    /// The encapsulation TCP's segments and timers.
    tcp: TcpLink,
    /// The earliest deadline of the rare work (Address Conflict Detection, LLDP, the
    /// encapsulation TCP's timers, the stack's hold) when it was last served.
    others_next: Option<Instant>,
    /// Something besides Class 1 happened since the rare work was last served (a frame for
    /// the stack or the TCP, an ARP message or LLDPDU, a new waker, link state or interface
    /// address): the next pass serves it and learns [`Self::others_next`] anew.
    others_stale: bool,
    /// The alarm keeps the deadline asked ([`LinkAlarm::keeps_deadline`]).
    alarm_keeps: bool,
    /// The deadline last asked of an alarm that keeps it.
    asked: Option<Instant>,
}

impl<'a, const STACK_SUMS: bool> Pump<'a, STACK_SUMS> {
    fn new(driver: &impl Driver, io: &dyn IoPort, alarm: &'a dyn LinkAlarm) -> Self {
        let caps = driver.capabilities();
        let mut sums = ChecksumCapabilities::default();
        sums.ipv4 = software(caps.checksum.ipv4);
        sums.udp = software(caps.checksum.udp);
        // The encapsulation port's TCP segments are the link task's.
        sums.tcp = software(caps.checksum.tcp);
        if STACK_SUMS {
            sums.icmpv4 = software(caps.checksum.icmpv4);
        }
        #[allow(unreachable_patterns)] // other media exist only with other driver features
        let mac = match driver.hardware_address() {
            HardwareAddress::Ethernet(mac) => mac,
            _ => [0; 6],
        };
        // Two devices powered up together must not probe in step: their MACs differ.
        let seed = mac
            .iter()
            .fold(now().as_micros(), |s, b| s.rotate_left(8) ^ u64::from(*b));
        io.tcp_seed(seed.rotate_left(32) ^ 0x5851_F42D_4C95_7F2D);
        Pump {
            mac,
            sums,
            neighbors: Neighbors::default(),
            last_route: LastRoute::default(),
            guard: Guard::new(mac, seed),
            io_next: None,
            io_stale: true,
            blocked: false,
            lldp_next: None,
            lldp_stale: true,
            flood_guard: FloodGuard::default(),
            waker: None,
            stack_hold: StackHold::default(),
            alarm,
            tcp: TcpLink::default(),
            others_next: None,
            others_stale: true,
            alarm_keeps: alarm.keeps_deadline(),
            asked: None,
        }
    }

    /// One wake-up. Never inlined: `cargo xtask bench` names the link task's own work by it.
    #[inline(never)]
    fn poll<D: Driver>(
        &mut self,
        cx: &mut Context<'_>,
        driver: &mut D,
        frames: &LinkFrames,
        io: &dyn IoPort,
    ) {
        let link = driver.link_state(cx);
        let up = link == LinkState::Up;
        if link != frames.link_state() {
            if up {
                io.lldp_link_up();
                self.lldp_stale = true;
            }
            frames.set_link_state(link);
            self.others_stale = true;
        }
        if !self.waker.as_ref().is_some_and(|w| w.will_wake(cx.waker())) {
            self.keep_waker(cx.waker(), frames, io);
            // Everything that wakes the task learns the new waker.
            self.others_stale = true;
            self.asked = None;
        }
        // Another task brought the deadline forward (a Forward_Open, a trigger): asked at once
        // in this wake-up's first pass. Only other tasks move it, and none runs meanwhile.
        if io.deadline_moved() {
            self.io_stale = true;
        }
        let me = io.interface();
        let mut at = now();
        // A new address to probe, or the link's change for Address Conflict Detection.
        self.others_stale |= !self.guard.follows(me.ip, up);
        // Each pass handles what is ready; another runs only if the driver had more to read
        // than a burst or a production came due meanwhile (an input the O->T data changed).
        let mut settled = false;
        for pass in 0..PASSES {
            if pass > 0 {
                at = now();
            }
            settled = self.pass(cx, driver, frames, io, (&me, up), at);
            if settled {
                break;
            }
        }
        if !settled {
            cx.waker().wake_by_ref();
        }
    }

    /// Gives `waker` to the stack's frame queues and the adapter, which keep it: they wake
    /// the task when the stack queues a frame or another task brings the deadline forward.
    #[inline(never)]
    fn keep_waker(&mut self, waker: &Waker, frames: &LinkFrames, io: &dyn IoPort) {
        frames.register_link(waker);
        io.watch_deadline(waker);
        self.waker = Some(waker.clone());
    }

    /// One pass at `at` for the interface `me` (its link up or not): receives, sends and
    /// produces what is ready, then arms the timer; true if nothing is left to do now. The
    /// rare work is served only if something besides Class 1 happened or its deadline came:
    /// a Class 1 wake-up pays a few comparisons for it. Out of line: the wake-up's loop
    /// around it holds few values.
    #[inline(never)]
    fn pass<D: Driver>(
        &mut self,
        cx: &mut Context<'_>,
        driver: &mut D,
        frames: &LinkFrames,
        io: &dyn IoPort,
        (me, up): (&NetworkConfig, bool),
        at: Instant,
    ) -> bool {
        let more_frames = self.receive(cx, driver, frames, io, me, at);
        self.blocked = false;
        if self.others_stale
            || !frames.tx.is_empty()
            || self.tcp.due(at)
            || self.others_next.is_some_and(|d| d <= at)
        {
            self.serve_others(cx, driver, frames, io, (me, up), at);
        }
        // The adapter is asked only when the deadline last learned has come or another task
        // may have moved it: a wake-up for a received frame pays a comparison.
        let io_next = if self.io_stale || self.io_next.is_some_and(|next| next <= at) {
            self.produce(cx, driver, io, me, at)
        } else {
            self.io_next
        };
        let deadline = earliest(io_next, self.others_next);
        !more_frames && self.sleep_until(deadline, at, cx)
    }

    /// Reads what the driver received; true if it read a whole burst (more may wait).
    fn receive<D: Driver>(
        &mut self,
        cx: &mut Context<'_>,
        driver: &mut D,
        frames: &LinkFrames,
        io: &dyn IoPort,
        me: &NetworkConfig,
        at: Instant,
    ) -> bool {
        let mut passed = false;
        let mut whole_burst = true;
        for _ in 0..RX_BURST {
            // A full queue waits for the stack, which wakes this task when it takes a frame,
            // for a while at most each time the stack falls behind (`StackHold`).
            let frame = self
                .stack_hold
                .may_read(frames.rx.is_full(), frames.rx.is_empty(), at)
                .then(|| driver.receive(cx))
                .flatten();
            let Some((rx, _)) = frame else {
                whole_burst = false;
                break;
            };
            passed |= rx.consume(|frame| self.ingest(frame, frames, io, me, at));
        }
        if passed {
            frames.wake_stack();
        }
        whole_burst
    }

    /// One received frame: O->T data to the adapter, anything else to the stack (true), and
    /// its sender learned if it was taken in. Out of line: the frame's temporaries are set up
    /// only when a frame came, not in every pass.
    #[inline(never)]
    fn ingest(
        &mut self,
        frame: &[u8],
        frames: &LinkFrames,
        io: &dyn IoPort,
        me: &NetworkConfig,
        at: Instant,
    ) -> bool {
        // IPv4 (Class 1) first: the ethertype alone rules out LLDP and ARP.
        if !frame::is_ipv4(frame) {
            if let Some(lldpdu) = lldp::lldpdu(frame) {
                // A new neighbour may bring the next LLDPDU forward: rare work.
                self.others_stale = true;
                io.lldp_receive(lldpdu, at);
                return false;
            }
            self.guard.receive(frame, io, at);
        }
        let seen = frame::inspect(frame, me.ip, &self.sums);
        let o_t = seen
            .o_t
            .and_then(|(from, range)| Some((from, frame.get(range)?)));
        // The sender's MAC is learned from a frame taken in (an O->T datagram or a TCP
        // segment, whose checksums held) or an ARP message about us, never from one dropped
        // as corrupt or unwanted: such a frame from a host's address must not turn its T->O
        // data elsewhere. Learned after the O->T data reached the device, not on its way
        // there; before any T->O datagram or TCP segment of this wake-up goes out.
        if let Some((from, data)) = o_t {
            // The data may have triggered a production: the deadline is learned anew.
            self.io_next = io.receive(from, data, at);
            if let Some((ip, mac)) = seen.sender {
                self.neighbors.learn(ip, mac);
            }
            return false;
        }
        // Anything but O->T data (ARP too) is rare work.
        self.others_stale = true;
        let (passed, taken) = self.other_frame(frame, seen.sender.is_some(), frames, io, me, at);
        if let Some((ip, mac)) = seen.sender.filter(|_| taken || !frame::is_ipv4(frame)) {
            self.neighbors.learn(ip, mac);
        }
        passed
    }

    /// Asks for the LLDP deadline again and sends the LLDPDU due at `at` (`lldp::service`).
    #[inline(never)]
    fn send_lldp<D: Driver>(
        &mut self,
        cx: &mut Context<'_>,
        driver: &mut D,
        io: &dyn IoPort,
        at: Instant,
    ) {
        let stale = core::mem::take(&mut self.lldp_stale);
        let next = &mut self.lldp_next;
        self.blocked |= lldp::service(cx, driver, io, self.mac, at, next, stale);
    }

    /// Sends the probe or announcement due at `at`, if the driver has room.
    #[inline(never)]
    fn send_acd_frame<D: Driver>(&mut self, cx: &mut Context<'_>, driver: &mut D, at: Instant) {
        let Some(arp) = self.guard.due(at) else {
            return;
        };
        match driver.transmit(cx) {
            Some(tx) => {
                let mut frame = [0u8; ARP_FRAME_LEN];
                arp.write(self.mac, self.guard.ip(), &mut frame);
                send_copy(tx, &frame);
            }
            None => self.guard.put_back(arp),
        }
    }

    /// Sends (or drops) every T->O datagram due at `at`; learns and returns the adapter's next
    /// deadline. Out of line, with the loop inside: the datagrams' temporaries are set up
    /// only when one is due, once for all of them.
    #[inline(never)]
    fn produce<D: Driver>(
        &mut self,
        cx: &mut Context<'_>,
        driver: &mut D,
        io: &dyn IoPort,
        me: &NetworkConfig,
        at: Instant,
    ) -> Option<Instant> {
        self.io_stale = false;
        let usable = self.guard.usable();
        // Bounded: each round sends or drops one datagram, and each producer is due once.
        for _ in 0..MAX_CONNECTIONS.saturating_mul(2) {
            let due = match io.due(at) {
                Ok(due) => due,
                // Nothing more due: the answer says when the next is.
                Err(next) => {
                    self.io_next = next;
                    return next;
                }
            };
            if !self.send_due(cx, driver, io, (me, usable), &due, at) {
                self.blocked = true;
                break;
            }
        }
        // The driver had no room, or the bound was reached: asked apart.
        self.io_next = io.deadline();
        self.io_next
    }

    /// Sends (or drops) the T->O datagram `due` at `at` from the interface `me` (its address
    /// usable or not); false if the driver had no room.
    #[inline(always)]
    fn send_due<D: Driver>(
        &mut self,
        cx: &mut Context<'_>,
        driver: &mut D,
        io: &dyn IoPort,
        (me, usable): (&NetworkConfig, bool),
        due: &IoDue,
        at: Instant,
    ) -> bool {
        if !usable {
            // Not from an address that may be in conflict: dropped.
            io.write(due, at, None);
            return true;
        }
        let Some(tx) = driver.transmit(cx) else {
            return false;
        };
        let to = *due.to.ip();
        let ttl = if to.is_multicast() {
            io.multicast_ttl()
        } else {
            UNICAST_TTL
        };
        let route = (due.to, due.dscp, ttl);
        let Some(headers) = self
            .last_route
            .headers((&self.mac, me), route, &mut self.neighbors)
        else {
            // Nobody to send it to yet: dropped, and the next hop asked for by ARP.
            io.write(due, at, None);
            if self.neighbors.may_ask(at) {
                let hop = next_hop(to, me.ip, me.netmask, me.gateway);
                let mut request = [0u8; ARP_REQUEST_LEN];
                frame::write_arp_request(&mut request, (self.mac, me.ip), hop);
                send_copy(tx, &request);
            }
            return true;
        };
        let len = HEADERS_LEN.saturating_add(due.max_len);
        tx.consume(len, |buf| write_t_o(buf, io, due, headers, &self.sums, at));
        true
    }

    /// Asks for a wake-up at `deadline`; false if it is due already at `at` (the pass's
    /// start) and nothing blocks it (the caller then runs another pass).
    ///
    /// Asked at every pass that sleeps, even if the deadline stayed: embassy-time
    /// ([`TimeQueue`]) keeps one expiry per task, the earliest asked since it last fired,
    /// and the driver may ask for wake-ups of its own on this task (`PolledLink`'s next
    /// read, the TAP's read retry). One of those firing first takes the task out of the
    /// queue, the link task's deadline with it: a deadline asked once and then skipped could
    /// be missed (the fifth step of issue 23 skipped it, and was taken back for this). A
    /// deadline passed meanwhile wakes the task at once. An alarm that keeps its deadline
    /// ([`LinkAlarm::keeps_deadline`], a slot of its own) is asked only when it changed.
    fn sleep_until(
        &mut self,
        deadline: Option<Instant>,
        at: Instant,
        cx: &mut Context<'_>,
    ) -> bool {
        let Some(deadline) = deadline else {
            return true;
        };
        if self.blocked {
            // Due, but waiting for the driver's room: its wake-up comes first.
            return true;
        }
        if at >= deadline {
            return false;
        }
        if self.asked == Some(deadline) {
            return true;
        }
        if self.alarm_keeps {
            self.asked = Some(deadline);
        }
        self.alarm
            .wake_at(to_embassy(deadline).as_ticks(), cx.waker());
        true
    }
}

/// Writes the T->O datagram `due` into `buf`: the adapter's payload, then `headers` (with
/// the checksums `sums` says software fills).
fn write_t_o(
    buf: &mut [u8],
    io: &dyn IoPort,
    due: &IoDue,
    headers: &Headers,
    sums: &ChecksumCapabilities,
    at: Instant,
) {
    let Some(payload) = buf.get_mut(HEADERS_LEN..) else {
        io.write(due, at, None);
        return;
    };
    let len = io.write(due, at, Some(&mut *payload));
    if len == 0 {
        // The driver's buffer was short of the connection's size: dropped.
        io.write(due, at, None);
    }
    // The device may fill less than the connection's size: the rest is padding.
    if let Some(rest) = payload.get_mut(len..).filter(|rest| !rest.is_empty()) {
        rest.fill(0);
    }
    headers.write(buf, len, sums);
}

/// What software does about a checksum the driver does `hardware` about.
fn software(hardware: Checksum) -> Sums {
    match hardware {
        // The driver computes and checks it: software neither.
        Checksum::None => Sums::None,
        Checksum::Tx => Sums::Tx,
        Checksum::Rx => Sums::Rx,
        Checksum::Both => Sums::Both,
    }
}
