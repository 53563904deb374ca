//! QoS object (class 0x48): the DSCP values the device marks its IP packets with, by kind of
//! traffic (Class 1 by connection priority, explicit messaging, PTP), and the 802.1Q tag
//! enable; the values saved in the non-volatile store and the set in use since start.
//!
//! When a Set applies: every instance attribute is non-volatile (CIP Vol 2, QoS object), and
//! a changed value takes effect the next time the device starts (power cycle or Identity
//! Reset), not on traffic already flowing: the reading of the open reference stack (OpENer
//! keeps an active copy taken at start-up) and of certified adapters' manuals ("takes effect
//! on device re-start"). So a Set is saved and read back at once
//! ([`QosState::configured`]), while the packets keep the values the device started with
//! ([`QosState::active`]) until its next start. That also keeps a running connection's
//! marking (its DSCP is taken once, when it opens) consistent with every other packet, and
//! a Set can never re-mark the TCP connection that carried it mid-stream.

use super::serve::{serve, Object};
use super::Ctx;
use crate::cip::object::{AttributeDef, ClassDef, DataType};
use crate::cip::status::{CipResult, General};
use crate::cip::{class_id, Request};
use crate::device::Device;
use crate::nv::{key, NvError, NvStore};
use crate::wire::Writer;

/// Layout version of the stored record.
const RECORD_VERSION: u8 = 1;
/// Bytes of the stored record: version, tag enable, seven DSCP values.
pub(crate) const RECORD_LEN: usize = 2 + 7;
const _: () = assert!(RECORD_LEN <= crate::nv::QOS_RECORD_ROOM);
/// The highest DSCP value (six bits).
pub const MAX_DSCP: u8 = 63;

/// The DSCP values of attributes 2-8, in attribute order: PTP (IEEE 1588) event messages,
/// PTP general messages, Class 0/1 connections of urgent, scheduled, high and low priority,
/// and explicit messaging (TCP and UDP 44818, Class 3). One array, so that a Set, a save and
/// a load copy it whole.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Dscp(pub [u8; 7]);

impl Dscp {
    /// The defaults of CIP Vol 2 (the values of the DiffServ classes EtherNet/IP uses).
    pub const DEFAULT: Dscp = Dscp([59, 47, 55, 47, 43, 31, 27]);

    /// The DSCP of a Class 1 connection whose network parameters carry `priority` (two bits:
    /// 0 low, 1 high, 2 scheduled, 3 urgent).
    pub fn for_priority(&self, priority: u8) -> u8 {
        let [_, _, urgent, scheduled, high, low, _] = self.0;
        match priority & 3 {
            0 => low,
            1 => high,
            2 => scheduled,
            _ => urgent,
        }
    }

    /// Attribute 8: the DSCP of explicit messaging.
    pub fn explicit(&self) -> u8 {
        let [.., explicit] = self.0;
        explicit
    }

    /// Attribute `id` (2-8); `None` for any other.
    pub fn attribute(&self, id: u16) -> Option<u8> {
        self.0.get(index(id)).copied()
    }
}

/// The index of attribute `id` (2-8) in [`Dscp`]'s array; out of range for any other.
fn index(id: u16) -> usize {
    usize::from(id).wrapping_sub(2)
}

impl Default for Dscp {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// The QoS object's state: the values set (saved, read back by Get) and those in use.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct QosState {
    /// Attribute 1 as set: 802.1Q tag enable (0 disabled). This device sends no tagged
    /// frames, so only 0 is accepted.
    pub tag_enable: u8,
    /// Attributes 2-8 as set (and saved): they apply from the next start.
    pub configured: Dscp,
    /// The values the packets carry: those configured when the device started.
    pub active: Dscp,
}

impl QosState {
    /// Factory defaults, in use.
    pub const fn new() -> Self {
        QosState {
            tag_enable: 0,
            configured: Dscp::DEFAULT,
            active: Dscp::DEFAULT,
        }
    }

    /// The settings stored in `store`, configured and in use (as at a start); `None` if there
    /// are none or they are unreadable (logged; the defaults hold).
    pub fn stored(store: &mut dyn NvStore) -> Result<Option<QosState>, NvError> {
        crate::nv::read_decoded::<RECORD_LEN, _>(store, key::QOS, "QoS", decode)
    }

    /// Stores attribute 1 and the configured DSCP values in `store`.
    pub fn save(&self, store: &mut dyn NvStore) -> Result<(), NvError> {
        let [a, b, c, d, e, f, g] = self.configured.0;
        store.write(
            key::QOS,
            &[RECORD_VERSION, self.tag_enable, a, b, c, d, e, f, g],
        )
    }
}

impl Default for QosState {
    fn default() -> Self {
        Self::new()
    }
}

/// A stored record as the state a start begins with; `None` if malformed or out of range.
fn decode(bytes: &[u8]) -> Option<QosState> {
    let [RECORD_VERSION, 0, values @ ..] = bytes else {
        return None;
    };
    let values = <[u8; 7]>::try_from(values).ok()?;
    if values.iter().any(|v| *v > MAX_DSCP) {
        return None;
    }
    let dscp = Dscp(values);
    Some(QosState {
        tag_enable: 0,
        configured: dscp,
        active: dscp,
    })
}

