//! The adapter shared between the runtime's tasks on one single-threaded executor: the
//! wake-up that tells the link task its deadline moved, the note that the multicast group
//! may have changed, the encapsulation port's TCP, and its Class 1, TCP and LLDP calls as an
//! [`IoPort`] and [`LldpPort`].

use core::cell::{Cell, RefCell};
use core::net::SocketAddrV4;
use core::task::Waker;

use embassy_sync::blocking_mutex::raw::NoopRawMutex;
use embassy_sync::blocking_mutex::Mutex;
use embassy_sync::signal::Signal;
use enip_stack::config::{
    MAX_CONNECTIONS, MAX_ENCAP_FRAME, MAX_PENDING_LIST_IDENTITY, MAX_SESSIONS,
};
use enip_stack::device::CloseReason;
use enip_stack::objects::LinkCounters;
use enip_stack::tcp::{Outgoing, Segment, TcpServer};
use enip_stack::{Adapter, Device, Instant, IoDue, NetworkConfig};
use static_cell::StaticCell;

use crate::clock::earliest;
use crate::link::KeptWaker;
use crate::link::{IoPort, LldpPort};

/// An [`Adapter`] shared by the runtime's futures and the link task; never borrowed across
/// an `.await`. Laid out in order (`repr(C)`): the adapter first, the TCP server's replies
/// last, so the Class 1 path's offsets into the adapter stay small.
#[repr(C)]
pub struct SharedAdapter<
    D: Device,
    const S: usize = { MAX_SESSIONS },
    const C: usize = { MAX_CONNECTIONS },
    const F: usize = { MAX_ENCAP_FRAME },
    const L: usize = { MAX_PENDING_LIST_IDENTITY },
> {
    adapter: Mutex<NoopRawMutex, RefCell<Adapter<D, S, C, F, L>>>,
    /// Set when a call brought the I/O deadline forward; the link task's waker.
    io_moved: Cell<bool>,
    io_waker: KeptWaker,
    /// Signalled when the multicast group T->O data goes to may have changed.
    membership: Signal<NoopRawMutex, ()>,
    /// The encapsulation port's TCP (the link task's): its connections are the adapter's
    /// sessions.
    tcp: RefCell<TcpServer<S, F>>,
    /// Signalled with the type of an Identity Reset whose reply went out.
    reset: Signal<NoopRawMutex, u8>,
}

/// Wraps `adapter` for [`crate::run`] and the link task.
pub fn share<D: Device, const S: usize, const C: usize, const F: usize, const L: usize>(
    adapter: Adapter<D, S, C, F, L>,
) -> SharedAdapter<D, S, C, F, L> {
    SharedAdapter {
        adapter: Mutex::new(RefCell::new(adapter)),
        io_moved: Cell::new(false),
        io_waker: KeptWaker::new(),
        membership: Signal::new(),
        tcp: RefCell::new(TcpServer::new(0)),
        reset: Signal::new(),
    }
}

/// A `static` home for the shared adapter: the link task is a task of its own and needs it
/// for the whole run. A firmware declares one for its device type, e.g.
/// `static ADAPTER: AdapterCell<MyDevice> = AdapterCell::new();`, and hands it to its board.
pub struct AdapterCell<
    D: Device,
    const S: usize = { MAX_SESSIONS },
    const C: usize = { MAX_CONNECTIONS },
    const F: usize = { MAX_ENCAP_FRAME },
    const L: usize = { MAX_PENDING_LIST_IDENTITY },
>(StaticCell<SharedAdapter<D, S, C, F, L>>);

impl<D: Device, const S: usize, const C: usize, const F: usize, const L: usize>
    AdapterCell<D, S, C, F, L>
{
    /// An empty cell.
    pub const fn new() -> Self {
        AdapterCell(StaticCell::new())
    }

    /// Shares the adapter `build` makes for the rest of the program; `None`, and `build` not
    /// called, if the cell was used before. The adapter and the TCP server are built on the
    /// stack before they move into the cell (about 44 KiB deep with the default capacities on
    /// a Cortex-M): call it from a function of its own, not inlined into a task's `async`
    /// body, so that depth is the stack's only while it runs.
    pub fn share(
        &'static self,
        build: impl FnOnce() -> Adapter<D, S, C, F, L>,
    ) -> Option<&'static SharedAdapter<D, S, C, F, L>> {
        self.0.try_init_with(|| share(build())).map(|a| &*a)
    }
}

