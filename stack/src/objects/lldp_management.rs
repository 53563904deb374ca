//! LLDP Management object (class 0x109) and the LLDP agent's state: the settings (LLDP
//! Enable, msgTxInterval, msgTxHold; non-volatile in the [`crate::nv`] record
//! [`key::LLDP`]), when the next LLDPDU is due, and the neighbours
//! ([`super::lldp_data_table`]).
//!
//! Transmission (802.1AB 9.2): an LLDPDU at start, then every msgTxInterval, and one at most
//! a second after the local information changed (host name, address, these settings, the
//! link coming up); TTL = msgTxInterval x msgTxHold (at most 65 535 s). Turning LLDP off sends
//! one shutdown LLDPDU (TTL 0). The runtime builds the frames: [`crate::Adapter::lldp_transmit`].

use super::lldp_data_table::{seconds, serve_table, NeighborTable};
use super::serve::{serve, Object};
use super::Ctx;
use crate::cip::object::{AttributeDef, ClassDef, DataType};
use crate::cip::status::{CipResult, General};
use crate::cip::{class_id, Request};
use crate::device::Device;
use crate::nv::{key, NvError, NvStore};
use crate::time::{Duration, Instant};
use crate::wire::bytes::get_u16;
use crate::wire::{Reader, Writer};

/// LLDP Enable bit 0: LLDP on globally.
pub const ENABLE_GLOBAL: u8 = 1 << 0;
/// LLDP Enable bit 1: LLDP on for the port (Ethernet Link instance 1).
pub const ENABLE_PORT_1: u8 = 1 << 1;
/// Bits in the LLDP Enable array: the global one and one per port.
const ENABLE_BITS: u16 = 2;
/// Default msgTxInterval in seconds (802.1AB).
pub const DEFAULT_TX_INTERVAL_S: u16 = 30;
/// Default msgTxHold (802.1AB).
pub const DEFAULT_TX_HOLD: u8 = 4;
/// msgTxInterval range in seconds (802.1AB-2016 10.5.1).
const TX_INTERVAL_S: core::ops::RangeInclusive<u16> = 1..=3600;
/// msgTxHold range (802.1AB-2016 10.5.1).
const TX_HOLD: core::ops::RangeInclusive<u8> = 1..=100;
/// LLDP Datastore bit 0: the neighbours are kept in the LLDP Data Table object.
const DATASTORE_DATA_TABLE: u16 = 1 << 0;
/// Shortest time between two LLDPDUs sent for a change.
const CHANGE_SPACING: Duration = Duration::from_secs(1);
/// Layout version of the stored record.
const RECORD_VERSION: u8 = 1;
/// Bytes of the stored record: version, enable, interval, hold.
pub(crate) const RECORD_MAX: usize = 5;
const _: () = assert!(RECORD_MAX <= crate::nv::LLDP_RECORD_ROOM);

/// The settable attributes 1-3.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LldpConfig {
    /// Attribute 1: bit 0 LLDP on globally, bit 1 on for the port (Ethernet Link instance 1).
    pub enable: u8,
    /// Attribute 2: msgTxInterval in seconds.
    pub tx_interval_s: u16,
    /// Attribute 3: msgTxHold.
    pub tx_hold: u8,
}

impl LldpConfig {
    /// Factory defaults: on, every 30 s, TTL 120 s.
    pub const DEFAULT: LldpConfig = LldpConfig {
        enable: ENABLE_GLOBAL | ENABLE_PORT_1,
        tx_interval_s: DEFAULT_TX_INTERVAL_S,
        tx_hold: DEFAULT_TX_HOLD,
    };

    /// True if LLDPDUs go out on the port: both the global and the port's bit set.
    pub fn transmits(&self) -> bool {
        self.enable & (ENABLE_GLOBAL | ENABLE_PORT_1) == ENABLE_GLOBAL | ENABLE_PORT_1
    }

    /// True if received LLDPDUs are taken in: the global bit set (the per-port bits are
    /// about transmission only).
    pub fn receives(&self) -> bool {
        self.enable & ENABLE_GLOBAL != 0
    }

    /// The Time To Live announced: msgTxInterval x msgTxHold, at most 65 535 s.
    pub fn ttl(&self) -> u16 {
        let ttl = u32::from(self.tx_interval_s).saturating_mul(u32::from(self.tx_hold));
        u16::try_from(ttl).unwrap_or(u16::MAX)
    }

    /// The settings stored in `store`; `None` if there are none or they are unreadable.
    pub fn stored(store: &mut dyn NvStore) -> Result<Option<LldpConfig>, NvError> {
        crate::nv::read_decoded::<RECORD_MAX, _>(store, key::LLDP, "LLDP", decode)
    }

