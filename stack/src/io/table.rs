//! The fixed-size connection table: lookup, ID allocation, closing with dependants, and the
//! one owner of the connections' timing (watchdogs, last activity, production deadlines,
//! triggers, in `io/timing.rs`). The timing changes only through the table's intents (`open`,
//! `feed`, `produce`, `trigger`, `trigger_all`, `close`, `expire`), each of which keeps the
//! next deadline and the first producer right; readers have `expires`, `last_activity`,
//! `next_production` and `next_deadline`.

use super::connection::{Connection, Producer, Transport};
use super::timing::{Produces, Timing};
use crate::config::{MAX_CONNECTIONS, MAX_EXPLICIT_CONNECTED};
use crate::device::Trigger;
use crate::device::{CloseReason, ConnectionEvent, Device, Kind};
use crate::time::Instant;
use crate::wire::forward_open::Triad;

/// Socket index of a connection whose opening session has ended.
const NO_SESSION: u8 = u8::MAX;

/// Identity status bit 0: an exclusive owner holds the device.
const STATUS_OWNED: u16 = 0x0001;
/// Extended device status (bits 4-7): no I/O connection established.
const EXT_NO_IO: u16 = 3 << 4;
/// Extended device status: at least one I/O connection in run mode.
const EXT_RUN: u16 = 6 << 4;
/// Extended device status: I/O connections established, all idle.
const EXT_IDLE: u16 = 7 << 4;
/// Extended device status: at least one faulted I/O connection.
const EXT_FAULTED_IO: u16 = 2 << 4;

/// All connection slots.
#[derive(Debug, Clone)]
pub struct ConnectionTable<const C: usize = MAX_CONNECTIONS> {
    slots: [Option<Connection>; C],
    next_id: u32,
    owned: heapless::Vec<u16, C>,
    /// Per slot: the last Class 3 reply, resent when a request is repeated.
    replies: [heapless::Vec<u8, MAX_EXPLICIT_CONNECTED>; C],
    /// An exclusive owner timed out, and none has opened since.
    owner_timed_out: bool,
    timeouts: u16,
    /// Every slot's watchdog, last activity and production deadline, and which comes first:
    /// the only copy.
    timing: Timing<C>,
    /// One past the highest occupied slot: the watchdog scans stop there.
    used: usize,
    /// Some connection produces to a multicast group.
    multicast: bool,
}

impl<const C: usize> ConnectionTable<C> {
    /// Low bits of the connection IDs the adapter chooses: the table slot (4 for 10 slots).
    const SLOT_BITS: u32 = usize::BITS - C.saturating_sub(1).leading_zeros();
    /// The slot bits of a connection ID.
    const SLOT_MASK: u32 = (1 << Self::SLOT_BITS) - 1;

