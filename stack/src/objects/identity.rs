//! Identity object (class 0x01): who the device is, its status, and the Reset service.

use super::serve::{serve, Object};
use super::Ctx;
use crate::cip::encoding::short_string;
use crate::cip::object::{AttributeDef, ClassDef, DataType};
use crate::cip::status::{CipResult, General};
use crate::cip::{class_id, service, Request};
use crate::device::Device;
use crate::wire::Writer;

/// Status bit 10: a major recoverable fault.
const MAJOR_RECOVERABLE_FAULT: u16 = 1 << 10;
/// Status bit 11: a major unrecoverable fault.
const MAJOR_UNRECOVERABLE_FAULT: u16 = 1 << 11;
/// Status bits 4-7: the extended device status.
const EXTENDED_STATUS: u16 = 0xF << 4;
/// Extended device status 0101: a major fault (status bit 10 or 11).
const EXT_MAJOR_FAULT: u16 = 5 << 4;

/// Identity attribute 5 from the device's own bits (`Device::status_bits`) and the
/// connections' (owned, extended device status): under a major fault the extended status is
/// 0101, whatever the connections are; an extended status the device sets is its own; else
/// the connections' (Vol 1 5A-2.2).
pub fn status(device: u16, connections: u16) -> u16 {
    let extended = if device & (MAJOR_RECOVERABLE_FAULT | MAJOR_UNRECOVERABLE_FAULT) != 0 {
        EXT_MAJOR_FAULT
    } else if device & EXTENDED_STATUS != 0 {
        device & EXTENDED_STATUS
    } else {
        connections & EXTENDED_STATUS
    };
    ((device | connections) & !EXTENDED_STATUS) | extended
}

/// Writes attribute 5 (Status) or else 8 (State) now. Out of line: the attributes read most
/// (name, revision) do not pay for the connection table's walk in their frame.
#[inline(never)]
fn status_attribute<D: Device, const C: usize>(
    ctx: &Ctx<'_, D, C>,
    id: u16,
    w: &mut Writer<'_>,
) -> crate::wire::Result<()> {
    let status = ctx.identity_status();
    if id == 5 {
        w.u16(status)
    } else {
        w.u8(state(status))
    }
}

/// Attribute 8, State, for status bits `status`: 5 under a major unrecoverable fault, 4 a
/// major recoverable one, else 3 (operational).
const fn state(status: u16) -> u8 {
    if status & MAJOR_UNRECOVERABLE_FAULT != 0 {
        5
    } else if status & MAJOR_RECOVERABLE_FAULT != 0 {
        4
    } else {
        3
    }
}

/// The Identity class: one instance, attributes 1-8, all read-only.
pub const CLASS: ClassDef = ClassDef {
    id: class_id::IDENTITY,
    name: "Identity",
    revision: 1,
    max_instance: 1,
    attributes: &[
        AttributeDef::get(1, DataType::Uint, "Vendor ID"),
        AttributeDef::get(2, DataType::Uint, "Device Type"),
        AttributeDef::get(3, DataType::Uint, "Product Code"),
        AttributeDef::get(4, DataType::Bytes(2), "Revision"),
        AttributeDef::get(5, DataType::Word, "Status"),
        AttributeDef::get(6, DataType::Udint, "Serial Number"),
        AttributeDef::get(7, DataType::ShortString { max: 32 }, "Product Name"),
        AttributeDef::get(8, DataType::Usint, "State"),
    ],
    get_all: &[1, 2, 3, 4, 5, 6, 7],
    optional_attributes: &[8],
};

struct Identity<'c, 'a, D: Device, const C: usize>(&'c mut Ctx<'a, D, C>);

