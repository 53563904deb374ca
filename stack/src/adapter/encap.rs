//! Encapsulation command handling for whole frames received over TCP or UDP.

use core::net::SocketAddrV4;

use super::{Inner, SocketId, TcpOutcome};
use crate::cip::context::{RequestContext, Via};
use crate::device::Device;
use crate::encap::session::Session;
use crate::io::explicit;
use crate::io::open::Origin;
use crate::objects::router;
use crate::time::Instant;
use crate::wire::cpf::{self, item_type, ItemHeaderRepr, SockAddrRepr};
use crate::wire::encap::{command, status, EncapRepr, Packet, HEADER_LEN};
use crate::wire::identity_item::{listen_socket, IdentityRepr, ServiceRepr};
use crate::wire::register_session::{self, RegisterSessionRepr, PROTOCOL_VERSION};
use crate::wire::rr_data::{self, RrDataRepr};
use crate::wire::Writer;

/// The ListIdentity reply's CIP Security item (CIP Vol 8; Wireshark's ENIP dissector).
#[cfg(feature = "cip-security")]
const CIP_SECURITY_ITEM: u16 = 0x0086;

/// Identity state reported in ListIdentity: operational.
const STATE_OPERATIONAL: u8 = 3;

impl<D: Device, const C: usize, const L: usize> Inner<D, C, L> {
    /// Answers one complete frame received on `session`'s socket, whose `header` the caller
    /// parsed; the outcome's `consumed` and `reset` are left for the caller.
    pub(crate) fn tcp_frame(
        &mut self,
        mut session: Session<'_>,
        header: &EncapRepr,
        frame: &[u8],
        now: Instant,
        reply: &mut [u8],
    ) -> TcpOutcome {
        if header.options != 0 {
            // Vol 2, 2-3.6: a frame with non-zero options is discarded.
            return TcpOutcome::default();
        }
        let data = frame.get(HEADER_LEN..).unwrap_or(&[]);
        let registered = session.handle();
        let mut close = false;
        let reply_len = match header.command {
            command::NOP => 0,
            command::LIST_IDENTITY => {
                let (handle, context) = (header.session_handle, header.sender_context);
                self.list_identity_reply(handle, context, now, reply)
            }
            command::LIST_SERVICES => list_services_reply(header, reply),
            command::LIST_INTERFACES => list_interfaces_reply(header, reply),
            command::REGISTER_SESSION => register_session(&mut session, header, data, reply),
            command::UNREGISTER_SESSION if registered == Some(header.session_handle) => {
                close = true;
                0
            }
            command::UNREGISTER_SESSION | command::SEND_RR_DATA | command::SEND_UNIT_DATA
                if registered != Some(header.session_handle) =>
            {
                error_reply(header, status::INVALID_SESSION, reply)
            }
            command::SEND_RR_DATA => {
                let len = self.send_rr_data(&session, header, data, now, reply);
                self.after_explicit_request();
                len
            }
            command::SEND_UNIT_DATA => {
                let len = self.send_unit_data(&session, header, data, now, reply);
                self.after_explicit_request();
                len
            }
            _ => error_reply(header, status::INVALID_COMMAND, reply),
        };
        TcpOutcome {
            consumed: 0,
            reply_len,
            close,
            reset: None,
        }
    }

    /// Handles one datagram received on UDP 44818. ListIdentity replies are charged to the
    /// byte budget ([`crate::config::LIST_IDENTITY_UDP_BYTES_PER_SECOND`]).
    pub(crate) fn udp_frame(
        &mut self,
        from: SocketAddrV4,
        broadcast: bool,
        datagram: &[u8],
        now: Instant,
        reply: &mut [u8],
    ) -> usize {
        let header = match Packet::new_checked(datagram).and_then(|p| EncapRepr::parse(&p)) {
            Ok(h) if h.options == 0 => h,
            _ => return 0,
        };
        match header.command {
            command::NOP => 0,
            // At most one reply per request, and only within the byte budget: a reply that
            // does not fit (or, for a broadcast request, finds the delay queue full) is not
            // sent at all, so spoofed requests cannot make the device an amplifier.
            command::LIST_IDENTITY => {
                let (handle, context) = (header.session_handle, header.sender_context);
                if broadcast && !self.delayed.has_room() {
                    return 0;
                }
                // Written now to know its size; a delayed one is written again when due.
                let len = self.list_identity_reply(handle, context, now, reply);
                if len == 0 || !self.delayed.budget.take(len, now) {
                    return 0;
                }
                if broadcast {
                    self.delayed
                        .schedule(from, context, handle, now, &mut self.rng);
                    return 0;
                }
                len
            }
            command::LIST_SERVICES => list_services_reply(&header, reply),
            command::LIST_INTERFACES => list_interfaces_reply(&header, reply),
            _ => error_reply(&header, status::INVALID_COMMAND, reply),
        }
    }