/// The QoS class: one instance, attributes 1-8, all settable (Get/Set_Attribute_Single;
/// the specification defines no Get_Attributes_All for it).
pub const CLASS: ClassDef = ClassDef {
    id: class_id::QOS,
    name: "QoS",
    revision: 1,
    max_instance: 1,
    attributes: &[
        AttributeDef::get_set(1, DataType::Usint, "802.1Q Tag Enable"),
        AttributeDef::get_set(2, DataType::Usint, "DSCP PTP Event"),
        AttributeDef::get_set(3, DataType::Usint, "DSCP PTP General"),
        AttributeDef::get_set(4, DataType::Usint, "DSCP Urgent"),
        AttributeDef::get_set(5, DataType::Usint, "DSCP Scheduled"),
        AttributeDef::get_set(6, DataType::Usint, "DSCP High"),
        AttributeDef::get_set(7, DataType::Usint, "DSCP Low"),
        AttributeDef::get_set(8, DataType::Usint, "DSCP Explicit"),
    ],
    get_all: &[],
    optional_attributes: &[1, 2, 3],
};

struct Qos<'c, 'a, D: Device, const C: usize>(&'c mut Ctx<'a, D, C>);

impl<D: Device, const C: usize> Object for Qos<'_, '_, D, C> {
    fn class(&self) -> &ClassDef {
        &CLASS
    }

    fn get(&mut self, _instance: u32, attr: &AttributeDef, w: &mut Writer<'_>) -> CipResult {
        let qos = &self.0.state.qos;
        let value = match attr.id {
            1 => qos.tag_enable,
            id => qos.configured.attribute(id).unwrap_or(0),
        };
        w.u8(value)?;
        Ok(())
    }

    /// Attribute 1 takes 0 only (no tagged frames here), 2-8 take 0-63; anything else is
    /// 0x09. The value is saved before the Set is answered (0x19, changing nothing, if that
    /// fails) and applies from the next start.
    fn set(&mut self, _instance: u32, attr: &AttributeDef, value: &[u8]) -> CipResult {
        let v = value.first().copied().unwrap_or(u8::MAX);
        let ctx = &mut *self.0;
        let mut qos = ctx.state.qos;
        match (attr.id, qos.configured.0.get_mut(index(attr.id))) {
            (1, _) if v == 0 => qos.tag_enable = v,
            (_, Some(value)) if v <= MAX_DSCP => *value = v,
            _ => return Err(General::InvalidAttributeValue.into()),
        }
        if let Some(store) = ctx.store.as_deref_mut() {
            if qos.save(store).is_err() {
                warn!("QoS attribute {}: storing failed", attr.id);
                return Err(General::StoreOperationFailure.into());
            }
        }
        ctx.state.qos = qos;
        Ok(())
    }
}

/// Handles a request to the QoS class or its instance 1.
pub(crate) fn handle<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    serve(&mut Qos(ctx), req, w)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nv::{AbStore, RamFlash, IMAGE_SIZE, MAX_WRITE_SIZE};

    #[test]
    fn defaults_are_the_specifications() {
        let d = QosState::new();
        assert_eq!(d.tag_enable, 0);
        assert_eq!(d.configured, d.active);
        assert_eq!(d.active.0, [59, 47, 55, 47, 43, 31, 27]);
        // Priority field of the network parameters: low, high, scheduled, urgent.
        let by_priority: [u8; 4] = core::array::from_fn(|p| d.active.for_priority(p as u8));
        assert_eq!(by_priority, [31, 43, 47, 55]);
    }

    #[test]
    fn settings_round_trip_through_the_store_and_apply_at_the_next_start() {
        let mut store = AbStore::mount(RamFlash::<{ MAX_WRITE_SIZE + IMAGE_SIZE }>::new());
        assert_eq!(QosState::stored(&mut store), Ok(None));
        let mut st = QosState::new();
        st.configured.0 = [63, 47, 55, 40, 43, 31, 0];
        st.save(&mut store).unwrap();
        let mut store = AbStore::mount(store.into_flash());
        let back = QosState::stored(&mut store).unwrap().unwrap();
        assert_eq!(back.configured, st.configured);
        // What was configured is what a start uses.
        assert_eq!(back.active, st.configured);
        assert_eq!(back.active.for_priority(2), 40);
        // A record with a value out of range, a tag enable this device cannot honour, or of
        // another length, is not believed.
        for bad in [
            &[RECORD_VERSION, 0, 59, 47, 55, 64, 43, 31, 27][..],
            &[RECORD_VERSION, 1, 59, 47, 55, 47, 43, 31, 27],
            &[RECORD_VERSION, 0, 59, 47, 55, 47, 43, 31],
            // Longer than the record (found by the `nv_records` fuzz target: was an error).
            &[RECORD_VERSION, 0, 59, 47, 55, 47, 43, 31, 27, 0],
            &[2, 0, 59, 47, 55, 47, 43, 31, 27],
        ] {
            store.write(key::QOS, bad).unwrap();
            assert_eq!(QosState::stored(&mut store), Ok(None), "{bad:?}");
        }
    }
}
