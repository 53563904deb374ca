//! Assembly object (class 0x04): instance data (attribute 3) and size (attribute 4).

use super::attributes::{read_only, unsupported, Attributes};
use super::class_info::ClassInfo;
use super::router::{attribute_services, instance, no_instance};
use super::status::{CipError, CipResult, General};
use super::{Ctx, Request};
use crate::config::MAX_ASSEMBLY_SIZE;
use crate::device::{AssemblyInfo, Device};
use crate::wire::Writer;

struct Instance<'c, 'a, D: Device> {
    ctx: &'c mut Ctx<'a, D>,
    info: AssemblyInfo,
}

impl<D: Device> Attributes for Instance<'_, '_, D> {
    fn get(&mut self, id: u16, w: &mut Writer<'_>) -> CipResult {
        match id {
            3 => {
                let size = usize::from(self.info.size);
                let mut buf = [0u8; MAX_ASSEMBLY_SIZE];
                let out = buf
                    .get_mut(..size)
                    .ok_or(CipError::new(General::ReplyDataTooLarge))?;
                let n = self.ctx.device.read_assembly(self.info.instance, out)?;
                w.bytes(out.get(..n).unwrap_or(&[]))?;
            }
            4 => w.u16(self.info.size)?,
            _ => return Err(unsupported()),
        }
        Ok(())
    }
    fn set(&mut self, id: u16, data: &[u8], exact: bool) -> CipResult<usize> {
        match id {
            3 => {
                let size = usize::from(self.info.size);
                if !self.info.role.settable() {
                    return Err(read_only());
                }
                let value = super::attributes::take(data, size, exact)?;
                if self
                    .ctx
                    .connections
                    .owned_outputs()
                    .contains(&self.info.instance)
                {
                    return Err(General::DeviceStateConflict.into());
                }
                self.ctx.device.write_assembly(self.info.instance, value)?;
                Ok(size)
            }
            4 => Err(read_only()),
            _ => Err(unsupported()),
        }
    }
    fn all(&self) -> &'static [u16] {
        &[]
    }
}

/// Handles a request to the Assembly class or one of the device's assembly instances.
pub(crate) fn handle<D: Device>(
    ctx: &mut Ctx<'_, D>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    match instance(req)? {
        0 => {
            let list = ctx.device.assemblies();
            attribute_services(
                &mut ClassInfo {
                    revision: 2,
                    max_instance: list.iter().map(|a| a.instance).max().unwrap_or(0),
                    instances: list.len() as u16,
                    optional_attributes: &[4],
                    max_instance_attribute: 4,
                },
                req,
                w,
            )
        }
        n => {
            let info = find(ctx.device, n).ok_or(no_instance())?;
            attribute_services(&mut Instance { ctx, info }, req, w)
        }
    }
}

/// The assembly `instance` of `device`, if it has one.
pub(crate) fn find<D: Device>(device: &D, instance: u32) -> Option<AssemblyInfo> {
    device
        .assemblies()
        .iter()
        .find(|a| u32::from(a.instance) == instance)
        .copied()
}
