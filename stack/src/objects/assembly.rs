//! Assembly object (class 0x04): instance data (attribute 3) and size (attribute 4), and
//! Get_Attributes_All (the data) where the device asks for it.

use super::serve::{serve, Object};
use super::Ctx;
use crate::cip::object::{Access, AttributeDef, ClassDef, DataType};
use crate::cip::status::{CipError, CipResult, General};
use crate::cip::{class_id, Request};
use crate::device::{AssemblyInfo, Device};
use crate::wire::Writer;

/// The Assembly class: the device's assembly instances, data and size. Data is settable on
/// output, configuration and explicit assemblies (see [`crate::AssemblyRole::settable`]).
pub const CLASS: ClassDef = ClassDef {
    id: class_id::ASSEMBLY,
    name: "Assembly",
    revision: 2,
    max_instance: 0,
    attributes: &[
        AttributeDef::get_set(3, DataType::RunTime, "Data"),
        AttributeDef::get(4, DataType::Uint, "Size"),
    ],
    get_all: &[],
    optional_attributes: &[4],
};

/// [`CLASS`] for a device whose assembly instances answer Get_Attributes_All with their data
/// ([`Device::assembly_get_attributes_all`]).
const CLASS_GET_ALL: ClassDef = ClassDef {
    get_all: &[3],
    ..CLASS
};

struct Assembly<'c, 'a, D: Device, const C: usize>(&'c mut Ctx<'a, D, C>);

impl<D: Device, const C: usize> Assembly<'_, '_, D, C> {
    fn info(&self, instance: u32) -> Option<AssemblyInfo> {
        crate::device::assembly(&*self.0.device, instance)
    }
}

impl<D: Device, const C: usize> Object for Assembly<'_, '_, D, C> {
    fn class(&self) -> &ClassDef {
        if self.0.device.assembly_get_attributes_all() {
            &CLASS_GET_ALL
        } else {
            &CLASS
        }
    }
    fn has_instance(&self, instance: u32) -> bool {
        self.info(instance).is_some()
    }
    fn max_instance(&self) -> u32 {
        let list = self.0.device.assemblies();
        list.iter()
            .map(|a| u32::from(a.instance))
            .max()
            .unwrap_or(0)
    }
    fn instance_count(&self) -> u32 {
        self.0.device.assemblies().len() as u32
    }
    fn access(&self, instance: u32, attr: &AttributeDef) -> Option<Access> {
        Some(match self.info(instance) {
            Some(info) if attr.id == 3 && info.role.settable() => Access::GetSet,
            _ => Access::Get,
        })
    }
    fn run_time_size(&self, instance: u32, _attr: &AttributeDef) -> Option<usize> {
        self.info(instance).map(|a| usize::from(a.size))
    }
    fn get(&mut self, instance: u32, attr: &AttributeDef, w: &mut Writer<'_>) -> CipResult {
        let info = self.info(instance).ok_or(General::ObjectDoesNotExist)?;
        if attr.id == 4 {
            w.u16(info.size)?;
            return Ok(());
        }
        // Read straight into the reply: the largest assembly is what the reply frame holds.
        let size = usize::from(info.size);
        let out = w
            .tail()
            .get_mut(..size)
            .ok_or(CipError::new(General::ReplyDataTooLarge))?;
        let n = self.0.device.read_assembly(info.instance, out)?;
        w.advance(if n <= size { n } else { 0 })?;
        Ok(())
    }
    fn set(&mut self, instance: u32, _attr: &AttributeDef, value: &[u8]) -> CipResult {
        let info = self.info(instance).ok_or(General::ObjectDoesNotExist)?;
        if self.0.connections.owned_outputs().contains(&info.instance) {
            return Err(General::DeviceStateConflict.into());
        }
        // A device refuses bad configuration data one way for both paths: a connection
        // failure, which a Forward_Open replies as given and a Set as an invalid value.
        let mut written = self.0.device.write_assembly(info.instance, value);
        if let Err(e) = &mut written {
            if e.general == General::ConnectionFailure {
                *e = General::InvalidAttributeValue.into();
            }
        }
        written
    }
}

/// Handles a request to the Assembly class or one of the device's assembly instances.
pub(crate) fn handle<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    serve(&mut Assembly(ctx), req, w)
}
