//! Frame builders and reply parsers for the originator (scanner) side: what a test scanner
//! or a PLC sends to an adapter. Everything writes into caller buffers.

use crate::wire::cpf::{self, item_type, ItemHeaderRepr, SockAddrRepr};
use crate::wire::encap::{command, EncapRepr, HEADER_LEN};
use crate::wire::epath::SegmentRepr;
use crate::wire::io_datagram::{self, IoDatagramRepr};
use crate::wire::message_router::{RequestRepr, ResponseRepr};
use crate::wire::register_session::{RegisterSessionRepr, PROTOCOL_VERSION};
use crate::wire::rr_data::{self, RrDataRepr};
use crate::wire::{Error, Result, Writer};

/// Writes an encapsulation frame with `command` and a body from `body`
/// ([`EncapRepr::emit_with_body`]); returns its length.
pub fn frame(
    out: &mut [u8],
    command: u16,
    session_handle: u32,
    sender_context: [u8; 8],
    body: impl FnOnce(&mut Writer<'_>) -> Result<()>,
) -> Result<usize> {
    let mut w = Writer::new(out);
    let header = EncapRepr {
        command,
        length: 0,
        session_handle,
        status: 0,
        sender_context,
        options: 0,
    };
    header.emit_with_body(&mut w, body)?;
    Ok(w.len())
}

/// A RegisterSession request.
pub fn register_session(out: &mut [u8]) -> Result<usize> {
    frame(out, command::REGISTER_SESSION, 0, [0; 8], |w| {
        RegisterSessionRepr {
            protocol_version: PROTOCOL_VERSION,
            options: 0,
        }
        .emit(w)
    })
}

/// Writes a Message Router request: service, path built from `path`, then `data`.
pub fn request(
    w: &mut Writer<'_>,
    service: u8,
    path: &[SegmentRepr<'_>],
    data: &[u8],
) -> Result<()> {
    let mut raw = [0u8; 64];
    let mut pw = Writer::new(&mut raw);
    for s in path {
        s.emit(&mut pw)?;
    }
    let n = pw.len();
    RequestRepr {
        service,
        path: raw.get(..n).unwrap_or(&[]),
        data,
    }
    .emit(w)
}

/// A SendRRData frame carrying the request written by `mr`, optionally with a T->O socket
/// address item (a Forward_Open asking for T->O data on a given port).
pub fn send_rr_data(
    out: &mut [u8],
    session_handle: u32,
    t_o_sockaddr: Option<SockAddrRepr>,
    mr: impl FnOnce(&mut Writer<'_>) -> Result<()>,
) -> Result<usize> {
    frame(out, command::SEND_RR_DATA, session_handle, [0; 8], |w| {
        RrDataRepr {
            interface_handle: 0,
            timeout: 10,
        }
        .emit(w)?;
        w.u16(if t_o_sockaddr.is_some() { 3 } else { 2 })?;
        ItemHeaderRepr::new(item_type::NULL_ADDRESS, 0).emit(w)?;
        ItemHeaderRepr::new(item_type::UNCONNECTED_DATA, 0).emit(w)?;
        let at = w.len();
        mr(w)?;
        w.patch_item_len(at);
        if let Some(s) = t_o_sockaddr {
            ItemHeaderRepr::new(item_type::SOCKADDR_T_O, cpf::SOCKADDR_LEN as u16).emit(w)?;
            s.emit(w)?;
        }
        Ok(())
    })
}

/// A SendUnitData frame on Class 3 connection `o_t_id` with sequence count `sequence`.
pub fn send_unit_data(
    out: &mut [u8],
    session_handle: u32,
    o_t_id: u32,
    sequence: u16,
    mr: impl FnOnce(&mut Writer<'_>) -> Result<()>,
) -> Result<usize> {
    frame(out, command::SEND_UNIT_DATA, session_handle, [0; 8], |w| {
        let at = rr_data::emit_connected(w, o_t_id, sequence)?;
        mr(w)?;
        w.patch_item_len(at);
        Ok(())
    })
}

/// A decoded SendRRData or SendUnitData reply.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Reply<'a> {
    /// The encapsulation header.
    pub header: EncapRepr,
    /// The Message Router response (absent when the encapsulation status is not success).
    pub response: Option<ResponseRepr<'a>>,
    /// The T->O socket address item, if the reply carried one.
    pub t_o_sockaddr: Option<SockAddrRepr>,
    /// Connection ID and sequence count of a SendUnitData reply.
    pub connected: Option<(u32, u16)>,
}

/// Parses a SendRRData or SendUnitData reply frame.
pub fn parse_reply(frame: &[u8]) -> Result<Reply<'_>> {
    let header = EncapRepr::parse_header(frame)?;
    let data = frame
        .get(HEADER_LEN..HEADER_LEN + usize::from(header.length))
        .ok_or(Error::Truncated)?;
    let mut reply = Reply {
        header,
        response: None,
        t_o_sockaddr: None,
        connected: None,
    };
    if header.status != 0 || data.is_empty() {
        return Ok(reply);
    }
    let items = cpf::Packet::new_checked(data.get(rr_data::PREFIX_LEN..).ok_or(Error::Truncated)?)?;
    for item in items.into_items() {
        match item.type_id {
            item_type::UNCONNECTED_DATA => reply.response = Some(ResponseRepr::parse(item.data)?),
            item_type::CONNECTED_ADDRESS => {
                let id = crate::wire::bytes::get_u32(item.data, 0);
                reply.connected = Some((id, 0));
            }
            item_type::CONNECTED_DATA => {
                let (seq, rest) = item.data.split_at_checked(2).ok_or(Error::Truncated)?;
                let seq = crate::wire::bytes::get_u16(seq, 0);
                reply.connected = reply.connected.map(|(id, _)| (id, seq));
                reply.response = Some(ResponseRepr::parse(rest)?);
            }
            item_type::SOCKADDR_T_O => reply.t_o_sockaddr = Some(SockAddrRepr::parse(item.data)?),
            _ => {}
        }
    }
    Ok(reply)
}

/// A Class 1 O->T datagram; `run_idle` adds the 32-bit header with the run bit as given.
pub fn io_datagram(
    out: &mut [u8],
    connection_id: u32,
    encap_sequence: u32,
    sequence: u16,
    run_idle: Option<bool>,
    data: &[u8],
) -> Result<usize> {
    let header = if run_idle.is_some() {
        io_datagram::RUN_IDLE_LEN
    } else {
        0
    };
    let len = data
        .len()
        .saturating_add(io_datagram::SEQUENCE_LEN)
        .saturating_add(header);
    let mut w = Writer::new(out);
    IoDatagramRepr {
        connection_id,
        encap_sequence,
        connected_len: u16::try_from(len).map_err(|_| Error::Exhausted)?,
        sequence,
    }
    .emit(&mut w)?;
    if let Some(run) = run_idle {
        w.u32(u32::from(run))?;
    }
    w.bytes(data)?;
    Ok(w.len())
}
