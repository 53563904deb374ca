//! Connection Manager object (class 0x06): Unconnected_Send addressed to this device;
//! Forward_Open and Forward_Close come with the connection table.

use super::router::{instance, no_instance, MAX_DEPTH};
use super::status::{CipError, CipResult, General};
use super::{service, Ctx, Request};
use crate::device::Device;
use crate::wire::epath::{Segment, Segments};
use crate::wire::{Reader, Writer};

/// Extended status: the route path names a port this device does not have.
const EXT_PORT_NOT_AVAILABLE: u16 = 0x0311;
/// Extended status: the route path's link address is not this device.
const EXT_LINK_ADDRESS_NOT_VALID: u16 = 0x0312;
/// Extended status: invalid segment in the route path.
const EXT_INVALID_SEGMENT: u16 = 0x0315;

/// Handles a request to the Connection Manager (Unconnected_Send is unwrapped by the router).
pub(crate) fn handle<D: Device>(
    _ctx: &mut Ctx<'_, D>,
    req: &Request<'_>,
    _w: &mut Writer<'_>,
    _depth: u8,
) -> CipResult {
    if instance(req)? != 1 {
        return Err(no_instance());
    }
    Err(General::ServiceNotSupported.into())
}

/// True if `req` is an Unconnected_Send to the Connection Manager.
pub(crate) fn is_unconnected_send(req: &Request<'_>) -> bool {
    req.service == service::UNCONNECTED_SEND
        && req.path.class == Some(u32::from(super::class_id::CONNECTION_MANAGER))
}

/// The embedded request of an Unconnected_Send whose route path ends here (port 1, link 0:
/// the backplane slot of a single-module device); its reply is sent as the whole reply.
pub(crate) fn embedded_request<'a>(req: &Request<'a>, depth: u8) -> CipResult<&'a [u8]> {
    if depth >= MAX_DEPTH {
        return Err(General::ServiceNotSupported.into());
    }
    if req.path.instance_or_point() != Some(1) {
        return Err(no_instance());
    }
    let mut r = Reader::new(req.data);
    r.u8()?; // priority / time tick
    r.u8()?; // timeout ticks
    let len = usize::from(r.u16()?);
    let embedded = r.take(len)?;
    if len % 2 == 1 {
        r.u8()?;
    }
    let words = usize::from(r.u8()?);
    r.u8()?;
    let route = r.take(words * 2)?;
    if r.remaining() != 0 {
        return Err(General::TooMuchData.into());
    }
    check_route(route)?;
    Ok(embedded)
}

/// Accepts a route path of exactly one port segment to port 1, link address 0.
fn check_route(route: &[u8]) -> CipResult {
    let mut segs = Segments::new(route);
    let first = segs.next();
    match (first, segs.next()) {
        (Some(Ok(Segment::Port { port: 1, link: [0] })), None) => Ok(()),
        (Some(Ok(Segment::Port { port: 1, .. })), None) => {
            Err(CipError::connection(EXT_LINK_ADDRESS_NOT_VALID))
        }
        (Some(Ok(Segment::Port { .. })), None) => Err(CipError::connection(EXT_PORT_NOT_AVAILABLE)),
        _ => Err(CipError::connection(EXT_INVALID_SEGMENT)),
    }
}
