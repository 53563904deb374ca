//! [`Profile`]: one of the compiled-in profiles, chosen by name at run time, implementing
//! [`Device`] by dispatch. Each profile is one line of [`profiles!`]'s invocation.

use enip_stack::cip::context::RequestContext;
use enip_stack::cip::object::{Access, ClassDef};
use enip_stack::cip::request::Request;
use enip_stack::cip::CipResult;
use enip_stack::device::{AttributeRef, ConnectionEvent, InputChanges, Multicast, OpenRequest};
use enip_stack::eds::EdsInfo;
use enip_stack::nv::SharedStore;
use enip_stack::wire::Writer;
use enip_stack::{AssemblyInfo, Device, IdentityInfo, Instant};

/// Defines [`Profile`] over `name Variant(Type) eds_info;` lines: a variant, a name and an
/// EDS description per profile, each only with its feature (the feature is the name).
macro_rules! profiles {
    ($($name:literal $variant:ident($ty:ty) $eds:path, $doc:literal;)*) => {
        /// One of the device profiles, chosen at run time; implements [`Device`] by dispatch.
        // Without a heap the profiles are held by value.
        #[allow(clippy::large_enum_variant)]
        #[derive(Debug, Clone, PartialEq, Eq)]
        pub enum Profile {
            $(
                #[doc = $doc]
                #[cfg(feature = $name)]
                $variant($ty),
            )*
        }

        impl Profile {
            /// The names [`Profile::from_name`] accepts (the profiles compiled in).
            pub const NAMES: &'static [&'static str] = &[$(#[cfg(feature = $name)] $name,)*];

            /// The profile called `name` in its power-up state, if it is compiled in.
            pub fn from_name(name: &str) -> Option<Self> {
                match name {
                    $(#[cfg(feature = $name)] $name => Some(Profile::$variant(<$ty>::new())),)*
                    _ => None,
                }
            }

            /// The profile's name, as [`Profile::from_name`] accepts it.
            pub const fn name(&self) -> &'static str {
                match self {
                    $(#[cfg(feature = $name)] Profile::$variant(_) => $name,)*
                }
            }

            /// What the profile's EDS file says beyond the device's own description.
            pub const fn eds_info(&self) -> &'static EdsInfo<'static> {
                match self {
                    $(#[cfg(feature = $name)] Profile::$variant(_) => &$eds,)*
                }
            }
        }

        /// The first profile compiled in (`generic` when it is).
        impl Default for Profile {
            // Each profile's block returns; the ones after the first compiled in are never
            // reached.
            #[allow(unreachable_code)]
            fn default() -> Self {
                $(#[cfg(feature = $name)] {
                    return Profile::$variant(<$ty>::new());
                })*
            }
        }

        /// Runs `$body` with `$dev` bound to the profile's device.
        macro_rules! dispatch {
            ($profile:expr, $dev:ident => $body:expr) => {
                match $profile {
                    $(#[cfg(feature = $name)] Profile::$variant($dev) => $body,)*
                }
            };
        }
    };
}

profiles! {
    "generic" Generic(super::Generic) super::generic::EDS,
        "The OpENer sample application's assemblies ([`super::Generic`]).";
    "position-servo" PositionServo(super::PositionServo)
        super::position_servo::eds::EDS, "The Lenze PositionServo drive ([`super::PositionServo`]).";
    "parker-ipa" ParkerIpa(super::ParkerIpa) super::parker_ipa::eds::EDS,
        "The Parker IPA / ACR9000 controller ([`super::ParkerIpa`]).";
    "ametek-pls" AmetekPls(super::AmetekPls) super::ametek_pls::eds::EDS,
        "The Ametek 7500 programmable limit switch ([`super::AmetekPls`]).";
    "kollmorgen-akd" KollmorgenAkd(super::KollmorgenAkd)
        super::kollmorgen_akd::eds::EDS, "The Kollmorgen AKD servo drive ([`super::KollmorgenAkd`]).";
}

impl Profile {
    /// Keeps the profile's saved settings (PositionServo EPM, AKD DRV.NVSAVE parameters,
    /// Ametek NVRAM program) in `store` from now on, each in its own record: the profile
    /// powers up again from what the store holds ([`super::PoweredUp`]). Generic and Parker
    /// IPA save nothing.
    pub fn attach_store(&mut self, store: SharedStore) {
        dispatch!(self, p => *p = super::PoweredUp::powered_up(store))
    }

    /// The profile's EDS file.
    pub fn write_eds(&self, w: &mut impl core::fmt::Write) -> core::fmt::Result {
        enip_stack::eds::write_eds(w, self, self.eds_info())
    }
}

/// Implements [`Device`] for [`Profile`] by dispatch, one line per method of the trait, and
/// lists them in `FORWARDED`; a test compares that list with the trait's methods in the
/// stack's source, so a method added to the trait cannot be left to its default here.
macro_rules! forward_device {
    (
        &self: $(fn $name:ident($s:ident $(, $arg:ident: $ty:ty)*) $(-> $ret:ty)?;)*
        &mut self: $(fn $mname:ident($ms:ident $(, $marg:ident: $mty:ty)*) $(-> $mret:ty)?;)*
    ) => {
        impl Device for Profile {
            $(fn $name(&$s $(, $arg: $ty)*) $(-> $ret)? {
                dispatch!($s, d => d.$name($($arg),*))
            })*
            $(fn $mname(&mut $ms $(, $marg: $mty)*) $(-> $mret)? {
                dispatch!($ms, d => d.$mname($($marg),*))
            })*
        }

        /// The [`Device`] methods [`Profile`] forwards.
        #[cfg(test)]
        const FORWARDED: &[&str] = &[$(stringify!($name),)* $(stringify!($mname),)*];
    };
}

forward_device! {
    &self:
    fn identity(self) -> &IdentityInfo;
    fn status_bits(self) -> u16;
    fn assemblies(self) -> &[AssemblyInfo];
    fn accepts_connection_size(self, assembly: &AssemblyInfo, data: usize) -> bool;
    fn assembly_get_attributes_all(self) -> bool;
    fn classes(self) -> &[ClassDef];
    fn has_instance(self, class: &ClassDef, instance: u32) -> bool;
    fn instance_count(self, class: &ClassDef) -> u32;
    fn attribute_access(self, at: &AttributeRef<'_>) -> Access;
    fn attribute_size(self, at: &AttributeRef<'_>) -> Option<usize>;
    fn multicast(self) -> Option<Multicast>;
    &mut self:
    fn read_assembly(self, instance: u16, out: &mut [u8]) -> CipResult<usize>;
    fn write_assembly(self, instance: u16, data: &[u8]) -> CipResult;
    fn get_attribute(self, cx: &RequestContext, at: &AttributeRef<'_>, w: &mut Writer<'_>)
        -> CipResult;
    fn set_attribute(self, cx: &RequestContext, at: &AttributeRef<'_>, value: &[u8]) -> CipResult;
    fn handle_request(self, cx: &RequestContext, req: &Request<'_>, reply: &mut Writer<'_>)
        -> Option<CipResult>;
    fn admit(self, request: &OpenRequest<'_>) -> CipResult;
    fn input_changes(self) -> Option<&mut InputChanges>;
    fn reset(self, kind: u8) -> CipResult;
    fn connection_event(self, event: ConnectionEvent);
    fn poll(self, now: Instant) -> Option<Instant>;
    fn set_multicast(self, multicast: Multicast) -> CipResult;
}

#[cfg(test)]
mod tests {
    use super::*;

    extern crate std;
    use std::string::String;
    use std::vec::Vec;

    /// The methods of `pub trait Device` in the stack's source (wherever it is declared).
    fn device_trait_methods() -> Vec<String> {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../stack/src");
        let mut dirs = std::vec![root];
        let mut methods = Vec::new();
        while let Some(dir) = dirs.pop() {
            for entry in std::fs::read_dir(&dir).unwrap().flatten() {
                let path = entry.path();
                if path.is_dir() {
                    dirs.push(path);
                    continue;
                }
                let text = std::fs::read_to_string(&path).unwrap_or_default();
                let mut lines = text.lines().skip_while(|l| {
                    let rest = l.strip_prefix("pub trait Device").unwrap_or("x");
                    !(rest.starts_with(' ') || rest.starts_with(':') || rest.starts_with('{'))
                });
                if lines.next().is_none() {
                    continue;
                }
                for line in lines.take_while(|l| *l != "}") {
                    if let Some(rest) = line.strip_prefix("    fn ") {
                        let name = rest.split(['(', '<']).next().unwrap();
                        methods.push(name.into());
                    }
                }
            }
        }
        methods
    }

    /// A method added to `Device` with a default would otherwise run that default for every
    /// profile behind the enum (as `accepts_connection_size` once did for the Parker IPA).
    #[test]
    fn forwards_every_device_method() {
        let mut trait_methods = device_trait_methods();
        assert!(trait_methods.len() >= 21, "{trait_methods:?}");
        let mut forwarded: Vec<String> = FORWARDED.iter().map(|m| String::from(*m)).collect();
        trait_methods.sort();
        forwarded.sort();
        assert_eq!(forwarded, trait_methods);
    }

    #[test]
    fn every_name_round_trips() {
        for name in Profile::NAMES {
            assert_eq!(Profile::from_name(name).map(|p| p.name()), Some(*name));
        }
        assert_eq!(Profile::from_name("nope"), None);
    }

    /// Every profile's EDS in `eds/` is what the profile says today (`UPDATE_EDS=1`
    /// rewrites them).
    #[test]
    fn every_eds_file_is_current() {
        extern crate std;
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../eds");
        for name in Profile::NAMES {
            let mut eds = std::string::String::new();
            Profile::from_name(name)
                .unwrap()
                .write_eds(&mut eds)
                .unwrap();
            let path = dir.join(std::format!("{name}.eds"));
            if std::env::var_os("UPDATE_EDS").is_some() {
                std::fs::write(&path, &eds).unwrap();
            }
            let committed = std::fs::read_to_string(&path).unwrap_or_default();
            assert!(
                committed == eds,
                "{} is stale: UPDATE_EDS=1 cargo test -p enip-profiles eds",
                path.display()
            );
        }
    }

    #[cfg(feature = "generic")]
    #[test]
    fn dispatches_to_the_profile() {
        let mut p = Profile::from_name("generic").unwrap();
        assert_eq!(p.identity().product_name, "enip-rs generic");
        p.write_assembly(super::super::generic::OUTPUT, &[3; 32])
            .unwrap();
        let mut buf = [0u8; 32];
        assert_eq!(
            p.read_assembly(super::super::generic::INPUT, &mut buf),
            Ok(32)
        );
        assert_eq!(buf, [3; 32]);
    }
}
