//! The fixed-size connection table: lookup, ID allocation, closing with dependants.

use super::connection::{Connection, Producer, Transport};
use super::schedule::Schedule;
use crate::config::{MAX_CONNECTIONS, MAX_EXPLICIT_CONNECTED};
use crate::device::{CloseReason, ConnectionEvent, Device, Kind};
use crate::time::Instant;
use crate::wire::forward_open::Triad;

/// Low bits of the connection IDs the adapter chooses: the table slot.
const SLOT_BITS: u32 = 4;
const SLOT_MASK: u32 = (1 << SLOT_BITS) - 1;
const _: () = assert!(
    MAX_CONNECTIONS <= 1 << SLOT_BITS,
    "slots must fit in the ID's low bits"
);

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

/// All connection slots.
#[derive(Debug, Clone)]
pub struct ConnectionTable {
    slots: [Option<Connection>; MAX_CONNECTIONS],
    next_id: u32,
    owned: heapless::Vec<u16, MAX_CONNECTIONS>,
    /// Per slot: the last Class 3 reply, resent when a request is repeated.
    replies: [heapless::Vec<u8, MAX_EXPLICIT_CONNECTED>; MAX_CONNECTIONS],
    /// Exclusive-owner connections closed by their watchdog so far (wrapping).
    owner_timeouts: u32,
    timeouts: u16,
    /// When each producer is next due, and which comes first.
    schedule: Schedule,
    /// Per slot: when its watchdog fires (`Instant::NEVER` for an empty slot); mirrors
    /// [`Connection::expires`], kept by `insert` and [`ConnectionTable::set_expiry`].
    expiry: [Instant; MAX_CONNECTIONS],
    /// No watchdog fires before this instant: a lower bound that every move of an expiry
    /// keeps, so [`ConnectionTable::expire`] looks at the slots only once it is reached, and
    /// [`ConnectionTable::next_deadline`] only while it is not after the next production.
    expiry_bound: Instant,
    /// One past the highest occupied slot: the watchdog scans stop there.
    used: usize,
    /// Some connection produces to a multicast group.
    multicast: bool,
}

