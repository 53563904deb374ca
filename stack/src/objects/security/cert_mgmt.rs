//! Certificate Management object (class 0x5F): one instance per certificate set (a device
//! certificate and a CA certificate), instance 1 the factory one, more made by Create and
//! removed by Delete; the class attributes Capability Flags, Certificate List and
//! Certificate Encodings Flag.
//!
//! The certificates' bytes live with the runtime (on the host, files; the factory device
//! certificate generated at first start): the attributes report each certificate's status as
//! the runtime found it ([`crate::Adapter::set_certificate_status`]) and a path to the File
//! object (0x37) instance that serves the certificate the runtime uses (instance 1 only,
//! through the runtime's [`super::CsrSigner`]; an empty path otherwise). Create_CSR (0x4B) needs a key pair and a
//! signature, which the stack does not have: the runtime's signer makes the request
//! ([`super::csr`]), and without one the service answers 0x08 (service not supported).

use super::super::serve::{serve, Object};
use super::super::Ctx;
use super::{SecurityState, CERT_MGMT_CLASS};
use crate::cip::encoding::short_string;
use crate::cip::object::{AttributeDef, ClassDef, DataType};
use crate::cip::status::{CipError, CipResult, General};
use crate::cip::{service, Request};
use crate::device::Device;
use crate::wire::{Reader, Writer};

/// Instances at most: the factory one and three created.
pub const MAX_CERTS: usize = 4;
/// Most characters of an instance's name (a SHORT_STRING).
pub const MAX_CERT_NAME: usize = 32;
/// The factory instance's name.
const FACTORY_NAME: &[u8] = b"Default Device Certificate";
/// Service codes of the class.
const CREATE: u8 = 0x08;
const DELETE: u8 = 0x09;
const VERIFY_CERTIFICATE: u8 = 0x4C;
/// Class attribute 8, Capability Flags: push model (certificates written by a tool).
const CAPABILITY_PUSH: u32 = 1 << 0;
/// Class attribute 10, Certificate Encodings Flag: PEM.
const ENCODINGS_PEM: u32 = 1 << 0;

/// What the runtime found of a certificate (attributes 3 and 4, Certificate Status).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CertStatus {
    /// 0: none, or not checked.
    NotVerified = 0,
    /// 1: loaded and checked.
    Verified = 1,
    /// 2: present but unusable (unreadable, expired, not signed by its CA).
    Invalid = 2,
}

/// One Certificate Management instance.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CertInstance {
    /// The instance exists.
    pub exists: bool,
    /// Attribute 1: its name.
    pub name: heapless::Vec<u8, MAX_CERT_NAME>,
    /// Attribute 5: 0 PEM, 1 PKCS#7.
    pub encoding: u8,
    /// Attribute 3's status: the device certificate.
    pub device: CertStatus,
    /// Attribute 4's status: the CA certificate.
    pub ca: CertStatus,
    /// A CSR was made for it (Create_CSR): attribute 2 says Configuring until verified.
    pub configuring: bool,
}

impl CertInstance {
    /// No instance.
    pub const fn none() -> Self {
        CertInstance {
            exists: false,
            name: heapless::Vec::new(),
            encoding: 0,
            device: CertStatus::NotVerified,
            ca: CertStatus::NotVerified,
            configuring: false,
        }
    }
    /// A created instance named `name` (at most [`MAX_CERT_NAME`] bytes).
    pub fn created(name: &[u8], encoding: u8) -> Option<Self> {
        Some(CertInstance {
            exists: true,
            name: heapless::Vec::from_slice(name).ok()?,
            encoding,
            ..Self::none()
        })
    }
    /// Attribute 2: 1 Created, 2 Configuring (a CSR made), 3 Verified (its device
    /// certificate checked), 4 Invalid.
    pub fn state(&self) -> u8 {
        match self.device {
            CertStatus::NotVerified if self.configuring => 2,
            CertStatus::NotVerified => 1,
            CertStatus::Verified => 3,
            CertStatus::Invalid => 4,
        }
    }
}

/// Instance 1 only, the factory device certificate's.
pub(crate) fn factory_instances() -> [CertInstance; MAX_CERTS] {
    let mut certs = [const { CertInstance::none() }; MAX_CERTS];
    if let (Some(first), Some(c)) = (certs.first_mut(), CertInstance::created(FACTORY_NAME, 0)) {
        *first = c;
    }
    certs
}

