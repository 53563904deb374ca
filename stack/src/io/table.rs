//! The fixed-size connection table: lookup, ID allocation, closing with dependants.

use super::connection::{Connection, Kind, Transport};
use crate::config::{MAX_CONNECTIONS, MAX_EXPLICIT_CONNECTED};
use crate::device::{CloseReason, ConnectionEvent, ConnectionInfo, Device};
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
    /// No producer is due before this instant: exact after each production scan, lowered
    /// when a connection opens or a producer is triggered.
    pub(crate) production_bound: Instant,
    /// No watchdog expires before this instant. Traffic only moves an expiry later, so it
    /// stays a lower bound until a connection is inserted; [`ConnectionTable::expire`]
    /// rescans only once it is reached.
    expiry_bound: Instant,
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
            expiry_bound: Instant(u64::MAX),
            production_bound: Instant(u64::MAX),
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
    /// True if no connection is open.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
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
    /// A watchdog was moved to `at` (traffic on a connection): the table's bound on the
    /// earliest expiry follows it down.
    pub(crate) fn note_expiry(&mut self, at: Instant) {
        self.expiry_bound = self.expiry_bound.min(at);
    }
    /// The slot [`ConnectionTable::insert`] will use next, if one is free.
    pub fn free_slot(&self) -> Option<usize> {
        self.slots.iter().position(Option::is_none)
    }
    /// Stores `conn` in a free slot and returns it; `None` (and `conn` dropped) if full.
    pub fn insert(&mut self, conn: Connection) -> Option<usize> {
        let slot = self.free_slot()?;
        self.expiry_bound = self.expiry_bound.min(conn.expires);
        if let Some(p) = conn.producer() {
            self.production_bound = self.production_bound.min(p.due_at());
        }
        if let Some(s) = self.slots.get_mut(slot) {
            *s = Some(conn);
        }
        self.refresh_owned();
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
        self.iter()
            .flat_map(|(_, c)| [Some(c.expires), c.producer().map(|p| p.due_at())])
            .flatten()
            .min()
    }
    /// Closes the connection in `slot` and the listen-only connections that follow its
    /// production, telling `device` when the last exclusive owner goes.
    pub fn close<D: Device>(&mut self, slot: usize, reason: CloseReason, device: &mut D) {
        let Some(conn) = self.slots.get_mut(slot).and_then(Option::take) else {
            return;
        };
        info!(
            "connection {} closed ({:?} from {}): {}",
            slot,
            conn.kind,
            conn.originator,
            reason.describe()
        );
        device.connection_event(ConnectionEvent::Closed(
            ConnectionInfo::of(slot, &conn),
            reason,
        ));
        let had_owner = !self.owned.is_empty();
        if conn.producer().is_some() {
            for (i, s) in self.slots.iter_mut().enumerate() {
                let follows = s.as_ref().is_some_and(|c| {
                    c.kind == Kind::ListenOnly && c.t_o_id == conn.t_o_id && c.producer().is_none()
                });
                if let Some(c) = s.take_if(|_| follows) {
                    info!(
                        "connection {} closed: {}",
                        i,
                        CloseReason::Dependency.describe()
                    );
                    let info = ConnectionInfo::of(i, &c);
                    device.connection_event(ConnectionEvent::Closed(info, CloseReason::Dependency));
                }
            }
        }
        self.refresh_owned();
        if had_owner && self.owned.is_empty() {
            device.connection_event(ConnectionEvent::OwnershipLost(reason));
        }
    }
    /// Closes every open connection with `reason`.
    pub fn close_all<D: Device>(&mut self, reason: CloseReason, device: &mut D) {
        for slot in 0..MAX_CONNECTIONS {
            self.close(slot, reason, device);
        }
    }
    /// Closes the Class 1 connections whose consumed or produced assembly can no longer carry
    /// the size they opened with ([`CloseReason::Reconfigured`]).
    pub fn close_resized<D: Device>(&mut self, device: &mut D) {
        for slot in 0..MAX_CONNECTIONS {
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
        for slot in 0..MAX_CONNECTIONS {
            let expired = self.get(slot).filter(|c| c.expires <= now);
            if let Some(owner) = expired.map(|c| c.kind == Kind::ExclusiveOwner) {
                if owner {
                    self.owner_timeouts = self.owner_timeouts.wrapping_add(1);
                }
                self.timeouts = self.timeouts.wrapping_add(1);
                self.close(slot, CloseReason::Timeout, device);
                closed = closed.saturating_add(1);
            }
        }
        self.expiry_bound = self
            .iter()
            .map(|(_, c)| c.expires)
            .min()
            .unwrap_or(Instant(u64::MAX));
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
        for slot in 0..MAX_CONNECTIONS {
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

    fn refresh_owned(&mut self) {
        self.owned.clear();
        for slot in self.slots.iter().flatten() {
            if let (Kind::ExclusiveOwner, Some(c)) = (slot.kind, slot.consumer()) {
                // Cannot fail: at most one entry per slot.
                let _ = self.owned.push(c.instance);
            }
        }
    }
}