    /// Stores the settings in `store`.
    pub fn save(&self, store: &mut dyn NvStore) -> Result<(), NvError> {
        let [i0, i1] = self.tx_interval_s.to_le_bytes();
        store.write(
            key::LLDP,
            &[RECORD_VERSION, self.enable, i0, i1, self.tx_hold],
        )
    }

    fn is_valid(&self) -> bool {
        self.enable & !(ENABLE_GLOBAL | ENABLE_PORT_1) == 0
            && TX_INTERVAL_S.contains(&self.tx_interval_s)
            && TX_HOLD.contains(&self.tx_hold)
    }
}

/// Reads a stored record; `None` if malformed or out of range.
fn decode(bytes: &[u8]) -> Option<LldpConfig> {
    let mut r = Reader::new(bytes);
    if r.u8().ok()? != RECORD_VERSION {
        return None;
    }
    let c = LldpConfig {
        enable: r.u8().ok()?,
        tx_interval_s: r.u16().ok()?,
        tx_hold: r.u8().ok()?,
    };
    c.is_valid().then_some(c)
}

/// What is due to be sent.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LldpDue {
    /// The full LLDPDU.
    Update,
    /// The shutdown LLDPDU (TTL 0).
    Shutdown,
}

/// The LLDP agent: settings, transmit schedule and neighbours.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LldpState {
    /// Attributes 1-3.
    pub config: LldpConfig,
    /// The LLDP Data Table.
    pub neighbors: NeighborTable,
    /// When the next LLDPDU is due (the epoch at start: at once).
    next_tx: Instant,
    /// When the last one went out.
    last_tx: Option<Instant>,
    /// LLDP was turned off: the shutdown LLDPDU is due.
    shutdown_pending: bool,
    /// LLDPDUs sent.
    pub sent: u32,
    /// LLDPDUs received and discarded as malformed.
    pub discarded: u32,
}

impl LldpState {
    /// Power-up state, factory settings.
    pub const fn new() -> Self {
        LldpState {
            config: LldpConfig::DEFAULT,
            neighbors: NeighborTable::new(),
            next_tx: Instant(0),
            last_tx: None,
            shutdown_pending: false,
            sent: 0,
            discarded: 0,
        }
    }

    /// The local information changed: an LLDPDU goes out soon (a second after the last one
    /// at the earliest). Never inlined: called from several objects, never on the Class 1
    /// path.
    #[inline(never)]
    pub fn local_changed(&mut self) {
        let soon = self.last_tx.map_or(Instant(0), |t| t.add(CHANGE_SPACING));
        self.next_tx = self.next_tx.min(soon);
    }

    /// When [`Self::take_due`] has something to send (`None`: never, LLDP being off).
    pub fn deadline(&self) -> Option<Instant> {
        if self.shutdown_pending {
            return Some(Instant(0));
        }
        self.config.transmits().then_some(self.next_tx)
    }

    /// What is due at `now`, now counted as sent (the next one scheduled).
    pub fn take_due(&mut self, now: Instant) -> Option<LldpDue> {
        if core::mem::take(&mut self.shutdown_pending) {
            return Some(LldpDue::Shutdown);
        }
        if !self.config.transmits() || now < self.next_tx {
            return None;
        }
        self.last_tx = Some(now);
        self.next_tx = now.add(Duration::from_secs(u64::from(self.config.tx_interval_s)));
        self.sent = self.sent.wrapping_add(1);
        Some(LldpDue::Update)
    }

    /// Applies new settings: a change is announced, and turning LLDP off sends the shutdown
    /// LLDPDU.
    fn reconfigure(&mut self, config: LldpConfig) {
        let was = self.config.transmits();
        self.config = config;
        if was && !config.transmits() {
            self.shutdown_pending = true;
        }
        if !was && config.transmits() {
            self.next_tx = Instant(0);
        }
        self.local_changed();
    }
}

impl Default for LldpState {
    fn default() -> Self {
        Self::new()
    }
}

/// The LLDP Management class: one instance, attributes 1-5; 1-3 settable and non-volatile.
pub const CLASS: ClassDef = ClassDef {
    id: class_id::LLDP_MANAGEMENT,
    name: "LLDP Management",
    revision: 1,
    max_instance: 1,
    attributes: &[
        AttributeDef::get_set(1, DataType::Bytes(3), "LLDP Enable"),
        AttributeDef::get_set(2, DataType::Uint, "msgTxInterval"),
        AttributeDef::get_set(3, DataType::Usint, "msgTxHold"),
        AttributeDef::get(4, DataType::Word, "LLDP Datastore"),
        AttributeDef::get(5, DataType::Udint, "Last Change"),
    ],
    get_all: &[1, 2, 3, 4, 5],
    optional_attributes: &[],
};

struct Management<'c, 'a, D: Device, const C: usize>(&'c mut Ctx<'a, D, C>);