impl<D: Device, const C: usize> Object for Identity<'_, '_, D, C> {
    fn class(&self) -> &ClassDef {
        &CLASS
    }
    fn get(&mut self, _instance: u32, attr: &AttributeDef, w: &mut Writer<'_>) -> CipResult {
        let ident = *self.0.device.identity();
        match attr.id {
            1 => w.u16(ident.vendor_id)?,
            2 => w.u16(ident.device_type)?,
            3 => w.u16(ident.product_code)?,
            4 => w.bytes(&[ident.revision.0, ident.revision.1])?,

            6 => w.u32(ident.serial_number)?,
            7 => short_string(w, ident.product_name.as_bytes())?,
            // 5 and 8, from the connections and the device's faults.
            id => status_attribute(self.0, id, w)?,
        }
        Ok(())
    }
    fn service(
        &mut self,
        instance: u32,
        req: &Request<'_>,
        _w: &mut Writer<'_>,
    ) -> Option<CipResult> {
        (instance == 1 && req.service == service::RESET).then(|| reset(self.0, req.data))
    }
}

/// Handles a request to the Identity class or its instance 1.
pub(crate) fn handle<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    serve(&mut Identity(ctx), req, w)
}

/// Reset: no data or one byte, 0 (power cycle) or 1 (factory defaults); handed to the device.
/// Out of line, so the check for it stays small enough to inline into every Identity request.
#[inline(never)]
fn reset<D: Device, const C: usize>(ctx: &mut Ctx<'_, D, C>, data: &[u8]) -> CipResult {
    let kind = match data {
        [] => 0,
        [k @ (0 | 1)] => *k,
        [_] => return Err(General::InvalidParameter.into()),
        _ => return Err(General::TooMuchData.into()),
    };
    // Factory defaults are one batch of the store: the device's records and the TCP/IP
    // settings go in one save, so a power cut leaves all of them or none. The device answers
    // first: a Reset it refuses (e.g. 0x0C while a drive is enabled) drops the batch and
    // changes nothing. A store that cannot save is 0x19.
    let store = match (kind, ctx.store.as_deref_mut()) {
        (1, Some(store)) => {
            store.begin().map_err(|_| General::StoreOperationFailure)?;
            Some(store)
        }
        _ => None,
    };
    let answer = ctx.device.reset(kind);
    match store {
        Some(store) if answer.is_err() => {
            store.abandon();
            return answer;
        }
        Some(store) => {
            let removed = [
                crate::nv::key::TCP_IP,
                crate::nv::key::LLDP,
                crate::nv::key::QOS,
                crate::nv::key::ACD,
                #[cfg(feature = "cip-security")]
                crate::nv::key::SECURITY,
            ]
            .into_iter()
            .try_for_each(|key| store.remove(key));
            if removed.is_err() {
                store.abandon();
                return Err(General::StoreOperationFailure.into());
            }
            store.commit().map_err(|_| General::StoreOperationFailure)?;
        }
        None => answer?,
    }
    if kind == 1 {
        ctx.state.tcpip = super::tcpip::TcpIpState::new();
        ctx.state.lldp.config = super::lldp_management::LldpConfig::DEFAULT;
        // The defaults are configured; the values in use stay until the restart.
        ctx.state.qos = super::qos::QosState {
            active: ctx.state.qos.active,
            ..super::qos::QosState::new()
        };
        ctx.state.acd.settings = crate::acd::AcdSettings::DEFAULT;
        ctx.state.acd.saved = crate::acd::LastConflict::NONE;
        #[cfg(feature = "cip-security")]
        ctx.state.security.factory_reset();
    }
    ctx.state.pending_reset = Some(kind);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_major_fault_is_extended_status_0101_and_state_4_or_5() {
        // No fault: the connections' nibble (0011, no I/O) with the device's own bits.
        assert_eq!(status(0x0100, 0x0030), 0x0130);
        assert_eq!(state(status(0x0100, 0x0030)), 3);
        // A major recoverable fault beside an owned connection in run mode (0110).
        assert_eq!(status(0x0400, 0x0061), 0x0451);
        assert_eq!(state(status(0x0400, 0x0061)), 4);
        assert_eq!(state(status(0x0C00, 0x0030)), 5);
        // An extended status the device sets itself (0100: configuration bad) is its own.
        assert_eq!(status(0x0040, 0x0070), 0x0040);
    }
}
