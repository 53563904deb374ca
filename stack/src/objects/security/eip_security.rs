//! EtherNet/IP Security object (class 0x5E): the TLS settings (allowed cipher suites, the
//! device certificate and trusted CA as paths to Certificate Management instances, the
//! client-verification flags) and their configuration session (Begin_Config, Kick_Timer,
//! Apply_Config, Abort_Config).
//!
//! The settable attributes take a value only inside a configuration session, from the
//! client that began it (0x0C otherwise; 0x0F over plaintext in a session its address began
//! over TLS); the value goes into the pending settings, which
//! Gets show while the session runs. Apply_Config checks them (0x0C with extended status
//! 0x0002 without a device certificate, 0x0004 without an allowed suite; 0x0C if client
//! verification is on with no trusted CA), saves them (0x19 if the store fails, changing
//! nothing) and puts them in use for the next TLS session; Abort_Config or a lapsed session
//! drops them. Pre-shared keys (attribute 5): at most one, stored with the settings; a Get
//! shows its identity and usage with a key size of 0, never the key. Reset (0x05) returns the factory default
//! settings; Reset and Begin_Config of a configured object come over TLS or are refused
//! (0x0F), as the open reference stack's development branch checks for Reset.

use super::super::serve::{serve, Object};
use super::super::Ctx;
use super::cert_mgmt::{emit_path, read_path};
use super::{begin, owned, requester, ObjectMode, Psk, TlsSettings, AVAILABLE_SUITES};
use super::{CERT_MGMT_CLASS, EIP_SECURITY_CLASS};
use crate::cip::object::{AttributeDef, ClassDef, DataType};
use crate::cip::status::{CipError, CipResult, General};
use crate::cip::{service, Request};
use crate::device::Device;
use crate::wire::{Reader, Writer};

/// Service codes of the class.
const BEGIN_CONFIG: u8 = 0x4B;
const KICK_TIMER: u8 = 0x4C;
const APPLY_CONFIG: u8 = 0x4D;
const ABORT_CONFIG: u8 = 0x4E;
/// Apply_Config extended status: certificate suites allowed, no device certificate.
pub const NO_CERTIFICATE: u16 = 0x0002;
/// Apply_Config extended status: no cipher suite allowed.
pub const NO_SUITE: u16 = 0x0004;

/// The EtherNet/IP Security class: one instance, attributes 1-11 (Get_Attributes_All in
/// that order).
pub const CLASS: ClassDef = ClassDef {
    id: EIP_SECURITY_CLASS,
    name: "EtherNet/IP Security",
    revision: 1,
    max_instance: 1,
    attributes: &[
        AttributeDef::get(1, DataType::Usint, "State"),
        AttributeDef::get(2, DataType::Dword, "Capability Flags"),
        AttributeDef::get(3, DataType::Unsized, "Available Cipher Suites"),
        AttributeDef::get_set(4, DataType::Unsized, "Allowed Cipher Suites"),
        AttributeDef::get_set(5, DataType::Unsized, "Pre-Shared Keys"),
        AttributeDef::get_set(6, DataType::Unsized, "Active Device Certificates"),
        AttributeDef::get_set(7, DataType::Unsized, "Trusted Authorities"),
        AttributeDef::get(8, DataType::Unsized, "Certificate Revocation List"),
        AttributeDef::get_set(9, DataType::Bool, "Verify Client Certificate"),
        AttributeDef::get_set(10, DataType::Bool, "Send Certificate Chain"),
        AttributeDef::get_set(11, DataType::Bool, "Check Expiration"),
    ],
    get_all: &[1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11],
    optional_attributes: &[],
};

struct EipSecurity<'c, 'a, D: Device, const C: usize>(&'c mut Ctx<'a, D, C>);

/// A USINT count, then that many suites (big-endian, as IANA writes them).
fn emit_suites(w: &mut Writer<'_>, suites: &[u16]) -> CipResult {
    w.u8(suites.len() as u8)?;
    for s in suites {
        w.bytes(&s.to_be_bytes())?;
    }
    Ok(())
}

/// A USINT count (0 or 1), then a path to the Certificate Management instance.
fn emit_instances(w: &mut Writer<'_>, instance: Option<u8>) -> CipResult {
    match instance {
        Some(i) => {
            w.u8(1)?;
            emit_path(w, CERT_MGMT_CLASS as u8, i)
        }
        None => Ok(w.u8(0)?),
    }
}

