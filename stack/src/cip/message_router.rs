//! Message Router object (class 0x02): its object list, and Multiple_Service_Packet.

use super::attributes::{read_only_up_to, unsupported, Attributes};
use super::class_info::ClassInfo;
use super::router::{attribute_services, instance, no_instance, respond, MAX_DEPTH};
use super::status::{CipError, CipResult, General};
use super::{class_id, service, Ctx, Request};
use crate::config::{MAX_CONNECTIONS, MAX_MULTIPLE_SERVICES};
use crate::device::Device;
use crate::wire::{Reader, Writer};

/// Classes the stack itself implements.
const STANDARD_CLASSES: [u16; 6] = [
    class_id::IDENTITY,
    class_id::MESSAGE_ROUTER,
    class_id::ASSEMBLY,
    class_id::CONNECTION_MANAGER,
    class_id::TCP_IP_INTERFACE,
    class_id::ETHERNET_LINK,
];

struct Instance<'c, 'a, D: Device>(&'c mut Ctx<'a, D>);

impl<D: Device> Attributes for Instance<'_, '_, D> {
    fn get(&mut self, id: u16, w: &mut Writer<'_>) -> CipResult {
        match id {
            1 => {
                let vendor = self.0.device.vendor_classes();
                w.u16((STANDARD_CLASSES.len() + vendor.len()) as u16)?;
                for c in STANDARD_CLASSES.iter().chain(vendor) {
                    w.u16(*c)?;
                }
            }
            2 => w.u16(MAX_CONNECTIONS as u16)?,
            _ => return Err(unsupported()),
        }
        Ok(())
    }
    fn set(&mut self, id: u16, _data: &[u8], _exact: bool) -> CipResult<usize> {
        Err(read_only_up_to(id, 2))
    }
    fn all(&self) -> &'static [u16] {
        &[1, 2]
    }
}

/// Handles a request to the Message Router class or its instance 1.
pub(crate) fn handle<D: Device>(
    ctx: &mut Ctx<'_, D>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
    depth: u8,
) -> CipResult {
    match instance(req)? {
        0 => attribute_services(
            &mut ClassInfo {
                revision: 1,
                max_instance: 1,
                instances: 1,
                optional_attributes: &[1, 2],
                max_instance_attribute: 2,
            },
            req,
            w,
        ),
        1 if req.service == service::MULTIPLE_SERVICE_PACKET => {
            multiple_service_packet(ctx, req.data, w, depth)
        }
        1 => attribute_services(&mut Instance(ctx), req, w),
        _ => Err(no_instance()),
    }
}

/// Multiple_Service_Packet: runs each embedded request in order and replies with a count, an
/// offset table and every embedded response; 0x1E if any embedded service failed.
fn multiple_service_packet<D: Device>(
    ctx: &mut Ctx<'_, D>,
    data: &[u8],
    w: &mut Writer<'_>,
    depth: u8,
) -> CipResult {
    if depth >= MAX_DEPTH {
        return Err(General::ServiceNotSupported.into());
    }
    let mut r = Reader::new(data);
    let count = usize::from(r.u16()?);
    if count == 0 || count > MAX_MULTIPLE_SERVICES {
        return Err(General::InvalidParameter.into());
    }
    let table_len = 2 + 2 * count;
    let mut offsets = [0usize; MAX_MULTIPLE_SERVICES + 1];
    for slot in offsets.iter_mut().take(count) {
        *slot = usize::from(r.u16()?);
    }
    if let Some(end) = offsets.get_mut(count) {
        *end = data.len();
    }
    let bounds = offsets.get(..=count).unwrap_or(&[]);
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
        w.patch_u16(base + 2 + 2 * i, (at - base) as u16);
        respond(ctx, sub, w, depth + 1)?;
        failed |= w.written().get(at + 2).is_some_and(|&s| s != 0);
    }
    if failed {
        return Err(CipError::new(General::EmbeddedServiceError).keeping_data());
    }
    Ok(())
}
