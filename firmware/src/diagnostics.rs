//! The board's diagnostics object, vendor-specific class [`CLASS`] (0x3A0, in the CIP range
//! 0x300-0x4FF left to vendors), served in front of any device profile by [`Diagnosed`]:
//!
//! | instance 1 attribute | type  | value                                                   |
//! |----------------------|-------|---------------------------------------------------------|
//! | 1                    | UDINT | bytes of the call stack region                          |
//! | 2                    | UDINT | bytes of it painted at boot (the deepest depth measurable)|
//! | 3                    | UDINT | the deepest use since boot, in bytes (the high-water mark)|
//!
//! Get_Attribute_Single only (0x08 for other services, 0x14 other attributes, 0x16 other
//! instances). A read of attribute 3 also logs the mark. Test images of a board add service
//! [`PROVOKE`] (data: one byte, a fault kind the board knows) to fault on purpose.

use enip_stack::cip::context::RequestContext;
use enip_stack::cip::request::Request;
use enip_stack::cip::service::GET_ATTRIBUTE_SINGLE;
use enip_stack::cip::status::{CipError, CipResult, General};
use enip_stack::device::Front;
use enip_stack::wire::Writer;
use enip_stack::Device;

/// The diagnostics class.
pub const CLASS: u32 = 0x3A0;
/// The test images' service that faults on purpose (a class-specific service code).
pub const PROVOKE: u8 = 0x4B;

/// The call stack's use, as the board measures it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StackUse {
    /// Bytes of the stack region.
    pub size: u32,
    /// Bytes painted at boot: the deepest use the board can see.
    pub painted: u32,
    /// The deepest use since boot, in bytes.
    pub deepest: u32,
}

/// What the board supplies: its stack measurement, and in test images the fault trigger.
#[derive(Debug, Clone, Copy)]
pub struct Platform {
    /// Measures the stack now.
    pub stack: fn() -> StackUse,
    /// Faults on purpose (test images only): called with [`PROVOKE`]'s data byte.
    pub provoke: Option<fn(u8)>,
}

/// A device with the diagnostics class in front of it.
pub struct Diagnosed<D> {
    device: D,
    platform: Platform,
}

impl<D: Device> Diagnosed<D> {
    /// `device` with the board's `platform` diagnostics.
    pub const fn new(device: D, platform: Platform) -> Self {
        Diagnosed { device, platform }
    }

    /// Serves a request to [`CLASS`].
    fn serve(&self, req: &Request<'_>, reply: &mut Writer<'_>) -> CipResult {
        match (req.service, self.platform.provoke) {
            (GET_ATTRIBUTE_SINGLE, _) => {}
            (PROVOKE, Some(provoke)) => {
                let [kind] = req.data else {
                    return Err(General::InvalidParameter.into());
                };
                provoke(*kind);
                return Ok(());
            }
            _ => return Err(General::ServiceNotSupported.into()),
        }
        if req.path.instance != Some(1) {
            return Err(General::ObjectDoesNotExist.into());
        }
        let stack = (self.platform.stack)();
        let value = match req.path.attribute {
            Some(1) => stack.size,
            Some(2) => stack.painted,
            Some(3) => {
                info!(
                    "stack high-water mark: {} of {} bytes painted ({} in the region)",
                    stack.deepest, stack.painted, stack.size
                );
                stack.deepest
            }
            _ => return Err(General::AttributeNotSupported.into()),
        };
        reply.u32(value).map_err(CipError::from)
    }
}

impl<D: Device> Front for Diagnosed<D> {
    type Inner = D;
    fn inner(&self) -> &D {
        &self.device
    }
    fn inner_mut(&mut self) -> &mut D {
        &mut self.device
    }
    fn front_request(
        &mut self,
        cx: &RequestContext,
        req: &Request<'_>,
        reply: &mut Writer<'_>,
    ) -> Option<CipResult> {
        if req.path.class == Some(CLASS) {
            return Some(self.serve(req, reply));
        }
        self.device.handle_request(cx, req, reply)
    }
}

#[cfg(test)]
mod tests;
