//! A device's vendor classes, served by the same machinery as the built-in objects: the
//! device's [`ClassDef`]s and its [`Device`] value hooks seen as an [`Object`].

use super::serve::{serve, Object};
use super::Ctx;
use crate::cip::object::{Access, AttributeDef, ClassDef};
use crate::cip::status::{CipError, CipResult, General};
use crate::cip::Request;
use crate::device::{AttributeRef, Device};
use crate::wire::Writer;

struct Vendor<'c, 'a, D: Device, const C: usize> {
    ctx: &'c mut Ctx<'a, D, C>,
    def: ClassDef,
}

impl<D: Device, const C: usize> Vendor<'_, '_, D, C> {
    fn at<'r>(&'r self, instance: u32, attribute: &'r AttributeDef) -> AttributeRef<'r> {
        AttributeRef {
            class: &self.def,
            instance,
            attribute,
        }
    }
}

impl<D: Device, const C: usize> Object for Vendor<'_, '_, D, C> {
    fn class(&self) -> &ClassDef {
        &self.def
    }
    fn has_instance(&self, instance: u32) -> bool {
        self.ctx.device.has_instance(&self.def, instance)
    }
    fn instance_count(&self) -> u32 {
        self.ctx.device.instance_count(&self.def)
    }
    fn access(&self, instance: u32, attr: &AttributeDef) -> Option<Access> {
        Some(self.ctx.device.attribute_access(&self.at(instance, attr)))
    }
    fn run_time_size(&self, instance: u32, attr: &AttributeDef) -> Option<usize> {
        self.ctx.device.attribute_size(&self.at(instance, attr))
    }
    fn get(&mut self, instance: u32, attribute: &AttributeDef, w: &mut Writer<'_>) -> CipResult {
        let at = AttributeRef {
            class: &self.def,
            instance,
            attribute,
        };
        self.ctx.device.get_attribute(&self.ctx.request, &at, w)
    }
    fn set(&mut self, instance: u32, attribute: &AttributeDef, value: &[u8]) -> CipResult {
        let at = AttributeRef {
            class: &self.def,
            instance,
            attribute,
        };
        self.ctx.device.set_attribute(&self.ctx.request, &at, value)
    }
    fn service(
        &mut self,
        _instance: u32,
        req: &Request<'_>,
        w: &mut Writer<'_>,
    ) -> Option<CipResult> {
        self.ctx.device.handle_request(&self.ctx.request, req, w)
    }
}

/// Handles a request for `class` (not a built-in one): a declared class is served, anything
/// else goes to [`Device::handle_request`]; 0x05 if the device has nothing for it either.
pub(crate) fn handle<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    class: Option<u16>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    let declared = class.and_then(|id| ctx.device.classes().iter().find(|c| c.id == id).copied());
    match declared {
        Some(def) => serve(&mut Vendor { ctx, def }, req, w),
        None => {
            let cx = ctx.request;
            ctx.device
                .handle_request(&cx, req, w)
                .unwrap_or(Err(CipError::new(General::PathDestinationUnknown)))
        }
    }
}