    /// Writes a ListIdentity reply as of `now`; returns its length (0 if `out` is too small).
    pub(crate) fn list_identity_reply(
        &mut self,
        session_handle: u32,
        sender_context: [u8; 8],
        now: Instant,
        out: &mut [u8],
    ) -> usize {
        let ident = *self.device.identity();
        let status = crate::objects::identity::status(
            self.device.status_bits(),
            self.connections.identity_status(),
        );
        let item = IdentityRepr {
            protocol_version: PROTOCOL_VERSION,
            socket: listen_socket(self.net.ip),
            vendor_id: ident.vendor_id,
            device_type: ident.device_type,
            product_code: ident.product_code,
            revision: ident.revision,
            status,
            serial_number: ident.serial_number,
            product_name: ident.product_name.as_bytes(),
            state: STATE_OPERATIONAL,
        };
        let header = EncapRepr {
            command: command::LIST_IDENTITY,
            length: 0,
            session_handle,
            status: status::SUCCESS,
            sender_context,
            options: 0,
        };
        #[cfg(feature = "cip-security")]
        let security = {
            // The states as of now: a configuration session that lapsed shows as ended.
            let st = &mut self.objects.security;
            st.expire(now);
            st.enabled.then(|| st.list_identity_item())
        };
        #[cfg(not(feature = "cip-security"))]
        let _ = now;
        with_body(&header, out, |w| {
            #[cfg(feature = "cip-security")]
            if let Some(sec) = security {
                w.u16(2)?;
                ItemHeaderRepr::new(item_type::LIST_IDENTITY, item.buffer_len() as u16).emit(w)?;
                item.emit(w)?;
                ItemHeaderRepr::new(CIP_SECURITY_ITEM, sec.len() as u16).emit(w)?;
                return w.bytes(&sec);
            }
            w.u16(1)?;
            ItemHeaderRepr::new(item_type::LIST_IDENTITY, item.buffer_len() as u16).emit(w)?;
            item.emit(w)
        })
    }

    /// The originator of requests on `session`.
    fn origin(session: &Session<'_>, t_o_sockaddr: Option<SockAddrRepr>) -> Option<Origin> {
        Some(Origin {
            ip: *session.peer?.ip(),
            socket: session.index as u8,
            t_o_sockaddr,
        })
    }

    /// SendRRData: a null address item and an unconnected data item carrying a request,
    /// optionally followed by socket address items (Forward_Open).
    fn send_rr_data(
        &mut self,
        session: &Session<'_>,
        header: &EncapRepr,
        data: &[u8],
        now: Instant,
        out: &mut [u8],
    ) -> usize {
        if data.len() < rr_data::PREFIX_LEN {
            return error_reply(header, status::INVALID_LENGTH, out);
        }
        let Some((request, t_o_sockaddr)) = unconnected_request(data) else {
            return error_reply(header, status::INCORRECT_DATA, out);
        };
        let origin = Self::origin(session, t_o_sockaddr);
        let cx = RequestContext::unconnected(session.peer, now);
        let mut ctx = self.ctx(cx, origin);
        let len = with_body(&header.reply(status::SUCCESS, 0), out, |w| {
            RrDataRepr::CIP.emit(w)?;
            let count_at = w.len();
            w.u16(2)?;
            ItemHeaderRepr::new(item_type::NULL_ADDRESS, 0).emit(w)?;
            ItemHeaderRepr::new(item_type::UNCONNECTED_DATA, 0).emit(w)?;
            let at = w.len();
            router::respond(&mut ctx, request, w, 0)?;
            w.patch_item_len(at);
            if let Some(sockaddr) = ctx.reply_t_o_sockaddr {
                w.patch_u16(count_at, 3);
                ItemHeaderRepr::new(item_type::SOCKADDR_T_O, cpf::SOCKADDR_LEN as u16).emit(w)?;
                sockaddr.emit(w)?;
            }
            Ok(())
        });
        if len == 0 {
            error_reply(header, status::INSUFFICIENT_MEMORY, out)
        } else {
            len
        }
    }