impl ConnectionTable {
    /// An empty table; connection IDs start from `seed`.
    pub fn new(seed: u32) -> Self {
        ConnectionTable {
            slots: [const { None }; MAX_CONNECTIONS],
            next_id: seed,
            owned: heapless::Vec::new(),
            replies: [const { heapless::Vec::new() }; MAX_CONNECTIONS],
            owner_timeouts: 0,
            timeouts: 0,
            schedule: Schedule::new(),
            expiry: [Instant::NEVER; MAX_CONNECTIONS],
            expiry_bound: Instant::NEVER,
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
    /// The connection in `slot`, mutably.
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
        let slot = (id & SLOT_MASK) as usize;
        self.get(slot).filter(|c| c.o_t_id == id).map(|_| slot)
    }
    /// Like [`ConnectionTable::find_o_t`], with the connection to update.
    pub(crate) fn find_o_t_mut(&mut self, id: u32) -> Option<(usize, &mut Connection)> {
        let slot = (id & SLOT_MASK) as usize;
        let conn = self.get_mut(slot).filter(|c| c.o_t_id == id)?;
        Some((slot, conn))
    }
    /// A fresh non-zero connection ID for the connection going into `slot`, that no open
    /// connection uses; its low bits are the slot.
    pub fn new_id(&mut self, slot: usize) -> u32 {
        loop {
            self.next_id = self.next_id.wrapping_add(1 << SLOT_BITS);
            let id = (self.next_id & !SLOT_MASK) | (slot as u32 & SLOT_MASK);
            if id != 0 && !self.iter().any(|(_, c)| c.o_t_id == id || c.t_o_id == id) {
                return id;
            }
        }
    }
    /// The watchdog of the connection in `slot` (whose [`Connection::expires`] the caller
    /// just moved) now fires `at`: traffic can bring it earlier than the first-packet grace.
    pub(crate) fn set_expiry(&mut self, slot: usize, at: Instant) {
        if let Some(e) = self.expiry.get_mut(slot) {
            *e = at;
        }
        self.expiry_bound = self.expiry_bound.min(at);
    }
    /// The producer in `slot` is next due `at` (produced, triggered, opened, closed).
    pub(crate) fn set_due(&mut self, slot: usize, at: Instant) {
        self.schedule.set(slot, at);
    }
    /// The producer due first, and when: the lowest slot of the earliest deadline
    /// (`Instant::NEVER` if none produces).
    pub(crate) fn next_producer(&self) -> (usize, Instant) {
        self.schedule.first()
    }
    /// The slot [`ConnectionTable::insert`] will use next, if one is free.
    pub fn free_slot(&self) -> Option<usize> {
        self.slots.iter().position(Option::is_none)
    }
    /// Stores `conn` in a free slot and returns it; `None` (and `conn` dropped) if full.
    pub fn insert(&mut self, conn: Connection) -> Option<usize> {
        let slot = self.free_slot()?;
        if let Some(e) = self.expiry.get_mut(slot) {
            *e = conn.expires;
        }
        self.expiry_bound = self.expiry_bound.min(conn.expires);
        if let Some(s) = self.slots.get_mut(slot) {
            *s = Some(conn);
        }
        self.used = self.used.max(slot.saturating_add(1));
        let due = self
            .get(slot)
            .and_then(Connection::producer)
            .map(Producer::due_at);
        self.set_due(slot, due.unwrap_or(Instant::NEVER));
        self.refresh_summary();
        Some(slot)
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
            | match (io, run) {
                (false, _) => EXT_NO_IO,
                (true, true) => EXT_RUN,
                (true, false) => EXT_IDLE,
            }
    }
    /// The earliest watchdog expiry or production deadline.
    pub fn next_deadline(&self) -> Option<Instant> {
        // No watchdog fires before `expiry_bound`: while that is after the next production,
        // the production is the answer and the expiries need no look.
        let (_, production) = self.schedule.first();
        let at = if production < self.expiry_bound {
            production
        } else {
            let expiry = self.expiry.get(..self.used).unwrap_or(&self.expiry);
            expiry.iter().fold(production, |a, &b| a.min(b))
        };
        (at != Instant::NEVER).then_some(at)
    }
    /// Closes the connection in `slot` and the listen-only connections that follow its
    /// production, telling `device` when the last exclusive owner goes.
    pub fn close<D: Device>(&mut self, slot: usize, reason: CloseReason, device: &mut D) {
        let Some(conn) = self.slots.get_mut(slot).and_then(Option::take) else {
            return;
        };
        self.clear_deadlines(slot);
        info!(
            "connection {} closed ({:?} from {}): {}",
            slot,
            conn.kind,
            conn.originator,
            reason.describe()
        );
        device.connection_event(ConnectionEvent::Closed(conn.info(slot), reason));
        let had_owner = !self.owned.is_empty();
        if conn.producer().is_some() {
            for i in self.slots_in_use() {
                let follows = |c: &mut Connection| {
                    c.kind == Kind::ListenOnly && c.t_o_id == conn.t_o_id && c.producer().is_none()
                };
                if let Some(c) = self.slots.get_mut(i).and_then(|s| s.take_if(follows)) {
                    self.clear_deadlines(i);
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
            let resized = self.get(slot).is_some_and(|c| {
                let differs = |instance: u16, size: u16| {
                    device
                        .assemblies()
                        .iter()
                        .find(|a| a.instance == instance)
                        .is_none_or(|a| {
                            size > a.size || !device.accepts_connection_size(a, usize::from(size))
                        })
                };
                c.consumer()
                    .is_some_and(|k| k.size > 0 && differs(k.instance, k.size))
                    || c.producer().is_some_and(|p| differs(p.instance, p.size))
            });
            if resized {
                self.close(slot, CloseReason::Reconfigured, device);
            }
        }
    }
    /// Closes every connection whose watchdog expired by `now`; returns how many.
    pub fn expire<D: Device>(&mut self, now: Instant, device: &mut D) -> usize {
        if now < self.expiry_bound {
            return 0;
        }
        let mut closed = 0usize;
        for slot in self.slots_in_use() {
            if self.expiry.get(slot).is_none_or(|&at| at > now) {
                continue;
            }
            if let Some(owner) = self.get(slot).map(|c| c.kind == Kind::ExclusiveOwner) {
                if owner {
                    self.owner_timeouts = self.owner_timeouts.wrapping_add(1);
                }
                self.timeouts = self.timeouts.wrapping_add(1);
                self.close(slot, CloseReason::Timeout, device);
                closed = closed.saturating_add(1);
            }
        }
        self.expiry_bound = self.expiry.iter().copied().min().unwrap_or(Instant::NEVER);
        closed
    }
    /// Exclusive-owner connections closed by their watchdog since start-up (wrapping): what
    /// the Network Status indicator shows as a connection timeout.
    pub fn owner_timeouts(&self) -> u32 {
        self.owner_timeouts
    }
    /// Connections of any kind closed by their watchdog (Connection Manager attribute 8).
    pub fn timeouts(&self) -> u16 {
        self.timeouts
    }
    /// The latest traffic on connections opened through the session on socket `socket`.
    pub fn last_activity_of_session(&self, socket: u8) -> Option<Instant> {
        self.iter()
            .filter(|(_, c)| c.socket == socket)
            .map(|(_, c)| c.last_activity)
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

    /// An emptied slot is never due and never expires.
    fn clear_deadlines(&mut self, slot: usize) {
        if let Some(e) = self.expiry.get_mut(slot) {
            *e = Instant::NEVER;
        }
        self.set_due(slot, Instant::NEVER);
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