impl<D: Device, const S: usize, const C: usize, const F: usize, const L: usize> Default
    for AdapterCell<D, S, C, F, L>
{
    fn default() -> Self {
        Self::new()
    }
}

/// Runs `f` with exclusive access to the shared adapter. If `f` brought the link task's
/// deadline forward (a Forward_Open, a trigger, an LLDP change), the link task is woken to
/// honour it; if it changed the multicast group, the runtime joins the new one.
///
/// The borrow cannot be taken twice: every caller returns before its next `.await`, and the
/// executor runs one task at a time.
pub fn with_adapter<
    D: Device,
    const S: usize,
    const C: usize,
    const F: usize,
    const L: usize,
    R,
>(
    shared: &SharedAdapter<D, S, C, F, L>,
    f: impl FnOnce(&mut Adapter<D, S, C, F, L>) -> R,
) -> R {
    let before = shared.watch();
    let r = with_adapter_quiet(shared, f);
    shared.notice(before);
    r
}

/// What [`with_adapter`] compares before and after its call: the link task's deadline and
/// the multicast group.
type Watched = (Option<Instant>, Option<core::net::Ipv4Addr>);

impl<D: Device, const S: usize, const C: usize, const F: usize, const L: usize>
    SharedAdapter<D, S, C, F, L>
{
    /// What [`with_adapter`] watches, now. Never inlined, nor [`Self::notice`]: one copy for
    /// every caller of `with_adapter` (a closure each), none on the Class 1 path.
    #[inline(never)]
    fn watch(&self) -> Watched {
        with_adapter_quiet(self, |a| (link_deadline(a), a.multicast_group()))
    }

    /// Wakes the link task if the deadline came forward since `before`, and signals a
    /// changed multicast group.
    #[inline(never)]
    fn notice(&self, before: Watched) {
        let (deadline, group) = self.watch();
        if earlier(deadline, before.0) {
            self.io_moved.set(true);
            self.io_waker.wake();
        }
        if group != before.1 {
            self.membership.signal(());
        }
    }
}

/// Like [`with_adapter`] without the wake-ups: for the link task and the indicators.
pub(crate) fn with_adapter_quiet<
    D: Device,
    const S: usize,
    const C: usize,
    const F: usize,
    const L: usize,
    R,
>(
    shared: &SharedAdapter<D, S, C, F, L>,
    f: impl FnOnce(&mut Adapter<D, S, C, F, L>) -> R,
) -> R {
    shared.adapter.lock(|cell| f(&mut cell.borrow_mut()))
}

/// Waits until the multicast group may have changed.
pub(crate) async fn membership_changed<
    D: Device,
    const S: usize,
    const C: usize,
    const F: usize,
    const L: usize,
>(
    shared: &SharedAdapter<D, S, C, F, L>,
) {
    shared.membership.wait().await
}

