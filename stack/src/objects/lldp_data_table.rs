//! LLDP Data Table object (class 0x10A): what the LLDPDUs of the neighbours on the link said,
//! one instance per neighbour, kept for the Time To Live they announced.
//!
//! A neighbour is known by its MSAP identifier (Chassis ID and Port ID, 802.1AB 8.5.1),
//! kept as the CRC-32 of those two TLVs. Instance `n` is slot `n` of the table and keeps its number while the
//! neighbour stays; a table entry expires at the time of its last LLDPDU plus the TTL it
//! carried (checked whenever the table is read or fed, so nothing needs a timer), and an
//! LLDPDU with TTL 0 removes it at once. A new neighbour that finds the table full is
//! dropped and counted, as 802.1AB's tooManyNeighbors.

use core::net::Ipv4Addr;

use super::serve::{serve, Object};
use super::Ctx;
use crate::cip::encoding::{ip, short_string};
use crate::cip::object::{AttributeDef, ClassDef, DataType};
use crate::cip::status::CipResult;
use crate::cip::{class_id, Request};
use crate::config::MAX_LLDP_NEIGHBORS;
use crate::device::Device;
use crate::nv::crc32;
use crate::time::{Duration, Instant};
use crate::wire::lldp::{
    CipIdentification, LldpduRepr, CHASSIS_INTERFACE_NAME, MAX_ADDRESSES, PORT_INTERFACE_NAME,
};
use crate::wire::Writer;

/// Longest interface label kept of a neighbour (attribute 3 allows 64 characters).
pub const MAX_LABEL: usize = 64;

/// One neighbour's data.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Neighbor {
    /// CRC-32 of the Chassis ID and Port ID TLVs.
    msap: u32,
    /// CRC-32 of the whole LLDPDU last received: a change shows as another value.
    digest: u32,
    /// Attribute 2: the neighbour's MAC address: the CIP MAC Address TLV's, else a Chassis
    /// ID or Port ID of the MAC address subtype, else all zero.
    pub mac: [u8; 6],
    /// Attribute 3: the CIP Interface Label TLV, else a Chassis ID or Port ID of the
    /// interface name subtype, else empty.
    pub label: heapless::Vec<u8, MAX_LABEL>,
    /// Attribute 4: the Time To Live announced, in seconds.
    pub ttl_s: u16,
    /// Attribute 5: System Capabilities (supported, enabled).
    pub capabilities: (u16, u16),
    /// Attribute 6: the IPv4 management addresses.
    pub addresses: heapless::Vec<Ipv4Addr, MAX_ADDRESSES>,
    /// Attribute 7: CIP Identification (all zero when the neighbour sent none).
    pub identity: CipIdentification,
    /// When the data expire.
    expires: Instant,
    /// Attribute 9: when the data last changed.
    pub changed: Instant,
}

/// The neighbours on the link.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NeighborTable {
    slots: [Option<Neighbor>; MAX_LLDP_NEIGHBORS],
    /// When an entry was last added, changed or removed (the LLDP Management object's Last
    /// Change).
    pub last_change: Instant,
    /// New neighbours dropped for want of room.
    pub too_many: u32,
}

impl NeighborTable {
    /// An empty table.
    pub const fn new() -> Self {
        NeighborTable {
            slots: [const { None }; MAX_LLDP_NEIGHBORS],
            last_change: Instant(0),
            too_many: 0,
        }
    }

    /// Removes the entries whose TTL ran out by `now`; the change is dated when it happened.
    pub fn expire(&mut self, now: Instant) {
        for slot in &mut self.slots {
            if let Some(n) = slot.as_ref().filter(|n| n.expires <= now) {
                self.last_change = self.last_change.max(n.expires);
                *slot = None;
            }
        }
    }

    /// Takes in an LLDPDU `pdu` (its bytes `raw`) received at `now`.
    pub fn receive(&mut self, pdu: &LldpduRepr<'_>, raw: &[u8], now: Instant) {
        self.expire(now);
        let msap = crc32(pdu.msap);
        let at = self
            .slots
            .iter()
            .position(|s| s.as_ref().map(|n| n.msap) == Some(msap));
        if pdu.ttl == 0 {
            if let Some(slot) = at.and_then(|i| self.slots.get_mut(i)) {
                *slot = None;
                self.last_change = now;
            }
            return;
        }
        let digest = crc32(raw);
        let expires = now.add(Duration::from_secs(u64::from(pdu.ttl)));
        let free = || self.slots.iter().position(Option::is_none);
        let Some(slot) = at.or_else(free).and_then(|i| self.slots.get_mut(i)) else {
            self.too_many = self.too_many.wrapping_add(1);
            return;
        };
        if let Some(n) = slot.as_mut().filter(|n| n.digest == digest) {
            n.expires = expires;
            return;
        }
        *slot = Some(Neighbor {
            msap,
            digest,
            mac: pdu.neighbor_mac(),
            label: label(pdu),
            ttl_s: pdu.ttl,
            capabilities: pdu.capabilities.unwrap_or((0, 0)),
            addresses: pdu.addresses.clone(),
            identity: pdu.cip_identification.unwrap_or_default(),
            expires,
            changed: now,
        });
        self.last_change = now;
    }

    /// The neighbour of instance `instance` (1-based).
    pub fn get(&self, instance: u32) -> Option<&Neighbor> {
        let i = usize::try_from(instance.checked_sub(1)?).ok()?;
        self.slots.get(i)?.as_ref()
    }

