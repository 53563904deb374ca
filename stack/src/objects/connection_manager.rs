//! Connection Manager object (class 0x06): Forward_Open, Large_Forward_Open, Forward_Close,
//! and Unconnected_Send addressed to this device.

use super::router::MAX_DEPTH;
use super::serve::{serve, Object};
use super::Ctx;
use crate::cip::connection_status as ext;
use crate::cip::object::{AttributeDef, ClassDef, DataType};
use crate::cip::status::{CipError, CipResult, General};
use crate::cip::{class_id, service, Request};
use crate::config::IO_PORT;
use crate::device::{CloseReason, Device};
use crate::io::open::{self, NetFacts};
use crate::wire::cpf::SockAddrRepr;
use crate::wire::epath::{SegmentRepr, Segments};
use crate::wire::forward_open::{
    ConnectionType, FailureReplyRepr, ForwardCloseReplyRepr, ForwardCloseRepr,
    ForwardOpenReplyRepr, ForwardOpenRepr, Triad,
};
use crate::wire::{Error, Reader, Writer};

/// Extended status: the route path names a port this device does not have.
const EXT_PORT_NOT_AVAILABLE: u16 = 0x0311;
/// Extended status: the route path's link address is not this device.
const EXT_LINK_ADDRESS_NOT_VALID: u16 = 0x0312;
/// Where a Forward_Open's triad starts: after the ticks and both connection IDs.
const FORWARD_OPEN_TRIAD_AT: usize = 10;
/// Where a Forward_Close's triad starts: after the ticks.
const FORWARD_CLOSE_TRIAD_AT: usize = 2;

/// Connection Manager instance attributes 1-7: request and reject counters (wrapping).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counters {
    /// Attribute 1: Forward_Open requests.
    pub open_requests: u16,
    /// Attribute 2: Forward_Opens rejected for their format.
    pub open_format_rejects: u16,
    /// Attribute 3: Forward_Opens rejected for lack of resources.
    pub open_resource_rejects: u16,
    /// Attribute 4: Forward_Opens rejected for any other reason.
    pub open_other_rejects: u16,
    /// Attribute 5: Forward_Close requests.
    pub close_requests: u16,
    /// Attribute 6: Forward_Closes rejected for their format.
    pub close_format_rejects: u16,
    /// Attribute 7: Forward_Closes rejected for any other reason.
    pub close_other_rejects: u16,
}

fn bump(counter: &mut u16) {
    *counter = counter.wrapping_add(1);
}

/// The Connection Manager class: request and reject counters (attributes 1-8), and the
/// Forward_Open, Large_Forward_Open and Forward_Close services.
pub const CLASS: ClassDef = ClassDef {
    id: class_id::CONNECTION_MANAGER,
    name: "Connection Manager",
    revision: 1,
    max_instance: 1,
    attributes: &[
        AttributeDef::get(1, DataType::Uint, "Open Requests"),
        AttributeDef::get(2, DataType::Uint, "Open Format Rejects"),
        AttributeDef::get(3, DataType::Uint, "Open Resource Rejects"),
        AttributeDef::get(4, DataType::Uint, "Open Other Rejects"),
        AttributeDef::get(5, DataType::Uint, "Close Requests"),
        AttributeDef::get(6, DataType::Uint, "Close Format Requests"),
        AttributeDef::get(7, DataType::Uint, "Close Other Requests"),
        AttributeDef::get(8, DataType::Uint, "Connection Timeouts"),
    ],
    get_all: &[1, 2, 3, 4, 5, 6, 7, 8],
    optional_attributes: &[1, 2, 3, 4, 5, 6, 7, 8],
};

struct Manager<'c, 'a, D: Device, const C: usize>(&'c mut Ctx<'a, D, C>);