/// The Certificate Management class.
pub const CLASS: ClassDef = ClassDef {
    id: CERT_MGMT_CLASS,
    name: "Certificate Management",
    revision: 1,
    max_instance: MAX_CERTS as u32,
    attributes: &[
        AttributeDef::get(1, DataType::ShortString { max: 32 }, "Name"),
        AttributeDef::get(2, DataType::Usint, "State"),
        AttributeDef::get(3, DataType::Unsized, "Device Certificate"),
        AttributeDef::get(4, DataType::Unsized, "CA Certificate"),
        AttributeDef::get(5, DataType::Usint, "Certificate Encoding"),
    ],
    get_all: &[1, 2, 3, 4, 5],
    optional_attributes: &[],
};

/// A padded EPATH with its USINT size in words, naming instance `instance` of `class`.
pub(crate) fn emit_path(w: &mut Writer<'_>, class: u8, instance: u8) -> CipResult {
    w.bytes(&[2, 0x20, class, 0x24, instance])?;
    Ok(())
}

/// Reads a padded EPATH with its USINT size naming a Certificate Management instance:
/// 0x09 if it names anything else or an instance that does not exist.
pub(crate) fn read_path(r: &mut Reader<'_>, st: &SecurityState) -> CipResult<u8> {
    let words = usize::from(r.u8()?);
    let path = r.take(words.saturating_mul(2))?;
    let instance = match *path {
        [0x20, c, 0x24, i] if u16::from(c) == CERT_MGMT_CLASS => u16::from(i),
        [0x20, c, 0x25, 0, lo, hi] if u16::from(c) == CERT_MGMT_CLASS => {
            u16::from_le_bytes([lo, hi])
        }
        _ => return Err(General::InvalidAttributeValue.into()),
    };
    match u8::try_from(instance) {
        Ok(i) if st.cert(u32::from(i)).is_some() => Ok(i),
        _ => Err(General::InvalidAttributeValue.into()),
    }
}

struct CertMgmt<'c, 'a, D: Device, const C: usize>(&'c mut Ctx<'a, D, C>);

impl<D: Device, const C: usize> CertMgmt<'_, '_, D, C> {
    fn st(&self) -> &SecurityState {
        &self.0.state.security
    }

    /// The class attributes 8-10 (Get_Attribute_Single at instance 0).
    fn class_attribute(&self, id: Option<u32>, w: &mut Writer<'_>) -> Option<CipResult> {
        let r = match id? {
            8 => w.u32(CAPABILITY_PUSH).map_err(CipError::from),
            9 => self.certificate_list(w),
            10 => w.u32(ENCODINGS_PEM).map_err(CipError::from),
            _ => return None,
        };
        Some(r)
    }

    fn certificate_list(&self, w: &mut Writer<'_>) -> CipResult {
        let existing = self.st().certs.iter().zip(1u8..).filter(|(c, _)| c.exists);
        w.u8(existing.clone().count() as u8)?;
        for (c, i) in existing {
            short_string(w, &c.name)?;
            emit_path(w, CERT_MGMT_CLASS as u8, i)?;
        }
        Ok(())
    }

    /// Create: a SHORT_STRING name in, the new instance number out.
    fn create(&mut self, data: &[u8], w: &mut Writer<'_>) -> CipResult {
        let mut r = Reader::new(data);
        let len = usize::from(r.u8()?);
        let name = r.take(len)?;
        if r.remaining() != 0 {
            return Err(General::TooMuchData.into());
        }
        if name.is_empty() || name.len() > MAX_CERT_NAME {
            return Err(General::InvalidParameter.into());
        }
        let st = &mut self.0.state.security;
        let (slot, instance) = st
            .certs
            .iter_mut()
            .zip(1u16..)
            .find(|(c, _)| !c.exists)
            .ok_or(CipError::new(General::ResourceUnavailable))?;
        *slot = CertInstance::created(name, 0).ok_or(CipError::new(General::InvalidParameter))?;
        if save_or_undo(self.0, instance).is_err() {
            return Err(General::StoreOperationFailure.into());
        }
        w.u16(instance)?;
        Ok(())
    }

