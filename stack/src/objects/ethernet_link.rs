//! Ethernet Link object (class 0xF6): speed, flags, MAC address, the counters the runtime
//! counts ([`super::link_counters`]), interface control, type, state, admin state, label and
//! capability.

use super::link_counters::{InterfaceCounters, LinkCounters, MediaCounters};
use super::serve::{attribute_services, serve, Object};
use super::Ctx;
use crate::cip::encoding::short_string;
use crate::cip::object::{AttributeDef, ClassDef, DataType};
use crate::cip::status::{CipResult, General};
use crate::cip::{class_id, service, Request};
use crate::device::Device;
use crate::wire::Writer;

/// Ethernet Link state kept by the stack.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LinkState {
    /// Attributes 4 and 5 since start or the last Get_And_Clear, as the runtime counted them.
    pub counters: LinkCounters,
}

impl LinkState {
    /// Power-up state.
    pub const fn new() -> Self {
        LinkState {
            counters: LinkCounters::new(),
        }
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

/// Interface Control bit 0: auto-negotiation enabled.
const CONTROL_AUTONEGOTIATE: u16 = 1 << 0;
/// Interface Control bit 1: forced full duplex.
const CONTROL_FORCED_FULL_DUPLEX: u16 = 1 << 1;
/// Interface Capability bit 1: auto-negotiation. Bits 0 (manual setting requires reset),
/// 2 (auto-MDIX) and 3 (manual speed/duplex) are clear: no board's driver can force a speed.
const CAPABILITY_AUTONEGOTIATE: u32 = 1 << 1;
/// Interface Capability: the speed/duplex pairs auto-negotiation chooses from.
const SPEED_DUPLEX: [(u16, u8); 4] = [(10, 0), (10, 1), (100, 0), (100, 1)];
/// Interface Type: twisted pair.
const TYPE_TWISTED_PAIR: u8 = 2;
/// Admin State: enabled.
const ADMIN_ENABLED: u8 = 1;
/// Admin State: disabled.
const ADMIN_DISABLED: u8 = 2;
/// Interface Label of the one port.
const LABEL: &[u8] = b"Port 1";

/// The Ethernet Link class (revision 4): one instance, attributes 1-11; 6 (interface control)
/// and 9 (admin state) settable within what the interface can do, and Get_And_Clear reads
/// and clears the counters (4, 5).
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
        AttributeDef::get_set(6, DataType::Bytes(4), "Interface Control"),
        AttributeDef::get(7, DataType::Usint, "Interface Type"),
        AttributeDef::get(8, DataType::Usint, "Interface State"),
        AttributeDef::get_set(9, DataType::Usint, "Admin State"),
        AttributeDef::get(10, DataType::ShortString { max: 64 }, "Interface Label"),
        AttributeDef::get(11, DataType::Bytes(17), "Interface Capability"),
    ],
    get_all: &[1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11],
    optional_attributes: &[4, 5, 6, 7, 8, 9, 10, 11],
};

struct Link<'c, 'a, D: Device, const C: usize>(&'c mut Ctx<'a, D, C>);

impl<D: Device, const C: usize> Object for Link<'_, '_, D, C> {
    fn class(&self) -> &ClassDef {
        &CLASS
    }
    fn extra_optional_services(&self) -> &'static [u8] {
        &[service::GET_AND_CLEAR]
    }

    fn get(&mut self, _instance: u32, attr: &AttributeDef, w: &mut Writer<'_>) -> CipResult {
        let net = self.0.net;
        let counters = &self.0.state.link.counters;
        match attr.id {
            1 => w.u32(net.link_speed_mbps)?,
            2 => w.u32(flags(net.link_up))?,
            3 => w.bytes(&net.mac)?,
            4 => counters
                .interface
                .values()
                .iter()
                .try_for_each(|v| w.u32(*v))?,
            5 => counters.media.values().iter().try_for_each(|v| w.u32(*v))?,
            6 => {
                w.u16(CONTROL_AUTONEGOTIATE)?;
                w.u16(0)?; // no forced speed
            }
            7 => w.u8(TYPE_TWISTED_PAIR)?,
            8 => w.u8(if net.link_up { 1 } else { 2 })?,
            9 => w.u8(ADMIN_ENABLED)?,
            10 => short_string(w, LABEL)?,
            _ => {
                w.u32(CAPABILITY_AUTONEGOTIATE)?;
                w.u8(SPEED_DUPLEX.len() as u8)?;
                for (speed, duplex) in SPEED_DUPLEX {
                    w.u16(speed)?;
                    w.u8(duplex)?;
                }
            }
        }
        Ok(())
    }

    /// Attribute 6: auto-negotiation (with no forced duplex or speed) is the interface's one
    /// setting; forcing with it on is 0x0C, reserved bits or a forced speed or duplex 0x09
    /// (capability bit 3 is clear). Attribute 9: enabled; disabling the device's only port,
    /// which would cut it off its network until a power cycle, is 0x09.
    fn set(&mut self, _instance: u32, attr: &AttributeDef, value: &[u8]) -> CipResult {
        let ok = match (attr.id, value) {
            (6, [lo, hi, speed_lo, speed_hi]) => {
                let bits = u16::from_le_bytes([*lo, *hi]);
                let speed = u16::from_le_bytes([*speed_lo, *speed_hi]);
                let forced = bits & CONTROL_FORCED_FULL_DUPLEX != 0 || speed != 0;
                if bits & CONTROL_AUTONEGOTIATE != 0 && forced {
                    return Err(General::ObjectStateConflict.into());
                }
                bits == CONTROL_AUTONEGOTIATE
            }
            (9, [v]) => match *v {
                ADMIN_ENABLED => true,
                ADMIN_DISABLED => {
                    warn!("Ethernet Link: the only port cannot be disabled");
                    false
                }
                _ => false,
            },
            _ => false,
        };
        if ok {
            Ok(())
        } else {
            Err(General::InvalidAttributeValue.into())
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

/// Get_And_Clear: the value of attribute 4 or 5, as Get_Attribute_Single gives it, then that
/// attribute cleared. Another attribute of the class is 0x2E (service not supported for the
/// path), an unknown one 0x14, none 0x05.
fn get_and_clear<D: Device, const C: usize>(
    link: &mut Link<'_, '_, D, C>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    let attr = req.path.attribute;
    if !matches!(attr, Some(4 | 5)) {
        let known = attr
            .and_then(|a| u16::try_from(a).ok())
            .and_then(|a| CLASS.attribute(a));
        return Err(match (attr, known) {
            (None, _) => General::PathDestinationUnknown,
            (Some(_), Some(_)) => General::ServiceNotSupportedForPath,
            (Some(_), None) => General::AttributeNotSupported,
        }
        .into());
    }
    let get = Request {
        service: service::GET_ATTRIBUTE_SINGLE,
        ..*req
    };
    attribute_services(link, 1, &get, w)?;
    let counters = &mut link.0.state.link.counters;
    if attr == Some(4) {
        counters.interface = InterfaceCounters::default();
    } else {
        counters.media = MediaCounters::default();
    }
    Ok(())
}

/// Handles a request to the Ethernet Link class or its instance 1.
pub(crate) fn handle<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    serve(&mut Link(ctx), req, w)
}