    /// An empty table; connection IDs start from `seed`.
    pub fn new(seed: u32) -> Self {
        const { assert!(C >= 1, "the connection table has at least one slot") };
        ConnectionTable {
            slots: [const { None }; C],
            next_id: seed,
            owned: heapless::Vec::new(),
            replies: [const { heapless::Vec::new() }; C],
            owner_timed_out: false,
            timeouts: 0,
            // The seed also sets the phase of the producers' grids, mixed: the phase a T->O
            // stream shows says nothing plain about the IDs to come.
            timing: Timing::new((seed.wrapping_mul(0x9E37_79B9) >> 16) as u16),
            used: 0,
            multicast: false,
        }
    }
    /// Open connections with their slot numbers.
    pub fn iter(&self) -> impl Iterator<Item = (usize, &Connection)> {
        self.slots
            .iter()
            .enumerate()
            .filter_map(|(i, c)| c.as_ref().map(|c| (i, c)))
    }
    /// The connection in `slot`.
    pub fn get(&self, slot: usize) -> Option<&Connection> {
        self.slots.get(slot).and_then(Option::as_ref)
    }
    /// The connection in `slot`, mutably: its sequence counts and run/idle state (its timing
    /// is the table's, changed only through the table's intents).
    pub(crate) fn get_mut(&mut self, slot: usize) -> Option<&mut Connection> {
        self.slots.get_mut(slot).and_then(Option::as_mut)
    }
    /// Number of open connections.
    pub fn len(&self) -> usize {
        self.iter().count()
    }
    /// True if some open connection produces to a multicast group.
    pub fn produces_multicast(&self) -> bool {
        self.multicast
    }
    /// True if no connection is open.
    pub fn is_empty(&self) -> bool {
        self.used == 0
    }
    /// Slot numbers that can hold a connection: those below the highest occupied one.
    pub(crate) fn slots_in_use(&self) -> core::ops::Range<usize> {
        0..self.used
    }
    /// The slot of the connection with `triad`.
    pub fn find_triad(&self, triad: &Triad) -> Option<usize> {
        self.iter().find(|(_, c)| c.triad == *triad).map(|(i, _)| i)
    }
    /// The slot of the connection consuming O->T connection ID `id`: the ID names its slot
    /// in its low bits ([`ConnectionTable::new_id`]), so no search.
    pub fn find_o_t(&self, id: u32) -> Option<usize> {
        let slot = (id & Self::SLOT_MASK) as usize;
        self.get(slot).filter(|c| c.o_t_id == id).map(|_| slot)
    }
    /// Like [`ConnectionTable::find_o_t`], with the connection to update.
    pub(crate) fn find_o_t_mut(&mut self, id: u32) -> Option<(usize, &mut Connection)> {
        let slot = (id & Self::SLOT_MASK) as usize;
        let conn = self.get_mut(slot).filter(|c| c.o_t_id == id)?;
        Some((slot, conn))
    }
    /// A fresh non-zero connection ID for the connection going into `slot`, that no open
    /// connection uses; its low bits are the slot.
    pub fn new_id(&mut self, slot: usize) -> u32 {
        loop {
            self.next_id = self.next_id.wrapping_add(1 << Self::SLOT_BITS);
            let id = (self.next_id & !Self::SLOT_MASK) | (slot as u32 & Self::SLOT_MASK);
            if id != 0 && !self.iter().any(|(_, c)| c.o_t_id == id || c.t_o_id == id) {
                return id;
            }
        }
    }
    /// When the watchdog of the connection in `slot` fires.
    pub fn expires(&self, slot: usize) -> Option<Instant> {
        self.get(slot).map(|_| self.timing.expires(slot))
    }
    /// When the connection in `slot` last heard from its originator (O->T data, a Class 3
    /// request), or when it opened; the session that opened it counts this as activity.
    pub fn last_activity(&self, slot: usize) -> Option<Instant> {
        self.get(slot).map(|_| self.timing.last_activity(slot))
    }
    /// When the producer of the connection in `slot` is next due: on its grid
    /// `previous + RPI` (a cyclic one's on the adapter's clock after its first production),
    /// or earlier once triggered (not before the inhibit time). `None`
    /// without a producer of its own.
    pub fn next_production(&self, slot: usize) -> Option<Instant> {
        self.get(slot)
            .and_then(Connection::producer)
            .map(|_| self.timing.next_production(slot))
    }
    /// The phase of the adapter's grid of `rpi` (microseconds, below `rpi`): a cyclic producer
    /// of that RPI produces at the instants `phase + k * rpi` of the adapter's clock from its
    /// second production on (its first is at once when it opens).
    pub fn grid_phase(&self, rpi: u32) -> u32 {
        self.timing.grid_phase(rpi)
    }
    /// The slot [`ConnectionTable::open`] will use next, if one is free.
    pub fn free_slot(&self) -> Option<usize> {
        self.slots.iter().position(Option::is_none)
    }
    /// Opens `conn` in a free slot at `now` and returns the slot; `None` (and `conn`
    /// dropped) if full. Its watchdog runs with the first-packet grace (its timeout, but at
    /// least [`crate::config::FIRST_PACKET_GRACE_US`]), and its producer, if it has its own,
    /// is due at once (a cyclic one then moves onto the adapter's grid of its RPI at its
    /// second production: `io/timing.rs`).
    pub fn open(&mut self, conn: Connection, now: Instant) -> Option<usize> {
        let slot = self.free_slot()?;
        let produces = match conn.producer().map(|p| p.trigger) {
            None => Produces::Nothing,
            Some(Trigger::Cyclic) => Produces::Cyclic,
            Some(_) => Produces::OnTrigger,
        };
        self.timing.open(slot, now, conn.timeout, produces);
        // An exclusive owner re-established: no timed-out one left to show.
        self.owner_timed_out &= conn.kind != Kind::ExclusiveOwner;
        if let Some(s) = self.slots.get_mut(slot) {
            *s = Some(conn);
        }
        self.used = self.used.max(slot.saturating_add(1));
        self.refresh_summary();
        Some(slot)
    }
    /// The originator of the connection in `slot` was heard at `now` (O->T data, a Class 3
    /// request): its watchdog restarts, to fire one timeout (multiplier x RPI) later.
    #[inline]
    pub(crate) fn feed(&mut self, slot: usize, now: Instant) {
        if let Some(c) = self.slots.get(slot).and_then(Option::as_ref) {
            self.timing.feed(slot, now, c.timeout);
        }
    }
    /// The slot of the producer due first at `now`, if one is due: the earliest deadline, the
    /// lowest slot of equal ones.
    #[inline]
    pub(crate) fn due(&self, now: Instant) -> Option<usize> {
        self.timing.due(now)
    }
    /// Produces the connection in `slot` (if its T->O ID is still `t_o_id`, when given) at
    /// `now`. `build` counts and builds the datagram from its producer, given its T->O ID and
    /// whether a trigger waits; when `build` returns `Some`, the producer moves on to its next
    /// deadline (the next point of its grid `previous + RPI`, or one RPI after a production
    /// that carried a trigger). `None`, with the timing unchanged, if there is no such
    /// producer or `build` declines.
    #[inline(always)]
    pub(crate) fn produce<R>(
        &mut self,
        slot: usize,
        t_o_id: Option<u32>,
        now: Instant,
        build: impl FnOnce(&mut Producer, u32, bool) -> Option<R>,
    ) -> Option<R> {
        let conn = self
            .slots
            .get_mut(slot)
            .and_then(Option::as_mut)
            .filter(|c| t_o_id.is_none_or(|id| c.t_o_id == id))?;
        let (rpi, t_o_id) = (conn.t_o_rpi, conn.t_o_id);
        let Transport::Class1 {
            producer: Some(p), ..
        } = &mut conn.transport
        else {
            return None;
        };
        let built = build(p, t_o_id, self.timing.triggered(slot))?;
        self.timing.produced(slot, now, rpi, p.inhibit);
        Some(built)
    }
    /// Input assembly `instance` has new data: its change-of-state and application-triggered
    /// producers go as soon as their inhibit time allows.
    pub(crate) fn trigger(&mut self, instance: u16) {
        self.trigger_where(|p| p.instance == instance);
    }
    /// Every input has new data: every change-of-state and application-triggered producer
    /// goes as soon as its inhibit time allows.
    pub(crate) fn trigger_all(&mut self) {
        self.trigger_where(|_| true);
    }
    /// The cached Class 3 reply of `slot`.
    pub fn cached_reply(&self, slot: usize) -> &[u8] {
        self.replies.get(slot).map_or(&[], |r| r.as_slice())
    }
    /// The Class 3 reply cache of `slot`, to refill.
    pub fn reply_cache_mut(
        &mut self,
        slot: usize,
    ) -> Option<&mut heapless::Vec<u8, MAX_EXPLICIT_CONNECTED>> {
        self.replies.get_mut(slot)
    }
    /// Output assembly instances held by exclusive owners.
    pub fn owned_outputs(&self) -> &[u16] {
        &self.owned
    }
    /// True if an exclusive owner connection timed out and no exclusive owner has opened
    /// since: extended device status 0010 and the Network Status indicator flashing red
    /// (Vol 2 9-4.2: until the timed-out connections are re-established).
    pub fn owner_timed_out(&self) -> bool {
        self.owner_timed_out
    }
    /// Identity status bits from the connections: owned, extended device status.
    pub fn identity_status(&self) -> u16 {
        let mut io = false;
        let mut run = false;
        for (_, c) in self.iter() {
            if let Transport::Class1 { consumer, .. } = &c.transport {
                io = true;
                run |= consumer.run;
            }
        }
        let owned = if self.owned.is_empty() {
            0
        } else {
            STATUS_OWNED
        };
        owned
            | match (self.owner_timed_out, io, run) {
                (true, _, _) => EXT_FAULTED_IO,
                (false, false, _) => EXT_NO_IO,
                (false, true, true) => EXT_RUN,
                (false, true, false) => EXT_IDLE,
            }
    }
    /// The earliest watchdog expiry or production deadline.
    pub fn next_deadline(&self) -> Option<Instant> {
        self.timing.next_deadline(self.used)
    }
    /// Closes the connection in `slot`, telling `device` when the last exclusive owner goes.
    /// A multicast production it shares with a connection that is not listen-only goes on in
    /// that one (same T->O ID, sequence counts and deadline); otherwise the connections that
    /// follow it close with it (only listen-only ones, unless its production was resized
    /// away: [`ConnectionTable::close_resized`]).
    pub fn close<D: Device>(&mut self, slot: usize, reason: CloseReason, device: &mut D) {
        self.close_with(slot, reason, false, device);
    }
    /// [`ConnectionTable::close`]; `production_gone` if what the connection produces no
    /// longer fits its assembly (the production then stops for every connection sharing it).
    fn close_with<D: Device>(
        &mut self,
        slot: usize,
        reason: CloseReason,
        production_gone: bool,
        device: &mut D,
    ) {
        let Some(conn) = self.slots.get_mut(slot).and_then(Option::take) else {
            return;
        };
        let multicast = conn.produces_multicast();
        let heir = match conn.producer() {
            // A production whose size no longer fits stops for all.
            Some(p) if multicast && !production_gone => {
                let heir = self.sharer(conn.t_o_id);
                if let Some(Transport::Class1 { producer, .. }) =
                    heir.and_then(|h| self.get_mut(h)).map(|c| &mut c.transport)
                {
                    *producer = Some(*p);
                }
                heir
            }
            _ => None,
        };
        if let Some(heir) = heir {
            self.timing.hand_over(slot, heir);
            info!("connection {} produces the multicast of {}", heir, slot);
        }
        self.timing.close(slot);
        info!(
            "connection {} closed ({:?} from {}): {}",
            slot,
            conn.kind,
            conn.originator,
            reason.describe()
        );
        device.connection_event(ConnectionEvent::Closed(conn.info(slot), reason));
        let had_owner = !self.owned.is_empty();
        if multicast && heir.is_none() {
            for i in self.slots_in_use() {
                let follows = |c: &mut Connection| c.follows() && c.t_o_id == conn.t_o_id;
                if let Some(c) = self.slots.get_mut(i).and_then(|s| s.take_if(follows)) {
                    self.timing.close(i);
                    info!(
                        "connection {} closed: {}",
                        i,
                        CloseReason::Dependency.describe()
                    );
                    let info = c.info(i);
                    device.connection_event(ConnectionEvent::Closed(info, CloseReason::Dependency));
                }
            }
        }
        self.refresh_summary();
        self.used = self
            .slots
            .iter()
            .rposition(Option::is_some)
            .map_or(0, |i| i.saturating_add(1));
        if had_owner && self.owned.is_empty() {
            device.connection_event(ConnectionEvent::OwnershipLost(reason));
        }
    }
    /// The first connection that is not listen-only following the multicast production of
    /// T->O ID `t_o_id`.
    fn sharer(&self, t_o_id: u32) -> Option<usize> {
        self.iter()
            .find(|(_, c)| c.follows() && c.kind != Kind::ListenOnly && c.t_o_id == t_o_id)
            .map(|(i, _)| i)
    }
    /// Closes every open connection with `reason`.
    pub fn close_all<D: Device>(&mut self, reason: CloseReason, device: &mut D) {
        for slot in self.slots_in_use() {
            self.close(slot, reason, device);
        }
    }
    /// Closes the Class 1 connections whose consumed or produced assembly can no longer carry
    /// the size they opened with ([`CloseReason::Reconfigured`]).
    pub fn close_resized<D: Device>(&mut self, device: &mut D) {
        for slot in self.slots_in_use() {
            let Some(c) = self.get(slot) else {
                continue;
            };
            let differs = |instance: u16, size: u16| {
                device
                    .assemblies()
                    .iter()
                    .find(|a| a.instance == instance)
                    .is_none_or(|a| {
                        size > a.size || !device.accepts_connection_size(a, usize::from(size))
                    })
            };
            let consumed = c
                .consumer()
                .is_some_and(|k| k.size > 0 && differs(k.instance, k.size));
            let produced = c.producer().is_some_and(|p| differs(p.instance, p.size));
            if consumed || produced {
                // Only a production that no longer fits stops for the connections sharing
                // it; one whose producer goes for its output goes on in a sharer.
                self.close_with(slot, CloseReason::Reconfigured, produced, device);
            }
        }
    }
    /// Closes every connection whose watchdog expired by `now`; returns how many.
    pub fn expire<D: Device>(&mut self, now: Instant, device: &mut D) -> usize {
        if !self.timing.may_expire(now) {
            return 0;
        }
        let mut closed = 0usize;
        for slot in self.slots_in_use() {
            if !self.timing.expired(slot, now) {
                continue;
            }
            if let Some(owner) = self.get(slot).map(|c| c.kind == Kind::ExclusiveOwner) {
                if owner {
                    self.owner_timed_out = true;
                }
                self.timeouts = self.timeouts.wrapping_add(1);
                self.close(slot, CloseReason::Timeout, device);
                closed = closed.saturating_add(1);
            }
        }
        self.timing.swept();
        closed
    }
    /// Connections of any kind closed by their watchdog (Connection Manager attribute 8).
    pub fn timeouts(&self) -> u16 {
        self.timeouts
    }
    /// The latest traffic on connections opened through the session on socket `socket`.
    pub fn last_activity_of_session(&self, socket: u8) -> Option<Instant> {
        self.iter()
            .filter(|(_, c)| c.socket == socket)
            .map(|(slot, _)| self.timing.last_activity(slot))
            .max()
    }
    /// Closes the Class 3 connections of the session on socket `socket`; its Class 1
    /// connections stay open, detached from it.
    pub fn close_session<D: Device>(&mut self, socket: u8, device: &mut D) {
        for slot in self.slots_in_use() {
            let Some(conn) = self.get_mut(slot).filter(|c| c.socket == socket) else {
                continue;
            };
            if matches!(conn.transport, Transport::Class3 { .. }) {
                self.close(slot, CloseReason::SessionClosed, device);
            } else {
                // Class 1 goes on without its session, and keeps no later session alive.
                conn.socket = NO_SESSION;
            }
        }
    }

    /// Triggers the change-of-state and application-triggered producers that `pick` chooses.
    fn trigger_where(&mut self, pick: impl Fn(&Producer) -> bool) {
        let slots = self.slots.get(..self.used).unwrap_or(&self.slots);
        for (slot, conn) in slots.iter().enumerate() {
            let producer = conn.as_ref().and_then(Connection::producer);
            if producer.is_some_and(|p| p.trigger != Trigger::Cyclic && pick(p)) {
                self.timing.trigger(slot);
            }
        }
    }
    /// Recomputes what the open connections add up to (after an open or a close): the owned
    /// outputs, and whether any produces multicast.
    fn refresh_summary(&mut self) {
        self.owned.clear();
        let multicast = self.iter().any(|(_, c)| c.produces_multicast());
        self.multicast = multicast;
        for slot in self.slots.iter().flatten() {
            if let (Kind::ExclusiveOwner, Some(c)) = (slot.kind, slot.consumer()) {
                // Cannot fail: at most one entry per slot.
                let _ = self.owned.push(c.instance);
            }
        }
    }
}

#[cfg(test)]
mod tests;