impl<D: Device, const C: usize> Object for Manager<'_, '_, D, C> {
    fn class(&self) -> &ClassDef {
        &CLASS
    }
    fn extra_optional_services(&self) -> &'static [u8] {
        &[service::UNCONNECTED_SEND, service::LARGE_FORWARD_OPEN]
    }

    fn get(&mut self, _instance: u32, attr: &AttributeDef, w: &mut Writer<'_>) -> CipResult {
        let c = self.0.state.connection_manager;
        let value = match attr.id {
            1 => c.open_requests,
            2 => c.open_format_rejects,
            3 => c.open_resource_rejects,
            4 => c.open_other_rejects,
            5 => c.close_requests,
            6 => c.close_format_rejects,
            7 => c.close_other_rejects,
            _ => self.0.connections.timeouts(),
        };
        w.u16(value)?;
        Ok(())
    }
    fn service(
        &mut self,
        instance: u32,
        req: &Request<'_>,
        w: &mut Writer<'_>,
    ) -> Option<CipResult> {
        let ctx = &mut *self.0;
        match (instance, req.service) {
            (1, service::FORWARD_OPEN | service::LARGE_FORWARD_OPEN) => {
                bump(&mut ctx.state.connection_manager.open_requests);
                Some(forward_open(ctx, req, w))
            }
            (1, service::FORWARD_CLOSE) => {
                bump(&mut ctx.state.connection_manager.close_requests);
                Some(forward_close(ctx, req.data, w))
            }
            _ => None,
        }
    }
}

/// Handles a request to the Connection Manager (Unconnected_Send is unwrapped by the router).
pub(crate) fn handle<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    serve(&mut Manager(ctx), req, w)
}

/// Malformed request data: short is "not enough data", a path that does not fill it "too much".
fn data_error(e: Error) -> CipError {
    match e {
        Error::Truncated => General::NotEnoughData.into(),
        _ => General::TooMuchData.into(),
    }
}

/// A Forward_Open or Forward_Close whose data did not parse ([`data_error`]), answered with
/// the failure reply's body (Vol 1 3-5.5.2) if the data reached as far as the triad `triad`.
fn malformed(e: Error, triad: Option<Triad>, w: &mut Writer<'_>) -> CipResult {
    let Some(triad) = triad else {
        return Err(data_error(e));
    };
    FailureReplyRepr {
        triad,
        remaining_path_words: 0,
    }
    .emit(w)?;
    Err(data_error(e).keeping_data())
}

fn forward_open<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    let fo = match ForwardOpenRepr::parse(req.data, req.service == service::LARGE_FORWARD_OPEN) {
        Ok(fo) => fo,
        Err(e) => {
            bump(&mut ctx.state.connection_manager.open_format_rejects);
            return malformed(e, Triad::at(req.data, FORWARD_OPEN_TRIAD_AT), w);
        }
    };
    let origin = ctx
        .origin
        .ok_or(CipError::new(General::ServiceNotSupported))?;
    let (multicast, ttl) = ctx.state.tcpip.multicast_in_use(&*ctx.device, ctx.net);
    let net = NetFacts {
        ip: ctx.net.ip,
        netmask: ctx.net.netmask,
        multicast,
        ttl,
        t_o_dscp: ctx.state.qos.active.for_priority(fo.t_o_params.priority),
    };
    let opened = open::forward_open(ctx.connections, ctx.device, &fo, &origin, &net, ctx.now());
    let slot = match opened {
        Ok(slot) => slot,
        Err(e) => {
            // Every status word, the additional ones (e.g. a device's offending byte) too.
            info!(
                "Forward_Open from {} refused: {} ({})",
                origin.ip,
                ext::describe(e.extended().unwrap_or(0)),
                e
            );
            let c = &mut ctx.state.connection_manager;
            bump(match e.extended() {
                Some(ext::BAD_SEGMENT) => &mut c.open_format_rejects,
                Some(ext::OUT_OF_CONNECTIONS) => &mut c.open_resource_rejects,
                _ => &mut c.open_other_rejects,
            });
            let remaining = if e.extended() == Some(ext::BAD_SEGMENT) {
                (fo.path.len() / 2) as u8
            } else {
                0
            };
            FailureReplyRepr {
                triad: fo.triad,
                remaining_path_words: remaining,
            }
            .emit(w)?;
            return Err(e.keeping_data());
        }
    };
    let conn = ctx
        .connections
        .get(slot)
        .ok_or(CipError::new(General::ResourceUnavailable))?;
    if fo.t_o_params.connection_type == ConnectionType::Multicast {
        ctx.reply_t_o_sockaddr = Some(SockAddrRepr {
            addr: net.multicast,
            port: IO_PORT,
        });
    }
    ForwardOpenReplyRepr {
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

fn forward_close<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    data: &[u8],
    w: &mut Writer<'_>,
) -> CipResult {
    let fc = match ForwardCloseRepr::parse(data) {
        Ok(fc) => fc,
        Err(e) => {
            bump(&mut ctx.state.connection_manager.close_format_rejects);
            return malformed(e, Triad::at(data, FORWARD_CLOSE_TRIAD_AT), w);
        }
    };
    let Some(slot) = ctx.connections.find_triad(&fc.triad) else {
        bump(&mut ctx.state.connection_manager.close_other_rejects);
        FailureReplyRepr {
            triad: fc.triad,
            remaining_path_words: 0,
        }
        .emit(w)?;
        return Err(CipError::connection(ext::NOT_FOUND).keeping_data());
    };
    ctx.connections
        .close(slot, CloseReason::ForwardClose, ctx.device);
    ForwardCloseReplyRepr {
        triad: fc.triad,
        application_reply: &[],
    }
    .emit(w)?;
    Ok(())
}

