//! Message Router object (class 0x02): its object list, and Multiple_Service_Packet.

use super::router::{respond, MAX_DEPTH};
use super::serve::{serve, Object};
use super::Ctx;
use crate::cip::object::{AttributeDef, ClassDef, DataType};
use crate::cip::status::{CipError, CipResult, General};
use crate::cip::{class_id, service, Request};
use crate::config::MAX_MULTIPLE_SERVICES;
use crate::device::Device;
use crate::wire::{Reader, Writer};

/// Classes the stack itself implements.
const STANDARD_CLASSES: [u16; 9] = [
    class_id::IDENTITY,
    class_id::MESSAGE_ROUTER,
    class_id::ASSEMBLY,
    class_id::CONNECTION_MANAGER,
    class_id::TCP_IP_INTERFACE,
    class_id::ETHERNET_LINK,
    class_id::QOS,
    class_id::LLDP_MANAGEMENT,
    class_id::LLDP_DATA_TABLE,
];

/// The object list with the CIP Security classes (feature `cip-security`, turned on).
#[cfg(feature = "cip-security")]
fn security_object_list(w: &mut Writer<'_>, vendor: &[ClassDef]) -> CipResult {
    use super::security::{CERT_MGMT_CLASS, CIP_SECURITY_CLASS, EIP_SECURITY_CLASS};
    let security = [CIP_SECURITY_CLASS, EIP_SECURITY_CLASS, CERT_MGMT_CLASS];
    let count = STANDARD_CLASSES
        .len()
        .saturating_add(security.len())
        .saturating_add(vendor.len());
    w.u16(count as u16)?;
    let standard = STANDARD_CLASSES.iter().chain(&security);
    for c in standard.chain(vendor.iter().map(|c| &c.id)) {
        w.u16(*c)?;
    }
    Ok(())
}

/// The Message Router class: its object list and connection count, and
/// Multiple_Service_Packet.
pub const CLASS: ClassDef = ClassDef {
    id: class_id::MESSAGE_ROUTER,
    name: "Message Router",
    revision: 1,
    max_instance: 1,
    attributes: &[
        AttributeDef::get(1, DataType::Unsized, "Object List"),
        AttributeDef::get(2, DataType::Uint, "Number Available"),
    ],
    get_all: &[1, 2],
    optional_attributes: &[1, 2],
};

struct Router<'c, 'a, D: Device, const C: usize> {
    ctx: &'c mut Ctx<'a, D, C>,
    depth: u8,
}

impl<D: Device, const C: usize> Object for Router<'_, '_, D, C> {
    fn class(&self) -> &ClassDef {
        &CLASS
    }
    fn extra_optional_services(&self) -> &'static [u8] {
        &[service::MULTIPLE_SERVICE_PACKET]
    }

    fn get(&mut self, _instance: u32, attr: &AttributeDef, w: &mut Writer<'_>) -> CipResult {
        if attr.id == 2 {
            w.u16(C as u16)?;
            return Ok(());
        }
        let vendor = self.ctx.device.classes();
        #[cfg(feature = "cip-security")]
        if self.ctx.state.security.enabled {
            return security_object_list(w, vendor);
        }
        w.u16(STANDARD_CLASSES.len().saturating_add(vendor.len()) as u16)?;
        for c in STANDARD_CLASSES.iter().chain(vendor.iter().map(|c| &c.id)) {
            w.u16(*c)?;
        }
        Ok(())
    }
    fn service(
        &mut self,
        instance: u32,
        req: &Request<'_>,
        w: &mut Writer<'_>,
    ) -> Option<CipResult> {
        (instance == 1 && req.service == service::MULTIPLE_SERVICE_PACKET)
            .then(|| multiple_service_packet(self.ctx, req.data, w, self.depth))
    }
}

/// Handles a request to the Message Router class or its instance 1.
pub(crate) fn handle<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
    depth: u8,
) -> CipResult {
    serve(&mut Router { ctx, depth }, req, w)
}

/// Multiple_Service_Packet: runs each embedded request in order and replies with a count, an
/// offset table and every embedded response; 0x1E if any embedded service failed. A count of
/// 0 is an invalid parameter (0x20), an offset table or an offset beyond the data not enough
/// data (0x13), more services than [`MAX_MULTIPLE_SERVICES`] resource unavailable (0x02),
/// offsets into the table or not increasing an invalid parameter (0x20).
#[allow(
    clippy::arithmetic_side_effects,
    reason = "count is at most MAX_MULTIPLE_SERVICES (checked first); offsets are positions in the writer, after `base`; depth is below MAX_DEPTH"
)]
fn multiple_service_packet<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    data: &[u8],
    w: &mut Writer<'_>,
    depth: u8,
) -> CipResult {
    if depth >= MAX_DEPTH {
        return Err(General::ServiceNotSupported.into());
    }
    let mut r = Reader::new(data);
    let count = usize::from(r.u16()?);
    if count == 0 {
        return Err(General::InvalidParameter.into());
    }
    if r.remaining() < 2 * count {
        return Err(General::NotEnoughData.into());
    }
    if count > MAX_MULTIPLE_SERVICES {
        return Err(General::ResourceUnavailable.into());
    }
    // `count` is at most MAX_MULTIPLE_SERVICES here: no overflow.
    let table_len = count.saturating_mul(2).saturating_add(2);
    let mut offsets = [0usize; MAX_MULTIPLE_SERVICES + 1];
    for slot in offsets.iter_mut().take(count) {
        *slot = usize::from(r.u16()?);
    }
    if let Some(end) = offsets.get_mut(count) {
        *end = data.len();
    }
    let bounds = offsets.get(..=count).unwrap_or(&[]);
    if bounds.iter().any(|&o| o > data.len()) {
        return Err(General::NotEnoughData.into());
    }
    if bounds.first().is_some_and(|&o| o < table_len)
        || bounds.windows(2).any(|p| matches!(p, [a, b] if a >= b))
    {
        return Err(General::InvalidParameter.into());
    }
    let base = w.len();
    w.u16(count as u16)?;
    w.zeros(2 * count)?;
    let mut failed = false;
    for (i, pair) in bounds.windows(2).enumerate() {
        let sub = match pair {
            [from, to] => data.get(*from..*to).unwrap_or(&[]),
            _ => &[],
        };
        let at = w.len();
        let entry = base.saturating_add(2).saturating_add(i.saturating_mul(2));
        w.patch_u16(entry, at.saturating_sub(base) as u16);
        respond(ctx, sub, w, depth.saturating_add(1))?;
        failed |= w
            .written()
            .get(at.saturating_add(2))
            .is_some_and(|&s| s != 0);
    }
    if failed {
        return Err(CipError::new(General::EmbeddedServiceError).keeping_data());
    }
    Ok(())
}
