//! Device profiles, and [`Profile`] to choose one by name at run time.

pub mod generic;
pub mod kollmorgen_akd;
pub mod position_servo;

use stack::cip::context::RequestContext;
use stack::cip::object::{Access, ClassDef};
use stack::cip::request::Request;
use stack::cip::CipResult;
use stack::device::{AttributeRef, ConnectionEvent, InputChanges, Multicast, OpenRequest};
use stack::wire::Writer;
use stack::{AssemblyInfo, Device, IdentityInfo, Instant};

pub use generic::Generic;
pub use kollmorgen_akd::KollmorgenAkd;
pub use position_servo::PositionServo;

/// One of the device profiles, chosen at run time; implements [`Device`] by dispatch.
// Without a heap the profiles are held by value; the enum lives in a `static` on the boards.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Profile {
    /// The OpENer sample application's assemblies ([`Generic`]).
    Generic(Generic),
    /// The Lenze PositionServo drive ([`PositionServo`]).
    PositionServo(PositionServo),
    /// The Kollmorgen AKD servo drive ([`KollmorgenAkd`]).
    KollmorgenAkd(KollmorgenAkd),
}

/// Runs `$body` with `$dev` bound to the profile's device.
macro_rules! dispatch {
    ($profile:expr, $dev:ident => $body:expr) => {
        match $profile {
            Profile::Generic($dev) => $body,
            Profile::PositionServo($dev) => $body,
            Profile::KollmorgenAkd($dev) => $body,
        }
    };
}

impl Profile {
    /// The names [`Profile::from_name`] accepts.
    pub const NAMES: &'static [&'static str] = &["generic", "position-servo", "kollmorgen-akd"];

    /// The profile called `name` in its power-up state, if there is one.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "generic" => Some(Profile::Generic(Generic::new())),
            "position-servo" => Some(Profile::PositionServo(PositionServo::new())),
            "kollmorgen-akd" => Some(Profile::KollmorgenAkd(KollmorgenAkd::new())),
            _ => None,
        }
    }

    /// The profile's name, as [`Profile::from_name`] accepts it.
    pub const fn name(&self) -> &'static str {
        match self {
            Profile::Generic(_) => "generic",
            Profile::PositionServo(_) => "position-servo",
            Profile::KollmorgenAkd(_) => "kollmorgen-akd",
        }
    }
}

impl Default for Profile {
    fn default() -> Self {
        Profile::Generic(Generic::new())
    }
}

impl Device for Profile {
    fn identity(&self) -> &IdentityInfo {
        dispatch!(self, d => d.identity())
    }
    fn status_bits(&self) -> u16 {
        dispatch!(self, d => d.status_bits())
    }
    fn assemblies(&self) -> &[AssemblyInfo] {
        dispatch!(self, d => d.assemblies())
    }
    fn read_assembly(&mut self, instance: u16, out: &mut [u8]) -> CipResult<usize> {
        dispatch!(self, d => d.read_assembly(instance, out))
    }
    fn write_assembly(&mut self, instance: u16, data: &[u8]) -> CipResult {
        dispatch!(self, d => d.write_assembly(instance, data))
    }
    fn classes(&self) -> &[ClassDef] {
        dispatch!(self, d => d.classes())
    }
    fn has_instance(&self, class: &ClassDef, instance: u32) -> bool {
        dispatch!(self, d => d.has_instance(class, instance))
    }
    fn instance_count(&self, class: &ClassDef) -> u32 {
        dispatch!(self, d => d.instance_count(class))
    }
    fn attribute_access(&self, at: &AttributeRef<'_>) -> Access {
        dispatch!(self, d => d.attribute_access(at))
    }
    fn attribute_size(&self, at: &AttributeRef<'_>) -> Option<usize> {
        dispatch!(self, d => d.attribute_size(at))
    }
    fn get_attribute(
        &mut self,
        cx: &RequestContext,
        at: &AttributeRef<'_>,
        w: &mut Writer<'_>,
    ) -> CipResult {
        dispatch!(self, d => d.get_attribute(cx, at, w))
    }
    fn set_attribute(
        &mut self,
        cx: &RequestContext,
        at: &AttributeRef<'_>,
        value: &[u8],
    ) -> CipResult {
        dispatch!(self, d => d.set_attribute(cx, at, value))
    }
    fn handle_request(
        &mut self,
        cx: &RequestContext,
        req: &Request<'_>,
        reply: &mut Writer<'_>,
    ) -> Option<CipResult> {
        dispatch!(self, d => d.handle_request(cx, req, reply))
    }
    fn admit(&mut self, request: &OpenRequest<'_>) -> CipResult {
        dispatch!(self, d => d.admit(request))
    }
    fn input_changes(&mut self) -> Option<&mut InputChanges> {
        dispatch!(self, d => d.input_changes())
    }
    fn reset(&mut self, kind: u8) -> CipResult {
        dispatch!(self, d => d.reset(kind))
    }
    fn connection_event(&mut self, event: ConnectionEvent) {
        dispatch!(self, d => d.connection_event(event))
    }
    fn poll(&mut self, now: Instant) -> Option<Instant> {
        dispatch!(self, d => d.poll(now))
    }
    fn multicast(&self) -> Option<Multicast> {
        dispatch!(self, d => d.multicast())
    }
    fn set_multicast(&mut self, multicast: Multicast) -> CipResult {
        dispatch!(self, d => d.set_multicast(multicast))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_round_trips() {
        for name in Profile::NAMES {
            assert_eq!(Profile::from_name(name).map(|p| p.name()), Some(*name));
        }
        assert_eq!(Profile::from_name("nope"), None);
    }

    #[test]
    fn dispatches_to_the_profile() {
        let mut p = Profile::from_name("generic").unwrap();
        assert_eq!(p.identity().product_name, "enip-rs generic");
        p.write_assembly(generic::OUTPUT, &[3; 32]).unwrap();
        let mut buf = [0u8; 32];
        assert_eq!(p.read_assembly(generic::INPUT, &mut buf), Ok(32));
        assert_eq!(buf, [3; 32]);
    }
}
