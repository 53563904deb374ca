//! Ethernet Link object (class 0xF6): speed, flags, MAC address, counters, admin state.

use super::serve::{attribute_services, serve, Object};
use super::Ctx;
use crate::cip::encoding::short_string;
use crate::cip::object::{AttributeDef, ClassDef, DataType};
use crate::cip::status::{CipResult, General};
use crate::cip::{class_id, service, Request};
use crate::device::Device;
use crate::wire::Writer;

/// Interface counters (attribute 4), as seen by the stack: encapsulation and I/O traffic.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct InterfaceCounters {
    /// Octets received.
    pub in_octets: u32,
    /// Unicast packets received.
    pub in_ucast: u32,
    /// Broadcast and multicast packets received.
    pub in_nucast: u32,
    /// Inbound packets discarded (malformed or unwanted).
    pub in_discards: u32,
    /// Octets sent.
    pub out_octets: u32,
    /// Unicast packets sent.
    pub out_ucast: u32,
}

/// Ethernet Link state kept by the stack.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LinkState {
    /// Counters since the last Get_and_Clear.
    pub counters: InterfaceCounters,
    /// Attribute 9: 1 enabled, 2 disabled.
    pub admin_state: u8,
}

impl LinkState {
    /// Power-up state.
    pub const fn new() -> Self {
        LinkState {
            counters: InterfaceCounters {
                in_octets: 0,
                in_ucast: 0,
                in_nucast: 0,
                in_discards: 0,
                out_octets: 0,
                out_ucast: 0,
            },
            admin_state: 1,
        }
    }
    /// Counts a received packet of `len` bytes.
    pub fn count_in(&mut self, len: usize, unicast: bool) {
        let c = &mut self.counters;
        c.in_octets = c.in_octets.wrapping_add(len as u32);
        if unicast {
            c.in_ucast = c.in_ucast.wrapping_add(1);
        } else {
            c.in_nucast = c.in_nucast.wrapping_add(1);
        }
    }
    /// Counts a discarded packet.
    pub fn count_discard(&mut self) {
        self.counters.in_discards = self.counters.in_discards.wrapping_add(1);
    }
    /// Counts a sent packet of `len` bytes.
    pub fn count_out(&mut self, len: usize) {
        let c = &mut self.counters;
        c.out_octets = c.out_octets.wrapping_add(len as u32);
        c.out_ucast = c.out_ucast.wrapping_add(1);
    }
}

impl Default for LinkState {
    fn default() -> Self {
        Self::new()
    }
}

/// Interface flags: link up (bit 0), full duplex (bit 1), auto-negotiation succeeded (3 << 2).
fn flags(link_up: bool) -> u32 {
    if link_up {
        0x01 | 0x02 | (3 << 2)
    } else {
        0
    }
}

/// The Ethernet Link class: one instance, attributes 1-11; 9 (admin state) is settable, and
/// Get_and_Clear reads and clears the counters (4) or reads the media counters (5).
pub const CLASS: ClassDef = ClassDef {
    id: class_id::ETHERNET_LINK,
    name: "Ethernet Link",
    revision: 4,
    max_instance: 1,
    attributes: &[
        AttributeDef::get(1, DataType::Udint, "Interface Speed"),
        AttributeDef::get(2, DataType::Dword, "Interface Flags"),
        AttributeDef::get(3, DataType::Bytes(6), "Physical Address"),
        AttributeDef::get(4, DataType::Bytes(44), "Interface Counters"),
        AttributeDef::get(5, DataType::Bytes(48), "Media Counters"),
        AttributeDef::get(6, DataType::Bytes(4), "Interface Control"),
        AttributeDef::get(7, DataType::Usint, "Interface Type"),
        AttributeDef::get(8, DataType::Usint, "Interface State"),
        AttributeDef::get_set(9, DataType::Usint, "Admin State"),
        AttributeDef::get(10, DataType::ShortString { max: 64 }, "Interface Label"),
        AttributeDef::get(11, DataType::Bytes(11), "Interface Capability"),
    ],
    get_all: &[1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11],
    optional_attributes: &[4, 5, 6, 7, 8, 9, 10, 11],
};

struct Link<'c, 'a, D: Device>(&'c mut Ctx<'a, D>);

impl<D: Device> Object for Link<'_, '_, D> {
    fn class(&self) -> &ClassDef {
        &CLASS
    }
    fn get(&mut self, _instance: u32, attr: &AttributeDef, w: &mut Writer<'_>) -> CipResult {
        let net = self.0.net;
        let link = &self.0.state.link;
        match attr.id {
            1 => w.u32(net.link_speed_mbps)?,
            2 => w.u32(flags(net.link_up))?,
            3 => w.bytes(&net.mac)?,
            4 => {
                let c = link.counters;
                for v in [c.in_octets, c.in_ucast, c.in_nucast, c.in_discards, 0, 0] {
                    w.u32(v)?;
                }
                for v in [c.out_octets, c.out_ucast, 0, 0, 0] {
                    w.u32(v)?;
                }
            }
            5 => w.zeros(12 * 4)?,
            6 => {
                w.u16(0x0001)?; // auto-negotiate
                w.u16(0)?;
            }
            7 => w.u8(2)?, // twisted pair
            8 => w.u8(if net.link_up { 1 } else { 2 })?,
            9 => w.u8(link.admin_state)?,
            10 => short_string(w, b"Port 1")?,
            _ => {
                w.u32(0x0000_0004)?; // auto-negotiate capable
                w.u8(2)?;
                w.u16(10)?;
                w.u8(1)?;
                w.u16(100)?;
                w.u8(1)?;
            }
        }
        Ok(())
    }

    fn set(&mut self, _instance: u32, _attr: &AttributeDef, value: &[u8]) -> CipResult {
        // Attribute 9, the only settable one.
        match value {
            [v @ (1 | 2)] => {
                self.0.state.link.admin_state = *v;
                Ok(())
            }
            _ => Err(General::InvalidAttributeValue.into()),
        }
    }

    fn service(
        &mut self,
        instance: u32,
        req: &Request<'_>,
        w: &mut Writer<'_>,
    ) -> Option<CipResult> {
        (instance == 1 && req.service == service::GET_AND_CLEAR)
            .then(|| get_and_clear(self, req, w))
    }
}

/// Get_and_Clear: Get_Attribute_Single of attribute 4 or 5, then attribute 4 cleared.
fn get_and_clear<D: Device>(
    link: &mut Link<'_, '_, D>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    let attr = req.path.attribute;
    if !matches!(attr, Some(4 | 5)) {
        return Err(if attr.is_some() {
            General::AttributeNotSupported.into()
        } else {
            General::PathDestinationUnknown.into()
        });
    }
    let get = Request {
        service: service::GET_ATTRIBUTE_SINGLE,
        ..*req
    };
    attribute_services(link, 1, &get, w)?;
    if attr == Some(4) {
        link.0.state.link.counters = InterfaceCounters::default();
    }
    Ok(())
}

/// Handles a request to the Ethernet Link class or its instance 1.
pub(crate) fn handle<D: Device>(
    ctx: &mut Ctx<'_, D>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    serve(&mut Link(ctx), req, w)
}
