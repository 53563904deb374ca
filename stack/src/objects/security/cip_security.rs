//! CIP Security object (class 0x5D): the device's security state and profiles, and the
//! configuration session that brackets a commissioning tool's changes (Begin_Config,
//! Kick_Timer, End_Config, Object_Cleanup).
//!
//! Begin_Config opens a session (from factory default, configured or incomplete; 0x0C while
//! one runs; 0x0F for a configured device unless the request came over TLS) owned by the
//! requester's address, which lapses after [`super::CONFIG_SESSION`]
//! without a Kick_Timer; Kick_Timer and End_Config from anyone else, or with no session,
//! are 0x0C (0x0F from that address over plaintext if the session was begun over TLS). End_Config marks the device Configured with the Confidentiality profile if the
//! EtherNet/IP Security object is configured, Incomplete Configuration if not (0x0C while
//! that object's own configuration is in progress), and saves it. Object_Cleanup deletes the
//! Certificate Management instances the TLS settings do not name (nothing to delete is not
//! an error here: the object-specific status 0xD0 of the open reference stack is not sent).

use super::super::serve::{serve, Object};
use super::super::Ctx;
use super::{begin, owned, requester, ObjectMode, CIP_SECURITY_CLASS, PROFILE_CONFIDENTIALITY};
use crate::cip::object::{AttributeDef, ClassDef, DataType};
use crate::cip::status::{CipResult, General};
use crate::cip::Request;
use crate::device::Device;
use crate::wire::Writer;

/// Service codes of the class.
const BEGIN_CONFIG: u8 = 0x4B;
const KICK_TIMER: u8 = 0x4C;
const END_CONFIG: u8 = 0x4D;
const OBJECT_CLEANUP: u8 = 0x4E;

/// The CIP Security class: one instance. Get_Attributes_All returns attributes 1 and 2 (the
/// order Wireshark's dissector reads).
pub const CLASS: ClassDef = ClassDef {
    id: CIP_SECURITY_CLASS,
    name: "CIP Security",
    revision: 1,
    max_instance: 1,
    attributes: &[
        AttributeDef::get(1, DataType::Usint, "State"),
        AttributeDef::get(2, DataType::Word, "Security Profiles"),
        AttributeDef::get(3, DataType::Word, "Security Profiles Configured"),
    ],
    get_all: &[1, 2],
    optional_attributes: &[3],
};

struct CipSecurity<'c, 'a, D: Device, const C: usize>(&'c mut Ctx<'a, D, C>);

impl<D: Device, const C: usize> CipSecurity<'_, '_, D, C> {
    fn run(&mut self, service: u8, data: &[u8]) -> CipResult {
        if !data.is_empty() {
            return Err(General::TooMuchData.into());
        }
        let now = self.0.now();
        let owner = requester(self.0);
        let st = &mut self.0.state.security;
        match service {
            BEGIN_CONFIG => return begin(&mut st.cip_mode, &mut st.cip_session, owner, now),
            KICK_TIMER => {
                owned(&mut st.cip_session, owner)?.until = now.add(super::CONFIG_SESSION);
                return Ok(());
            }
            OBJECT_CLEANUP => return self.cleanup(),
            _ => {}
        }
        // End_Config.
        owned(&mut st.cip_session, owner)?;
        let (mode, profiles) = match st.eip_mode {
            ObjectMode::InProgress => return Err(General::ObjectStateConflict.into()),
            ObjectMode::Configured => (ObjectMode::Configured, PROFILE_CONFIDENTIALITY),
            _ => (ObjectMode::Incomplete, 0),
        };
        let before = (st.cip_mode, st.profiles_configured);
        (st.cip_mode, st.profiles_configured) = (mode, profiles);
        if let Some(store) = self.0.store.as_deref_mut() {
            if super::save(&self.0.state.security, store).is_err() {
                let st = &mut self.0.state.security;
                (st.cip_mode, st.profiles_configured) = before;
                return Err(General::StoreOperationFailure.into());
            }
        }
        self.0.state.security.cip_session = None;
        Ok(())
    }

    /// Deletes the created certificate instances no TLS setting names.
    fn cleanup(&mut self) -> CipResult {
        let st = &mut self.0.state.security;
        let named = [
            st.active.active_cert,
            st.active.trusted_ca,
            st.pending.active_cert,
            st.pending.trusted_ca,
        ];
        let before = st.certs.clone();
        for (c, i) in st.certs.iter_mut().zip(1u8..).skip(1) {
            if c.exists && !named.contains(&Some(i)) {
                *c = super::CertInstance::none();
            }
        }
        if st.certs == before {
            return Ok(());
        }
        if let Some(store) = self.0.store.as_deref_mut() {
            if super::save(&self.0.state.security, store).is_err() {
                self.0.state.security.certs = before;
                return Err(General::StoreOperationFailure.into());
            }
        }
        Ok(())
    }
}

impl<D: Device, const C: usize> Object for CipSecurity<'_, '_, D, C> {
    fn class(&self) -> &ClassDef {
        &CLASS
    }
    fn get(&mut self, _instance: u32, attr: &AttributeDef, w: &mut Writer<'_>) -> CipResult {
        let st = &self.0.state.security;
        match attr.id {
            1 => w.u8(st.cip_mode as u8)?,
            2 => w.u16(PROFILE_CONFIDENTIALITY)?,
            _ => w.u16(st.profiles_configured)?,
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
            BEGIN_CONFIG | KICK_TIMER | END_CONFIG | OBJECT_CLEANUP
        );
        (instance == 1 && ours).then(|| self.run(req.service, req.data))
    }
}

/// Handles a request to the CIP Security class or its instance 1.
pub(crate) fn handle<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    serve(&mut CipSecurity(ctx), req, w)
}
