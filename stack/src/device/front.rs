//! [`Front`]: a device in front of another, taking over its identity or some requests and
//! forwarding everything else (a board's diagnostics class, a simulated plant's per-device
//! identity, a board's RPI floor), so that such a wrapper is a few lines rather than every
//! [`Device`] method.

use crate::cip::context::RequestContext;
use crate::cip::object::{Access, ClassDef};
use crate::cip::request::Request;
use crate::cip::status::CipResult;
use crate::time::Instant;
use crate::wire::Writer;

use super::{
    AssemblyInfo, AttributeRef, ConnectionEvent, Device, IdentityInfo, InputChanges, Multicast,
    OpenRequest,
};

/// A device in front of [`Front::Inner`]: every [`Device`] call goes to the inner device,
/// but for [`Device::identity`], [`Device::handle_request`] and [`Device::admit`], which a
/// front may take over ([`Front::front_identity`], [`Front::front_request`],
/// [`Front::front_admit`]). A type that implements it is a [`Device`].
///
/// ```
/// use enip_stack::device::Front;
/// use enip_stack::{Device, IdentityInfo};
///
/// /// `D` under another serial number.
/// struct Serial<D> {
///     inner: D,
///     identity: IdentityInfo,
/// }
///
/// impl<D: Device> Front for Serial<D> {
///     type Inner = D;
///     fn inner(&self) -> &D {
///         &self.inner
///     }
///     fn inner_mut(&mut self) -> &mut D {
///         &mut self.inner
///     }
///     fn front_identity(&self) -> &IdentityInfo {
///         &self.identity
///     }
/// }
/// # use enip_stack::cip::CipResult;
/// # use enip_stack::AssemblyInfo;
/// # struct Plain(IdentityInfo);
/// # impl Device for Plain {
/// #     fn identity(&self) -> &IdentityInfo { &self.0 }
/// #     fn assemblies(&self) -> &[AssemblyInfo] { &[] }
/// #     fn read_assembly(&mut self, _: u16, _: &mut [u8]) -> CipResult<usize> { Ok(0) }
/// #     fn write_assembly(&mut self, _: u16, _: &[u8]) -> CipResult { Ok(()) }
/// # }
/// # let id = |serial_number| IdentityInfo { vendor_id: 1, device_type: 0x2B, product_code: 1,
/// #     revision: (1, 1), serial_number, product_name: "plain" };
/// let device = Serial { inner: Plain(id(1)), identity: id(2) };
/// assert_eq!(device.identity().serial_number, 2);
/// assert_eq!(device.inner.identity().serial_number, 1);
/// ```
pub trait Front {
    /// The device behind.
    type Inner: Device;
    /// The device behind.
    fn inner(&self) -> &Self::Inner;
    /// The device behind, to call with a change.
    fn inner_mut(&mut self) -> &mut Self::Inner;
    /// [`Device::identity`]: by default the inner device's.
    fn front_identity(&self) -> &IdentityInfo {
        self.inner().identity()
    }
    /// [`Device::handle_request`]: the front sees every request first; by default the inner
    /// device's answer.
    fn front_request(
        &mut self,
        cx: &RequestContext,
        req: &Request<'_>,
        reply: &mut Writer<'_>,
    ) -> Option<CipResult> {
        self.inner_mut().handle_request(cx, req, reply)
    }
    /// [`Device::admit`]: the front judges every Forward_Open first; by default the inner
    /// device's verdict.
    fn front_admit(&mut self, request: &OpenRequest<'_>) -> CipResult {
        self.inner_mut().admit(request)
    }
}

impl<F: Front> Device for F {
    fn identity(&self) -> &IdentityInfo {
        self.front_identity()
    }
    fn status_bits(&self) -> u16 {
        self.inner().status_bits()
    }
    fn assemblies(&self) -> &[AssemblyInfo] {
        self.inner().assemblies()
    }
    fn read_assembly(&mut self, instance: u16, out: &mut [u8]) -> CipResult<usize> {
        self.inner_mut().read_assembly(instance, out)
    }
    fn write_assembly(&mut self, instance: u16, data: &[u8]) -> CipResult {
        self.inner_mut().write_assembly(instance, data)
    }
    fn accepts_connection_size(&self, assembly: &AssemblyInfo, data: usize) -> bool {
        self.inner().accepts_connection_size(assembly, data)
    }
    fn assembly_get_attributes_all(&self) -> bool {
        self.inner().assembly_get_attributes_all()
    }
    fn classes(&self) -> &[ClassDef] {
        self.inner().classes()
    }
    fn has_instance(&self, class: &ClassDef, instance: u32) -> bool {
        self.inner().has_instance(class, instance)
    }
    fn instance_count(&self, class: &ClassDef) -> u32 {
        self.inner().instance_count(class)
    }
    fn attribute_access(&self, at: &AttributeRef<'_>) -> Access {
        self.inner().attribute_access(at)
    }
    fn attribute_size(&self, at: &AttributeRef<'_>) -> Option<usize> {
        self.inner().attribute_size(at)
    }
    fn get_attribute(
        &mut self,
        cx: &RequestContext,
        at: &AttributeRef<'_>,
        w: &mut Writer<'_>,
    ) -> CipResult {
        self.inner_mut().get_attribute(cx, at, w)
    }
    fn set_attribute(
        &mut self,
        cx: &RequestContext,
        at: &AttributeRef<'_>,
        value: &[u8],
    ) -> CipResult {
        self.inner_mut().set_attribute(cx, at, value)
    }
    fn handle_request(
        &mut self,
        cx: &RequestContext,
        req: &Request<'_>,
        reply: &mut Writer<'_>,
    ) -> Option<CipResult> {
        self.front_request(cx, req, reply)
    }
    fn admit(&mut self, request: &OpenRequest<'_>) -> CipResult {
        self.front_admit(request)
    }
    fn connection_event(&mut self, event: ConnectionEvent) {
        self.inner_mut().connection_event(event)
    }
    fn input_changes(&mut self) -> Option<&mut InputChanges> {
        self.inner_mut().input_changes()
    }
    fn reset(&mut self, kind: u8) -> CipResult {
        self.inner_mut().reset(kind)
    }
    fn poll(&mut self, now: Instant) -> Option<Instant> {
        self.inner_mut().poll(now)
    }
    fn multicast(&self) -> Option<Multicast> {
        self.inner().multicast()
    }
    fn set_multicast(&mut self, multicast: Multicast) -> CipResult {
        self.inner_mut().set_multicast(multicast)
    }
}