/// Attribute 5 as a Get shows it: the count, then the identity, a key size of 0 and no key
/// bytes (a key is never read out), and the usage.
fn emit_psk(w: &mut Writer<'_>, psk: Option<&Psk>) -> CipResult {
    let Some(k) = psk else {
        return Ok(w.u8(0)?);
    };
    w.u8(1)?;
    w.u8(k.identity.len() as u8)?;
    w.bytes(&k.identity)?;
    w.u8(0)?;
    w.u8(k.usage)?;
    Ok(())
}

/// Attribute 5 as a Set carries it: a count (0 or 1: at most one key), then the identity
/// size and identity, the key size and key, and the usage. 0x09 for more than one key, an
/// empty or too long identity or key.
fn read_psk(r: &mut Reader<'_>) -> CipResult<Option<Psk>> {
    let bad = || CipError::new(General::InvalidAttributeValue);
    match r.u8()? {
        0 => return Ok(None),
        1 => {}
        _ => return Err(bad()),
    }
    let n = usize::from(r.u8()?);
    let identity = r.take(n)?;
    let n = usize::from(r.u8()?);
    let key = r.take(n)?;
    let usage = r.u8()?;
    if identity.is_empty() || key.is_empty() {
        return Err(bad());
    }
    Ok(Some(Psk {
        identity: heapless::Vec::from_slice(identity).map_err(|_| bad())?,
        key: heapless::Vec::from_slice(key).map_err(|_| bad())?,
        usage,
    }))
}