    /// The neighbours and their instance numbers.
    pub fn iter(&self) -> impl Iterator<Item = (u32, &Neighbor)> {
        (1u32..)
            .zip(self.slots.iter())
            .filter_map(|(i, s)| Some((i, s.as_ref()?)))
    }
}

impl Default for NeighborTable {
    fn default() -> Self {
        Self::new()
    }
}

/// The interface label of a neighbour: its CIP Interface Label, else a Chassis ID or Port ID
/// of the interface name subtype, else empty; cut to fit.
fn label(pdu: &LldpduRepr<'_>) -> heapless::Vec<u8, MAX_LABEL> {
    let chassis = (pdu.chassis_subtype == CHASSIS_INTERFACE_NAME).then_some(pdu.chassis_id);
    let port = (pdu.port_subtype == PORT_INTERFACE_NAME).then_some(pdu.port_id);
    let text = pdu.cip_interface_label.or(chassis).or(port).unwrap_or(&[]);
    let text = text.get(..MAX_LABEL).unwrap_or(text);
    heapless::Vec::from_slice(text).unwrap_or_default()
}

/// Whole seconds from the start of the runtime's clock to `t` (CIP's UDINT, saturating).
pub(crate) fn seconds(t: Instant) -> u32 {
    u32::try_from(t.as_micros() / 1_000_000).unwrap_or(u32::MAX)
}

/// The LLDP Data Table class: an instance per neighbour, attributes 1-9, all read-only.
pub const CLASS: ClassDef = ClassDef {
    id: class_id::LLDP_DATA_TABLE,
    name: "LLDP Data Table",
    revision: 1,
    max_instance: MAX_LLDP_NEIGHBORS as u32,
    attributes: &[
        AttributeDef::get(1, DataType::Uint, "Ethernet Link Instance Number"),
        AttributeDef::get(2, DataType::Bytes(6), "MAC Address"),
        AttributeDef::get(
            3,
            DataType::ShortString {
                max: MAX_LABEL as u8,
            },
            "Interface Label",
        ),
        AttributeDef::get(4, DataType::Uint, "Time to Live"),
        AttributeDef::get(5, DataType::Bytes(4), "System Capabilities TLV"),
        AttributeDef::get(6, DataType::Unsized, "IPv4 Management Addresses"),
        AttributeDef::get(7, DataType::Bytes(12), "CIP Identification"),
        AttributeDef::get(8, DataType::Bytes(4), "Additional Ethernet Capabilities"),
        AttributeDef::get(9, DataType::Udint, "Last Change"),
    ],
    get_all: &[1, 2, 3, 4, 5, 6, 7, 8, 9],
    optional_attributes: &[],
};

struct DataTable<'c, 'a, D: Device, const C: usize>(&'c mut Ctx<'a, D, C>);

impl<D: Device, const C: usize> Object for DataTable<'_, '_, D, C> {
    fn class(&self) -> &ClassDef {
        &CLASS
    }
    fn has_instance(&self, instance: u32) -> bool {
        self.0.state.lldp.neighbors.get(instance).is_some()
    }
    fn max_instance(&self) -> u32 {
        self.0
            .state
            .lldp
            .neighbors
            .iter()
            .map(|(i, _)| i)
            .max()
            .unwrap_or(0)
    }
    fn instance_count(&self) -> u32 {
        self.0.state.lldp.neighbors.iter().count() as u32
    }
    fn get(&mut self, instance: u32, attr: &AttributeDef, w: &mut Writer<'_>) -> CipResult {
        let Some(n) = self.0.state.lldp.neighbors.get(instance) else {
            return Err(crate::cip::status::General::ObjectDoesNotExist.into());
        };
        match attr.id {
            1 => w.u16(1)?,
            2 => w.bytes(&n.mac)?,
            3 => short_string(w, &n.label)?,
            4 => w.u16(n.ttl_s)?,
            5 => {
                w.u16(n.capabilities.0)?;
                w.u16(n.capabilities.1)?;
            }
            6 => {
                w.u8(n.addresses.len() as u8)?;
                for a in &n.addresses {
                    ip(w, *a)?;
                }
            }
            7 => n.identity.emit(w)?,
            // No preemption (802.3br) on this link.
            8 => w.zeros(4)?,
            _ => w.u32(seconds(n.changed))?,
        }
        Ok(())
    }
}

/// Handles a request to the LLDP Data Table class or one of its instances (the caller drops
/// the entries that expired first).
pub(crate) fn serve_table<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    serve(&mut DataTable(ctx), req, w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn label_is_the_cip_label_else_an_interface_name_id() {
        let mut pdu = LldpduRepr {
            chassis_subtype: CHASSIS_INTERFACE_NAME,
            chassis_id: b"bridge0",
            port_subtype: PORT_INTERFACE_NAME,
            port_id: b"eth0",
            ttl: 10,
            ..LldpduRepr::default()
        };
        assert_eq!(label(&pdu).as_slice(), b"bridge0");
        pdu.chassis_subtype = 4;
        assert_eq!(label(&pdu).as_slice(), b"eth0");
        pdu.cip_interface_label = Some(b"Port 2");
        assert_eq!(label(&pdu).as_slice(), b"Port 2");
        // Other subtypes (here a locally assigned Port ID) give no label; a long one is cut.
        pdu.cip_interface_label = None;
        pdu.port_subtype = 7;
        assert!(label(&pdu).is_empty());
        pdu.cip_interface_label = Some(&[b'x'; 100]);
        assert_eq!(label(&pdu).len(), MAX_LABEL);
    }
}
