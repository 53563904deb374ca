//! Connection Manager object (class 0x06): Forward_Open, Large_Forward_Open, Forward_Close,
//! and Unconnected_Send addressed to this device.

use super::router::{instance, no_instance, MAX_DEPTH};
use super::status::{CipError, CipResult, General};
use super::{service, Ctx, Request};
use crate::config::IO_PORT;
use crate::device::{CloseReason, Device};
use crate::io::open::{self, NetFacts};
use crate::io::status as ext;
use crate::wire::cpf::SockAddr;
use crate::wire::epath::{Segment, Segments};
use crate::wire::forward_open::{
    self, ConnectionType, ForwardClose, ForwardOpen, ForwardOpenReply,
};
use crate::wire::{Error, Reader, Writer};

/// Extended status: the route path names a port this device does not have.
const EXT_PORT_NOT_AVAILABLE: u16 = 0x0311;
/// Extended status: the route path's link address is not this device.
const EXT_LINK_ADDRESS_NOT_VALID: u16 = 0x0312;

/// Handles a request to the Connection Manager (Unconnected_Send is unwrapped by the router).
pub(crate) fn handle<D: Device>(
    ctx: &mut Ctx<'_, D>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    if instance(req)? != 1 {
        return Err(no_instance());
    }
    match req.service {
        service::FORWARD_OPEN | service::LARGE_FORWARD_OPEN => forward_open(ctx, req, w),
        service::FORWARD_CLOSE => forward_close(ctx, req.data, w),
        _ => Err(General::ServiceNotSupported.into()),
    }
}

/// Malformed request data: short is "not enough data", a path that does not fill it "too much".
fn data_error(e: Error) -> CipError {
    match e {
        Error::Truncated => General::NotEnoughData.into(),
        _ => General::TooMuchData.into(),
    }
}

fn forward_open<D: Device>(
    ctx: &mut Ctx<'_, D>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    let fo = ForwardOpen::parse(req.data, req.service == service::LARGE_FORWARD_OPEN)
        .map_err(data_error)?;
    let origin = ctx
        .origin
        .ok_or(CipError::new(General::ServiceNotSupported))?;
    let (multicast, ttl) = ctx.state.tcpip.multicast_in_use(&*ctx.device, ctx.net);
    let net = NetFacts {
        ip: ctx.net.ip,
        netmask: ctx.net.netmask,
        multicast,
        ttl,
    };
    let opened = open::forward_open(ctx.connections, ctx.device, &fo, &origin, &net, ctx.now);
    let slot = match opened {
        Ok(slot) => slot,
        Err(e) => {
            let remaining = if e.extended() == Some(ext::BAD_SEGMENT) {
                (fo.path.len() / 2) as u8
            } else {
                0
            };
            forward_open::emit_failure(w, &fo.triad, remaining)?;
            return Err(e.keeping_data());
        }
    };
    let conn = ctx
        .connections
        .get(slot)
        .ok_or(CipError::new(General::ResourceUnavailable))?;
    if fo.t_o_params.connection_type == ConnectionType::Multicast {
        ctx.reply_t_o_sockaddr = Some(SockAddr {
            addr: net.multicast,
            port: IO_PORT,
        });
    }
    ForwardOpenReply {
        o_t_connection_id: conn.o_t_id,
        t_o_connection_id: conn.t_o_id,
        triad: conn.triad,
        o_t_api: conn.o_t_rpi,
        t_o_api: conn.t_o_rpi,
        application_reply: &[],
    }
    .emit(w)?;
    Ok(())
}

fn forward_close<D: Device>(ctx: &mut Ctx<'_, D>, data: &[u8], w: &mut Writer<'_>) -> CipResult {
    let fc = ForwardClose::parse(data).map_err(data_error)?;
    let Some(slot) = ctx.connections.find_triad(&fc.triad) else {
        forward_open::emit_failure(w, &fc.triad, 0)?;
        return Err(CipError::connection(ext::NOT_FOUND).keeping_data());
    };
    ctx.connections
        .close(slot, CloseReason::ForwardClose, ctx.device);
    forward_open::emit_close_reply(w, &fc.triad)?;
    Ok(())
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
        _ => Err(CipError::connection(ext::BAD_SEGMENT)),
    }
}