impl<D: Device, const S: usize, const C: usize, const F: usize, const L: usize> IoPort
    for SharedAdapter<D, S, C, F, L>
{
    fn interface(&self) -> NetworkConfig {
        with_adapter_quiet(self, |a| *a.network())
    }

    fn receive(&self, from: SocketAddrV4, data: &[u8], now: Instant) -> Option<Instant> {
        with_adapter_quiet(self, |a| {
            // A discarded datagram is counted by the adapter; nothing to answer.
            let _ = a.io_receive(from, data, now);
            a.io_deadline()
        })
    }

    fn due(&self, now: Instant) -> Result<IoDue, Option<Instant>> {
        let (due, expired) = with_adapter_quiet(self, |a| {
            let before = a.connections().timeouts();
            let due = a.io_due(now).ok_or_else(|| a.io_deadline());
            (due, a.connections().timeouts() != before)
        });
        if expired {
            // A multicast connection may have been the last.
            self.membership.signal(());
        }
        due
    }

    fn write(&self, due: &IoDue, now: Instant, out: Option<&mut [u8]>) -> usize {
        with_adapter_quiet(self, |a| a.write_io(*due, now, out))
    }

    fn deadline(&self) -> Option<Instant> {
        with_adapter_quiet(self, |a| a.io_deadline())
    }

    fn multicast_ttl(&self) -> u8 {
        with_adapter_quiet(self, |a| a.multicast_ttl())
    }

    fn explicit_dscp(&self) -> u8 {
        with_adapter_quiet(self, |a| a.explicit_dscp())
    }

    fn tls_port_open(&self) -> bool {
        with_adapter_quiet(self, |a| a.tls_port_open())
    }

    fn add_link_counters(&self, counted: &LinkCounters) {
        with_adapter_quiet(self, |a| a.add_link_counters(counted))
    }

    fn watch_deadline(&self, waker: &Waker) {
        self.io_waker.register(waker);
    }

    fn deadline_moved(&self) -> bool {
        self.io_moved.replace(false)
    }

    fn tcp_seed(&self, seed: u64) {
        self.tcp.borrow_mut().seed(seed);
    }

    fn tcp_segment(&self, segment: &Segment<'_>, now: Instant) -> Option<Outgoing> {
        let mut tcp = self.tcp.borrow_mut();
        let answer = with_adapter(self, |a| tcp.process(segment, now, a));
        self.hand_over_reset(&mut tcp);
        answer
    }

    fn tcp_poll(&self, now: Instant) {
        let mut tcp = self.tcp.borrow_mut();
        with_adapter(self, |a| tcp.poll(now, a));
        self.hand_over_reset(&mut tcp);
    }

    fn tcp_deadline(&self) -> Option<Instant> {
        let tcp = self.tcp.borrow();
        with_adapter_quiet(self, |a| tcp.deadline(a))
    }

    fn tcp_owes(&self) -> bool {
        self.tcp.borrow().owes()
    }

    fn tcp_transmit(&self, now: Instant, send: &mut dyn FnMut(&Outgoing, &[u8])) -> bool {
        let mut tcp = self.tcp.borrow_mut();
        let Some(segment) = tcp.transmit(now) else {
            return false;
        };
        send(&segment.segment, segment.payload);
        true
    }
}

impl<D: Device, const S: usize, const C: usize, const F: usize, const L: usize>
    SharedAdapter<D, S, C, F, L>
{
    /// Waits for an Identity Reset whose reply went out (its connections are closed): its
    /// type.
    pub(crate) async fn reset_requested(&self) -> u8 {
        self.reset.wait().await
    }

    /// An Identity Reset whose reply went out: every connection closes, and [`crate::run`]
    /// performs it.
    fn hand_over_reset(&self, tcp: &mut TcpServer<S, F>) {
        if let Some(kind) = tcp.take_reset() {
            info!("identity reset type {} requested", kind);
            with_adapter(self, |a| a.close_all(CloseReason::Reset));
            self.reset.signal(kind);
        }
    }
}

impl<D: Device, const S: usize, const C: usize, const F: usize, const L: usize> LldpPort
    for SharedAdapter<D, S, C, F, L>
{
    fn lldp_receive(&self, lldpdu: &[u8], now: Instant) {
        with_adapter_quiet(self, |a| a.lldp_receive(lldpdu, now));
    }

    fn lldp_transmit(&self, now: Instant, out: &mut [u8]) -> usize {
        with_adapter_quiet(self, |a| a.lldp_transmit(now, out))
    }

    fn lldp_shutdown(&self, out: &mut [u8]) -> usize {
        with_adapter_quiet(self, |a| a.lldp_shutdown(out))
    }

    fn lldp_deadline(&self) -> Option<Instant> {
        with_adapter_quiet(self, |a| a.lldp_deadline())
    }

    fn lldp_link_up(&self) {
        with_adapter_quiet(self, |a| a.lldp_link_up());
    }
}

/// The link task's next deadline: a production, a watchdog expiry or an LLDPDU.
fn link_deadline<D: Device, const S: usize, const C: usize, const F: usize, const L: usize>(
    a: &Adapter<D, S, C, F, L>,
) -> Option<Instant> {
    earliest(a.io_deadline(), a.lldp_deadline())
}

/// True if deadline `a` comes before `b` (`None` is never).
fn earlier(a: Option<Instant>, b: Option<Instant>) -> bool {
    match (a, b) {
        (Some(a), Some(b)) => a < b,
        (Some(_), None) => true,
        (None, _) => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn earlier_treats_none_as_never() {
        assert!(earlier(Some(Instant(1)), None));
        assert!(earlier(Some(Instant(1)), Some(Instant(2))));
        assert!(!earlier(Some(Instant(2)), Some(Instant(2))));
        assert!(!earlier(None, Some(Instant(2))));
    }
}