/// A Set value that must be read whole: 0x13 if short, 0x15 if bytes remain.
fn whole<T>(value: &[u8], f: impl FnOnce(&mut Reader<'_>) -> CipResult<T>) -> CipResult<T> {
    let mut r = Reader::new(value);
    let v = f(&mut r)?;
    if r.remaining() != 0 {
        return Err(General::TooMuchData.into());
    }
    Ok(v)
}

impl<D: Device, const C: usize> EipSecurity<'_, '_, D, C> {
    /// The settings Gets show: the pending ones while a session runs.
    fn shown(&self) -> &TlsSettings {
        let st = &self.0.state.security;
        match st.eip_mode {
            ObjectMode::InProgress => &st.pending,
            _ => &st.active,
        }
    }

    fn run(&mut self, service: u8, data: &[u8]) -> CipResult {
        let now = self.0.now();
        let owner = requester(self.0);
        if service == service::RESET {
            return self.reset(data, owner.secure);
        }
        let st = &mut self.0.state.security;
        if service == APPLY_CONFIG {
            return self.apply(data);
        }
        if !data.is_empty() {
            return Err(General::TooMuchData.into());
        }
        match service {
            BEGIN_CONFIG => {
                begin(&mut st.eip_mode, &mut st.eip_session, owner, now)?;
                st.pending = st.active.clone();
            }
            KICK_TIMER => {
                owned(&mut st.eip_session, owner)?.until = now.add(super::CONFIG_SESSION);
            }
            _ => {
                let before = owned(&mut st.eip_session, owner)?.before;
                st.eip_session = None;
                st.eip_mode = before;
                st.pending = st.active.clone();
            }
        }
        Ok(())
    }

    /// Reset: the factory default settings, saved; a configured object only over TLS (0x0F),
    /// none while a configuration session runs (0x0C).
    fn reset(&mut self, data: &[u8], secure: bool) -> CipResult {
        if !data.is_empty() {
            return Err(General::TooMuchData.into());
        }
        let st = &mut self.0.state.security;
        match st.eip_mode {
            ObjectMode::InProgress => return Err(General::ObjectStateConflict.into()),
            ObjectMode::Configured if !secure => return Err(General::PrivilegeViolation.into()),
            _ => {}
        }
        let before = (st.active.clone(), st.eip_mode);
        st.active = TlsSettings::factory();
        st.pending = TlsSettings::factory();
        st.eip_mode = ObjectMode::FactoryDefault;
        if let Some(store) = self.0.store.as_deref_mut() {
            if super::save(&self.0.state.security, store).is_err() {
                let st = &mut self.0.state.security;
                (st.active, st.eip_mode) = before;
                st.pending = st.active.clone();
                return Err(General::StoreOperationFailure.into());
            }
        }
        let st = &mut self.0.state.security;
        st.generation = st.generation.wrapping_add(1);
        Ok(())
    }

    /// Apply_Config: optional apply behaviour flags (WORD) and close delay (UINT), which
    /// this device need not act on (new settings apply to new TLS sessions).
    fn apply(&mut self, data: &[u8]) -> CipResult {
        match data.len() {
            0 | 4 => {}
            1..=3 => return Err(General::NotEnoughData.into()),
            _ => return Err(General::TooMuchData.into()),
        }
        let owner = requester(self.0);
        let st = &mut self.0.state.security;
        owned(&mut st.eip_session, owner)?;
        let p = &st.pending;
        let conflict = CipError::new(General::ObjectStateConflict);
        if p.allowed.is_empty() {
            return Err(conflict.with_extended(NO_SUITE));
        }
        if p.active_cert.is_none() {
            return Err(conflict.with_extended(NO_CERTIFICATE));
        }
        if p.verify_client && p.trusted_ca.is_none() {
            return Err(conflict);
        }
        let before = (st.active.clone(), st.eip_mode);
        st.active = st.pending.clone();
        st.eip_mode = ObjectMode::Configured;
        if let Some(store) = self.0.store.as_deref_mut() {
            if super::save(&self.0.state.security, store).is_err() {
                let st = &mut self.0.state.security;
                (st.active, st.eip_mode) = before;
                return Err(General::StoreOperationFailure.into());
            }
        }
        let st = &mut self.0.state.security;
        st.eip_session = None;
        st.generation = st.generation.wrapping_add(1);
        Ok(())
    }
}

impl<D: Device, const C: usize> Object for EipSecurity<'_, '_, D, C> {
    fn class(&self) -> &ClassDef {
        &CLASS
    }
    fn get(&mut self, _instance: u32, attr: &AttributeDef, w: &mut Writer<'_>) -> CipResult {
        let s = self.shown();
        match attr.id {
            1 => w.u8(self.0.state.security.eip_mode as u8)?,
            2 => w.u32(0)?,
            3 => emit_suites(w, &AVAILABLE_SUITES)?,
            4 => emit_suites(w, &s.allowed)?,
            5 => emit_psk(w, s.psk.as_ref())?,
            6 => emit_instances(w, s.active_cert)?,
            7 => emit_instances(w, s.trusted_ca)?,
            // No revocation list.
            8 => w.u8(0)?,
            9 => w.u8(u8::from(s.verify_client))?,
            10 => w.u8(u8::from(s.send_chain))?,
            _ => w.u8(u8::from(s.check_expiration))?,
        }
        Ok(())
    }
    fn set(&mut self, _instance: u32, attr: &AttributeDef, value: &[u8]) -> CipResult {
        let owner = requester(self.0);
        let st = &mut self.0.state.security;
        if st.eip_mode != ObjectMode::InProgress {
            return Err(General::ObjectStateConflict.into());
        }
        owned(&mut st.eip_session, owner)?;
        let snapshot = st.clone();
        let p = &mut st.pending;
        let bool_value = || match value.first() {
            Some(0) => Ok(false),
            Some(1) => Ok(true),
            _ => Err(CipError::new(General::InvalidAttributeValue)),
        };
        match attr.id {
            4 => {
                p.allowed = whole(value, |r| {
                    let n = usize::from(r.u8()?);
                    let mut allowed = heapless::Vec::new();
                    for _ in 0..n {
                        let s = u16::from_be_bytes(r.array::<2>()?);
                        if !AVAILABLE_SUITES.contains(&s) || allowed.contains(&s) {
                            return Err(General::InvalidAttributeValue.into());
                        }
                        allowed
                            .push(s)
                            .map_err(|_| CipError::new(General::InvalidAttributeValue))?;
                    }
                    Ok(allowed)
                })?
            }
            5 => p.psk = whole(value, read_psk)?,
            6 | 7 => {
                let chosen = whole(value, |r| match r.u8()? {
                    0 => Ok(None),
                    1 => read_path(r, &snapshot).map(Some),
                    _ => Err(General::InvalidAttributeValue.into()),
                })?;
                if attr.id == 6 {
                    p.active_cert = chosen;
                } else {
                    p.trusted_ca = chosen;
                }
            }
            9 => p.verify_client = bool_value()?,
            10 => p.send_chain = bool_value()?,
            _ => p.check_expiration = bool_value()?,
        }
        Ok(())
    }
    fn service(
        &mut self,
        instance: u32,
        req: &Request<'_>,
        _w: &mut Writer<'_>,
    ) -> Option<CipResult> {
        let ours = matches!(
            req.service,
            BEGIN_CONFIG | KICK_TIMER | APPLY_CONFIG | ABORT_CONFIG | service::RESET
        );
        (instance == 1 && ours).then(|| self.run(req.service, req.data))
    }
}

/// Handles a request to the EtherNet/IP Security class or its instance 1.
pub(crate) fn handle<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    serve(&mut EipSecurity(ctx), req, w)
}