    /// Delete: not the factory instance (0x2D), not one the TLS settings name (0x0C).
    fn delete(&mut self, instance: u32, data: &[u8]) -> CipResult {
        if !data.is_empty() {
            return Err(General::TooMuchData.into());
        }
        if instance == 1 {
            return Err(General::InstanceNotDeletable.into());
        }
        let st = &self.0.state.security;
        let named = |s: &super::TlsSettings| {
            [s.active_cert, s.trusted_ca].contains(&u8::try_from(instance).ok())
        };
        if named(&st.active) || named(&st.pending) {
            return Err(General::ObjectStateConflict.into());
        }
        let index = usize::try_from(instance).unwrap_or(0).saturating_sub(1);
        let Some(slot) = self.0.state.security.certs.get_mut(index) else {
            return Err(General::ObjectDoesNotExist.into());
        };
        let before = core::mem::replace(slot, CertInstance::none());
        if let Some(store) = self.0.store.as_deref_mut() {
            if super::save(&self.0.state.security, store).is_err() {
                if let Some(slot) = self.0.state.security.certs.get_mut(index) {
                    *slot = before;
                }
                return Err(General::StoreOperationFailure.into());
            }
        }
        Ok(())
    }

    /// Verify_Certificate: a UINT, 1 the device certificate, 2 the CA certificate; success if
    /// the runtime verified it, 0x0C if not.
    fn verify(&self, instance: u32, data: &[u8]) -> CipResult {
        let which = match *data {
            [lo, hi] => u16::from_le_bytes([lo, hi]),
            [] | [_] => return Err(General::NotEnoughData.into()),
            _ => return Err(General::TooMuchData.into()),
        };
        let cert = self
            .st()
            .cert(instance)
            .ok_or(CipError::new(General::ObjectDoesNotExist))?;
        let status = match which {
            1 => cert.device,
            2 => cert.ca,
            _ => return Err(General::InvalidParameter.into()),
        };
        match status {
            CertStatus::Verified => Ok(()),
            _ => Err(General::ObjectStateConflict.into()),
        }
    }
}

/// Saves the instances after a Create; on failure removes instance `instance` again.
fn save_or_undo<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    instance: u16,
) -> Result<(), ()> {
    let Some(store) = ctx.store.as_deref_mut() else {
        return Ok(());
    };
    if super::save(&ctx.state.security, store).is_ok() {
        return Ok(());
    }
    let index = usize::from(instance).saturating_sub(1);
    if let Some(slot) = ctx.state.security.certs.get_mut(index) {
        *slot = CertInstance::none();
    }
    Err(())
}

impl<D: Device, const C: usize> Object for CertMgmt<'_, '_, D, C> {
    fn class(&self) -> &ClassDef {
        &CLASS
    }
    fn has_instance(&self, instance: u32) -> bool {
        self.st().cert(instance).is_some()
    }
    fn instance_count(&self) -> u32 {
        self.st().certs.iter().filter(|c| c.exists).count() as u32
    }
    fn get(&mut self, instance: u32, attr: &AttributeDef, w: &mut Writer<'_>) -> CipResult {
        let cert = self
            .st()
            .cert(instance)
            .ok_or(CipError::new(General::ObjectDoesNotExist))?;
        match attr.id {
            1 => short_string(w, &cert.name)?,
            2 => w.u8(cert.state())?,
            // Status, then a padded EPATH with its size to the File instance holding the
            // certificate the runtime uses (empty if it has none).
            3 | 4 => {
                let ca = attr.id == 4;
                let status = if ca { cert.ca } else { cert.device };
                w.u8(status as u8)?;
                match super::csr::certificate_file(self.0.csr.as_deref(), instance, ca) {
                    Some(file) => emit_path(w, super::FILE_CLASS as u8, file)?,
                    None => w.u8(0)?,
                }
            }
            _ => w.u8(cert.encoding)?,
        }
        Ok(())
    }
    fn service(
        &mut self,
        instance: u32,
        req: &Request<'_>,
        w: &mut Writer<'_>,
    ) -> Option<CipResult> {
        match (instance, req.service) {
            (0, service::GET_ATTRIBUTE_SINGLE) => self.class_attribute(req.path.attribute, w),
            (0, CREATE) => Some(self.create(req.data, w)),
            (0, _) => None,
            (_, DELETE) => Some(self.delete(instance, req.data)),
            (_, super::csr::CREATE_CSR) => {
                Some(super::csr::create_csr(self.0, instance, req.data, w))
            }
            (_, VERIFY_CERTIFICATE) => Some(self.verify(instance, req.data)),
            _ => None,
        }
    }
}

/// Handles a request to the Certificate Management class or one of its instances.
pub(crate) fn handle<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    serve(&mut CertMgmt(ctx), req, w)
}