/// True if `req` is an Unconnected_Send to the Connection Manager.
pub(crate) fn is_unconnected_send(req: &Request<'_>) -> bool {
    req.service == service::UNCONNECTED_SEND
        && req.path.class == Some(u32::from(class_id::CONNECTION_MANAGER))
}

/// The embedded request of an Unconnected_Send whose route path ends here (port 1, link 0:
/// the backplane slot of a single-module device); its reply is sent as the whole reply. A
/// route path that goes elsewhere is a routing error, whose reply (begun at the writer's
/// end, its header reserved) carries the Remaining Path Size (Vol 1 3-5.5.4: the route's
/// words as the router that found the error saw them, here all of them) and a reserved byte.
pub(crate) fn embedded_request<'a>(
    req: &Request<'a>,
    depth: u8,
    w: &mut Writer<'_>,
) -> CipResult<&'a [u8]> {
    if depth >= MAX_DEPTH {
        return Err(General::ServiceNotSupported.into());
    }
    match req.path.instance_or_point() {
        Some(1) => {}
        // The class itself: Unconnected_Send is an instance service, as Forward_Open is.
        Some(0) => return Err(General::ServiceNotSupported.into()),
        Some(_) => return Err(General::ObjectDoesNotExist.into()),
        None => return Err(General::PathDestinationUnknown.into()),
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
    if let Err(e) = check_route(route) {
        w.zeros(4)?;
        // Remaining Path Size, and a reserved byte (as the Forward_Open's failure reply).
        w.u8(words as u8)?;
        w.u8(0)?;
        return Err(e.keeping_data());
    }
    Ok(embedded)
}

/// Accepts a route path of exactly one port segment to port 1, link address 0.
fn check_route(route: &[u8]) -> CipResult {
    let mut segs = Segments::new(route);
    let first = segs.next();
    match (first, segs.next()) {
        (Some(Ok(SegmentRepr::Port { port: 1, link: [0] })), None) => Ok(()),
        (Some(Ok(SegmentRepr::Port { port: 1, .. })), None) => {
            Err(CipError::connection(EXT_LINK_ADDRESS_NOT_VALID))
        }
        (Some(Ok(SegmentRepr::Port { .. })), None) => {
            Err(CipError::connection(EXT_PORT_NOT_AVAILABLE))
        }
        _ => Err(CipError::connection(ext::BAD_SEGMENT)),
    }
}
