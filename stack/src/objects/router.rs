//! The Message Router: frames a request, checks the electronic key its path may start with,
//! sends it to the object its path names, and writes the response with the right general and
//! additional status.

use super::lldp_management;
use super::{assembly, connection_manager, ethernet_link, identity};
use super::{message_router, qos, tcpip, vendor, Ctx};
use crate::cip::class_id;
use crate::cip::request::Request;
use crate::cip::status::CipResult;
use crate::device::electronic_key::{self, KeyMismatch};
use crate::device::Device;
use crate::wire::message_router::{ResponseRepr, REPLY_BIT};
use crate::wire::{self, Writer};

/// How deep requests may nest (Multiple_Service_Packet, Unconnected_Send).
pub(crate) const MAX_DEPTH: u8 = 2;

/// Executes the Message Router request `request` and writes its whole response into `w`.
/// Fails only if not even an error response fits.
pub(crate) fn respond<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    request: &[u8],
    w: &mut Writer<'_>,
    depth: u8,
) -> wire::Result<()> {
    let mut req = Request::default();
    match req.parse_from(request) {
        Ok(()) => respond_to(ctx, &req, w, depth),
        Err((service, e)) => finish(w, w.len(), service, Err(e)),
    }
}

/// Executes a framed request; an Unconnected_Send to this device is answered by its embedded
/// request's response (framed once, here). A request whose path starts with an electronic
/// key the device does not match is not executed: key failure in path (0x25) with the part
/// that failed, as [`electronic_key`] says.
fn respond_to<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
    depth: u8,
) -> wire::Result<()> {
    let start = w.len();
    if let Some(key) = &req.path.key {
        if let Err(part) = electronic_key::check(key, ctx.device.identity()) {
            return finish(w, start, req.service, Err(KeyMismatch::path_failure(part)));
        }
    }
    if connection_manager::is_unconnected_send(req) {
        // An embedded request that cannot even be framed is the Unconnected_Send's error.
        let inner = connection_manager::embedded_request(req, depth, w)
            .and_then(|bytes| Request::parse(bytes).map_err(|(_, e)| e));
        return match inner {
            Ok(inner) => respond_to(ctx, &inner, w, depth.saturating_add(1)),
            Err(e) => finish(w, start, req.service, Err(e)),
        };
    }
    w.zeros(4)?;
    let result = dispatch(ctx, req, w, depth);
    finish(w, start, req.service, result)
}

/// Completes the response that starts at `start`: patches the header reserved there, or
/// replaces what was written with an error header (keeping the data where the error says so).
fn finish(w: &mut Writer<'_>, start: usize, service: u8, result: CipResult) -> wire::Result<()> {
    let general = match result {
        Ok(()) => 0u8,
        Err(e) if e.keeps_data() && w.len() > start => {
            let (words, n) = additional_bytes(e.additional());
            let words = words.get(..n).unwrap_or(&[]);
            w.insert(start.saturating_add(4), words)?;
            w.patch_u16(
                start.saturating_add(2),
                u16::from(e.general) | (((n / 2) as u16) << 8),
            );
            w.patch_u16(start, u16::from(service | REPLY_BIT));
            return Ok(());
        }
        Err(e) => {
            debug!("service {:#04x}: {}", u32::from(service), e);
            w.truncate(start);
            let (words, n) = additional_bytes(e.additional());
            return ResponseRepr {
                service: service | REPLY_BIT,
                general_status: e.general.into(),
                additional_status: words.get(..n).unwrap_or(&[]),
                data: &[],
            }
            .emit(w);
        }
    };
    w.patch_u16(start, u16::from(service | REPLY_BIT));
    w.patch_u16(start.saturating_add(2), u16::from(general));
    Ok(())
}

/// The additional status words as little-endian bytes, and how many bytes that is.
fn additional_bytes(words: &[u16]) -> ([u8; 2 * crate::cip::status::MAX_ADDITIONAL], usize) {
    let mut bytes = [0u8; 2 * crate::cip::status::MAX_ADDITIONAL];
    for (dst, src) in bytes.chunks_exact_mut(2).zip(words) {
        dst.copy_from_slice(&src.to_le_bytes());
    }
    let n = words.len().min(crate::cip::status::MAX_ADDITIONAL);
    (bytes, n.saturating_mul(2))
}

/// Sends a decoded request to its object: a built-in one, a class the device declares, or
/// else whatever the device makes of it (0x05 if nothing).
pub(crate) fn dispatch<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
    depth: u8,
) -> CipResult {
    // Configuration sessions that lapsed end first, whichever object the request is for
    // (the TCP/IP object's Set_Port_Admin_State asks the EtherNet/IP Security state too).
    #[cfg(feature = "cip-security")]
    {
        let now = ctx.now();
        ctx.state.security.expire(now);
    }
    let class = req.path.class.and_then(|c| u16::try_from(c).ok());
    match class {
        Some(class_id::IDENTITY) => identity::handle(ctx, req, w),
        Some(class_id::MESSAGE_ROUTER) => message_router::handle(ctx, req, w, depth),
        Some(class_id::ASSEMBLY) => assembly::handle(ctx, req, w),
        Some(class_id::CONNECTION_MANAGER) => connection_manager::handle(ctx, req, w),
        Some(class_id::TCP_IP_INTERFACE) => tcpip::handle(ctx, req, w),
        Some(class_id::ETHERNET_LINK) => ethernet_link::handle(ctx, req, w),
        Some(class_id::LLDP_MANAGEMENT | class_id::LLDP_DATA_TABLE) => {
            lldp_management::handle(ctx, req, w)
        }
        Some(class_id::QOS) => qos::handle(ctx, req, w),
        #[cfg(feature = "cip-security")]
        Some(c @ 0x5D..=0x5F) if ctx.state.security.enabled => security_handle(ctx, c, req, w),
        #[cfg(feature = "cip-security")]
        Some(super::security::FILE_CLASS) if ctx.state.security.enabled && ctx.csr.is_some() => {
            super::security::csr::handle(ctx, req, w)
        }
        _ => vendor::handle(ctx, class, req, w),
    }
}

/// A request to one of the CIP Security classes.
#[cfg(feature = "cip-security")]
fn security_handle<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    class: u16,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    use super::security::{cert_mgmt, cip_security, eip_security};
    match class {
        super::security::CIP_SECURITY_CLASS => cip_security::handle(ctx, req, w),
        super::security::EIP_SECURITY_CLASS => eip_security::handle(ctx, req, w),
        _ => cert_mgmt::handle(ctx, req, w),
    }
}
