//! The TCP/IP object's IANA port administration while the security objects are on:
//! attribute 14 (IANA Port Admin) and the service Set_Port_Admin_State (0x4C), with which a
//! configured device closes (or opens again) TCP 44818 to explicit messaging, leaving TLS
//! on 2221.
//!
//! Attribute 14 lists each port's name, number, protocol (6 TCP, 17 UDP), admin state (1
//! open) and admin capability (bit 0 configurable): only 44818/tcp is configurable, and a
//! change applies to new connections at once (bit 1, reset required, clear). The layout is
//! Wireshark's; the port names are ours.
//!
//! Set_Port_Admin_State takes a USINT count, then per port a UINT number, a USINT protocol
//! and a USINT admin state. Our rules, where no public source says: it must come over TLS
//! (0x0F otherwise) to a device whose EtherNet/IP Security object is configured (0x0C
//! otherwise: with 44818 closed and TLS not set up, nothing could reach the device); a port
//! that is not configurable or not listed, or a state other than 0 and 1, is 0x09; the
//! setting is saved (0x19 if the store fails, nothing changed).

use super::super::Ctx;
use super::ObjectMode;
use crate::cip::encoding::short_string;
use crate::cip::status::{CipError, CipResult, General};
use crate::cip::{service, Request};
use crate::device::Device;
use crate::wire::{Reader, Writer};

/// The TCP/IP object's Set_Port_Admin_State service.
const SET_PORT_ADMIN_STATE: u8 = 0x4C;
/// The configurable port: 44818/tcp.
const PLAIN_TCP: (u16, u8) = (44818, 6);

/// Answers Get_Attribute_Single of TCP/IP instance 1 attribute 14 and Set_Port_Admin_State
/// while the security objects are on; `None` for every other request.
pub(crate) fn port_admin<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> Option<CipResult> {
    if !ctx.state.security.enabled || req.path.instance_or_point() != Some(1) {
        return None;
    }
    match req.service {
        service::GET_ATTRIBUTE_SINGLE if req.path.attribute == Some(14) => {
            Some(attribute(ctx, w).map_err(CipError::from))
        }
        SET_PORT_ADMIN_STATE if req.path.attribute.is_none() => Some(set(ctx, req.data)),
        _ => None,
    }
}

/// Attribute 14's value.
fn attribute<D: Device, const C: usize>(
    ctx: &Ctx<'_, D, C>,
    w: &mut Writer<'_>,
) -> crate::wire::Result<()> {
    let st = &ctx.state.security;
    let ports: [(&[u8], u16, u8, bool, u8); 4] = [
        (b"EtherNet/IP", 44818, 6, !st.plain_tcp_closed, 1),
        (b"EtherNet/IP", 44818, 17, true, 0),
        (b"EtherNet/IP I/O", 2222, 17, true, 0),
        (
            b"EtherNet/IP TLS",
            crate::config::TLS_PORT,
            6,
            st.tls_port_open,
            0,
        ),
    ];
    w.u8(ports.len() as u8)?;
    for (name, number, protocol, open, capability) in ports {
        short_string(w, name)?;
        w.u16(number)?;
        w.u8(protocol)?;
        w.u8(u8::from(open))?;
        w.u8(capability)?;
    }
    Ok(())
}

/// Set_Port_Admin_State.
fn set<D: Device, const C: usize>(ctx: &mut Ctx<'_, D, C>, data: &[u8]) -> CipResult {
    let mut r = Reader::new(data);
    let count = r.u8()?;
    let mut closed = ctx.state.security.plain_tcp_closed;
    for _ in 0..count {
        let (number, protocol, state) = (r.u16()?, r.u8()?, r.u8()?);
        if (number, protocol) != PLAIN_TCP || state > 1 {
            return Err(General::InvalidAttributeValue.into());
        }
        closed = state == 0;
    }
    if r.remaining() != 0 {
        return Err(General::TooMuchData.into());
    }
    let st = &ctx.state.security;
    if !st.is_secure(ctx.origin.as_ref()) {
        return Err(General::PrivilegeViolation.into());
    }
    if st.eip_mode != ObjectMode::Configured {
        return Err(General::ObjectStateConflict.into());
    }
    let before = st.plain_tcp_closed;
    ctx.state.security.plain_tcp_closed = closed;
    if let Some(store) = ctx.store.as_deref_mut() {
        if super::save(&ctx.state.security, store).is_err() {
            ctx.state.security.plain_tcp_closed = before;
            return Err(General::StoreOperationFailure.into());
        }
    }
    let st = &mut ctx.state.security;
    st.generation = st.generation.wrapping_add(1);
    Ok(())
}