impl<D: Device, const C: usize> Object for Management<'_, '_, D, C> {
    fn class(&self) -> &ClassDef {
        &CLASS
    }
    fn get(&mut self, _instance: u32, attr: &AttributeDef, w: &mut Writer<'_>) -> CipResult {
        let lldp = &self.0.state.lldp;
        match attr.id {
            1 => {
                w.u16(ENABLE_BITS)?;
                w.u8(lldp.config.enable)?;
            }
            2 => w.u16(lldp.config.tx_interval_s)?,
            3 => w.u8(lldp.config.tx_hold)?,
            4 => w.u16(DATASTORE_DATA_TABLE)?,
            _ => w.u32(seconds(lldp.neighbors.last_change))?,
        }
        Ok(())
    }

    /// Checks the value (0x09 out of range), saves it before answering (0x19 if the store
    /// fails, nothing changed), then applies it at once.
    fn set(&mut self, _instance: u32, attr: &AttributeDef, value: &[u8]) -> CipResult {
        let mut config = self.0.state.lldp.config;
        match attr.id {
            1 => {
                // Exactly the global bit and one port's, in one byte.
                let bits = get_u16(value, 0);
                let byte = value.get(2).copied().unwrap_or(0xFF);
                if bits != ENABLE_BITS || byte & !(ENABLE_GLOBAL | ENABLE_PORT_1) != 0 {
                    return Err(General::InvalidAttributeValue.into());
                }
                config.enable = byte;
            }
            2 => config.tx_interval_s = get_u16(value, 0),
            _ => config.tx_hold = value.first().copied().unwrap_or(0),
        }
        if !config.is_valid() {
            return Err(General::InvalidAttributeValue.into());
        }
        if let Some(store) = self.0.store.as_deref_mut() {
            if config.save(store).is_err() {
                warn!("LLDP attribute {}: storing failed", attr.id);
                return Err(General::StoreOperationFailure.into());
            }
        }
        self.0.state.lldp.reconfigure(config);
        Ok(())
    }
}

/// Handles a request to the LLDP Management or the LLDP Data Table class or one of their
/// instances, after dropping the neighbours whose TTL ran out.
pub(crate) fn handle<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    let now = ctx.now();
    ctx.state.lldp.neighbors.expire(now);
    if req.path.class == Some(u32::from(class_id::LLDP_DATA_TABLE)) {
        return serve_table(ctx, req, w);
    }
    serve(&mut Management(ctx), req, w)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nv::{AbStore, RamFlash, IMAGE_SIZE, MAX_WRITE_SIZE};

    #[test]
    fn schedule_start_interval_change_and_shutdown() {
        let s = |x: u64| Instant(x * 1_000_000);
        let mut st = LldpState::new();
        assert_eq!(st.deadline(), Some(Instant(0)));
        assert_eq!(st.take_due(s(5)), Some(LldpDue::Update));
        assert_eq!(st.deadline(), Some(s(35)));
        assert_eq!(st.take_due(s(34)), None);
        // A change: one second after the last LLDPDU at the earliest.
        st.local_changed();
        assert_eq!(st.deadline(), Some(s(6)));
        assert_eq!(st.take_due(s(6)), Some(LldpDue::Update));
        assert_eq!(st.deadline(), Some(s(36)));
        // Turning LLDP off: one shutdown LLDPDU, then nothing.
        let mut off = st.config;
        off.enable = ENABLE_PORT_1;
        st.reconfigure(off);
        assert_eq!(st.take_due(s(7)), Some(LldpDue::Shutdown));
        assert_eq!((st.take_due(s(100)), st.deadline()), (None, None));
        // On again: at once.
        st.reconfigure(LldpConfig::DEFAULT);
        assert_eq!(st.take_due(s(101)), Some(LldpDue::Update));
        assert_eq!(st.sent, 3);
    }

    #[test]
    fn ttl_is_interval_times_hold_saturated() {
        assert_eq!(LldpConfig::DEFAULT.ttl(), 120);
        let c = LldpConfig {
            tx_interval_s: 3600,
            tx_hold: 100,
            ..LldpConfig::DEFAULT
        };
        assert_eq!(c.ttl(), u16::MAX);
    }

    #[test]
    fn settings_round_trip_through_the_store() {
        let mut store = AbStore::mount(RamFlash::<{ MAX_WRITE_SIZE + IMAGE_SIZE }>::new());
        assert_eq!(LldpConfig::stored(&mut store), Ok(None));
        let c = LldpConfig {
            enable: ENABLE_GLOBAL,
            tx_interval_s: 5,
            tx_hold: 2,
        };
        c.save(&mut store).unwrap();
        let mut store = AbStore::mount(store.into_flash());
        assert_eq!(LldpConfig::stored(&mut store), Ok(Some(c)));
        store
            .write(key::LLDP, &[RECORD_VERSION, 0, 0, 0, 1])
            .unwrap();
        assert_eq!(LldpConfig::stored(&mut store), Ok(None));
    }
}