    /// SendUnitData: a connected address item and a connected data item (sequence count and
    /// request) on a Class 3 connection of this session. Unknown connections are dropped.
    fn send_unit_data(
        &mut self,
        session: &Session<'_>,
        header: &EncapRepr,
        data: &[u8],
        now: Instant,
        out: &mut [u8],
    ) -> usize {
        let Some((o_t_id, sequence, request)) = connected_request(data) else {
            return 0;
        };
        let Some(step) = explicit::lookup(
            &mut self.connections,
            o_t_id,
            session.index as u8,
            sequence,
            now,
        ) else {
            return 0;
        };
        let origin = Self::origin(session, None);
        match step {
            explicit::Step::Repeat { slot, t_o_id } => {
                let cached = explicit::cached(&self.connections, slot);
                with_body(&header.reply(status::SUCCESS, 0), out, |w| {
                    let at = rr_data::emit_connected(w, t_o_id, sequence)?;
                    w.bytes(cached)?;
                    w.patch_item_len(at);
                    Ok(())
                })
            }
            explicit::Step::Execute { slot, t_o_id } => {
                let cx = RequestContext {
                    via: Via::Connected { slot },
                    peer: session.peer,
                    now,
                };
                let mut ctx = self.ctx(cx, origin);
                let mut reply_at = 0;
                let len = with_body(&header.reply(status::SUCCESS, 0), out, |w| {
                    let at = rr_data::emit_connected(w, t_o_id, sequence)?;
                    reply_at = at.saturating_add(2);
                    router::respond(&mut ctx, request, w, 0)?;
                    w.patch_item_len(at);
                    Ok(())
                });
                let reply = out.get(reply_at..len).unwrap_or(&[]);
                explicit::store(&mut self.connections, slot, o_t_id, sequence, reply);
                len
            }
        }
    }
}

/// RegisterSession: registers `session` under a fresh handle unless it has one.
fn register_session(
    session: &mut Session<'_>,
    header: &EncapRepr,
    data: &[u8],
    out: &mut [u8],
) -> usize {
    let request = match register_session::Packet::new_checked(data) {
        Ok(p) => RegisterSessionRepr::parse(&p),
        Err(_) => return error_reply(header, status::INVALID_LENGTH, out),
    };
    let (status, handle) = if session.handle().is_some() {
        (status::INVALID_COMMAND, header.session_handle)
    } else if request.protocol_version != PROTOCOL_VERSION || request.options != 0 {
        (status::UNSUPPORTED_PROTOCOL, header.session_handle)
    } else {
        let h = session.register();
        if let Some(peer) = session.peer {
            info!(
                "session {:#010x} registered by {} (socket {})",
                h, peer, session.index
            );
        }
        (status::SUCCESS, h)
    };
    let reply = EncapRepr {
        session_handle: handle,
        ..header.reply(status, 0)
    };
    with_body(&reply, out, |w| {
        RegisterSessionRepr {
            protocol_version: PROTOCOL_VERSION,
            options: 0,
        }
        .emit(w)
    })
}

