//! Identity object (class 0x01): who the device is, its status, and the Reset service.

use super::attributes::{read_only_up_to, unsupported, Attributes};
use super::class_info::ClassInfo;
use super::encoding::short_string;
use super::router::{attribute_services, instance, no_instance};
use super::status::{CipResult, General};
use super::{service, Ctx, Request};
use crate::device::Device;
use crate::wire::Writer;

/// Identity state attribute value: operational.
const STATE_OPERATIONAL: u8 = 3;

struct Instance<'c, 'a, D: Device>(&'c mut Ctx<'a, D>);

impl<D: Device> Attributes for Instance<'_, '_, D> {
    fn get(&mut self, id: u16, w: &mut Writer<'_>) -> CipResult {
        let ident = *self.0.device.identity();
        match id {
            1 => w.u16(ident.vendor_id)?,
            2 => w.u16(ident.device_type)?,
            3 => w.u16(ident.product_code)?,
            4 => w.bytes(&[ident.revision.0, ident.revision.1])?,
            5 => w.u16(self.0.identity_status())?,
            6 => w.u32(ident.serial_number)?,
            7 => short_string(w, ident.product_name.as_bytes())?,
            8 => w.u8(STATE_OPERATIONAL)?,
            _ => return Err(unsupported()),
        }
        Ok(())
    }
    fn set(&mut self, id: u16, _data: &[u8], _exact: bool) -> CipResult<usize> {
        Err(read_only_up_to(id, 8))
    }
    fn all(&self) -> &'static [u16] {
        &[1, 2, 3, 4, 5, 6, 7]
    }
}

/// Handles a request to the Identity class or its instance 1.
pub(crate) fn handle<D: Device>(
    ctx: &mut Ctx<'_, D>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    match instance(req)? {
        0 => attribute_services(
            &mut ClassInfo {
                revision: 1,
                max_instance: 1,
                instances: 1,
                optional_attributes: &[8],
                max_instance_attribute: 8,
            },
            req,
            w,
        ),
        1 if req.service == service::RESET => reset(ctx, req.data),
        1 => attribute_services(&mut Instance(ctx), req, w),
        _ => Err(no_instance()),
    }
}

/// Reset: no data or one byte, 0 (power cycle) or 1 (factory defaults); handed to the device.
fn reset<D: Device>(ctx: &mut Ctx<'_, D>, data: &[u8]) -> CipResult {
    let kind = match data {
        [] => 0,
        [k @ (0 | 1)] => *k,
        [_] => return Err(General::InvalidParameter.into()),
        _ => return Err(General::TooMuchData.into()),
    };
    ctx.device.reset(kind)?;
    if kind == 1 {
        ctx.state.tcpip = super::tcpip::TcpIpState::new();
    }
    ctx.state.pending_reset = Some(kind);
    Ok(())
}