/// The request in a SendRRData CPF (null address, unconnected data, then at most socket
/// address items), with the T->O socket address if one was sent.
fn unconnected_request(data: &[u8]) -> Option<(&[u8], Option<SockAddrRepr>)> {
    let rr = rr_data::Packet::new_checked(data).ok()?;
    if rr.interface_handle() != 0 {
        return None;
    }
    let cpf_bytes = data.get(rr_data::PREFIX_LEN..)?;
    let mut items = cpf::Packet::new_checked(cpf_bytes).ok()?.into_items();
    let (a, d) = (items.next()?, items.next()?);
    if a.type_id != item_type::NULL_ADDRESS
        || d.type_id != item_type::UNCONNECTED_DATA
        || d.data.is_empty()
    {
        return None;
    }
    let mut t_o = None;
    for extra in items {
        match extra.type_id {
            item_type::SOCKADDR_T_O => t_o = Some(SockAddrRepr::parse(extra.data).ok()?),
            item_type::SOCKADDR_O_T => {}
            _ => return None,
        }
    }
    Some((d.data, t_o))
}

/// The connection ID, sequence count and request of a SendUnitData CPF.
fn connected_request(data: &[u8]) -> Option<(u32, u16, &[u8])> {
    let rr = rr_data::Packet::new_checked(data).ok()?;
    if rr.interface_handle() != 0 {
        return None;
    }
    let cpf_bytes: &[u8] = data.get(rr_data::PREFIX_LEN..)?;
    let mut items = cpf::Packet::new_checked(cpf_bytes).ok()?.into_items();
    let (a, d) = (items.next()?, items.next()?);
    if a.type_id != item_type::CONNECTED_ADDRESS
        || d.type_id != item_type::CONNECTED_DATA
        || items.next().is_some()
    {
        return None;
    }
    let id = crate::wire::bytes::get_u32(a.data, 0);
    let (seq, request) = d.data.split_at_checked(2)?;
    if request.is_empty() {
        return None;
    }
    Some((
        id,
        u16::from_le_bytes([*seq.first()?, *seq.get(1)?]),
        request,
    ))
}

/// Writes the frame of `header` with a body from `body` ([`EncapRepr::emit_with_body`]);
/// returns its length, or 0 if it did not fit.
fn with_body(
    header: &EncapRepr,
    out: &mut [u8],
    body: impl FnOnce(&mut Writer<'_>) -> crate::wire::Result<()>,
) -> usize {
    let mut w = Writer::new(out);
    match header.emit_with_body(&mut w, body) {
        Ok(()) => w.len(),
        Err(_) => 0,
    }
}

/// A header-only reply carrying `status`.
fn error_reply(header: &EncapRepr, status: u32, out: &mut [u8]) -> usize {
    with_body(&header.reply(status, 0), out, |_| Ok(()))
}

fn list_services_reply(header: &EncapRepr, out: &mut [u8]) -> usize {
    with_body(&header.reply(status::SUCCESS, 0), out, |w| {
        let s = ServiceRepr::communications();
        w.u16(1)?;
        ItemHeaderRepr::new(item_type::LIST_SERVICES, s.buffer_len() as u16).emit(w)?;
        s.emit(w)
    })
}

fn list_interfaces_reply(header: &EncapRepr, out: &mut [u8]) -> usize {
    with_body(&header.reply(status::SUCCESS, 0), out, |w| w.u16(0))
}

/// A frame longer than the stack holds on `socket`, whose `consumed` bytes were taken: its
/// data is skipped as it arrives and the session goes on; answered 0x0065 in `reply`, but a
/// NOP never is, at any length (Vol 2, 2-4.1), nor a frame with options (2-3.6). Out of
/// line: the request path does not carry it.
#[cold]
#[inline(never)]
pub(super) fn too_long(
    socket: SocketId,
    header: &EncapRepr,
    consumed: usize,
    reply: &mut [u8],
) -> TcpOutcome {
    let silent = header.command == command::NOP || header.options != 0;
    warn!(
        "encapsulation length {} over capacity on socket {}: skipped",
        header.length, socket.0
    );
    let mut w = crate::wire::Writer::new(reply);
    let sent = !silent && header.reply(status::INVALID_LENGTH, 0).emit(&mut w).is_ok();
    TcpOutcome {
        consumed,
        reply_len: if sent { HEADER_LEN } else { 0 },
        ..TcpOutcome::default()
    }
}
