//! An explicit-messaging session over TCP 44818: RegisterSession, requests, Forward_Open and
//! Forward_Close.

use std::io::{self, Read, Write};
use std::net::{Ipv4Addr, SocketAddrV4, TcpStream};
use std::time::Duration;

use enip_stack::config::{ENCAP_PORT, MAX_ENCAP_FRAME};
use enip_stack::originator;
use enip_stack::wire::encap::{EncapRepr, HEADER_LEN};
use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use enip_stack::wire::forward_open::{
    ForwardCloseRepr, ForwardOpenReplyRepr, ForwardOpenRepr, Triad,
};
use enip_stack::wire::Writer;

/// A Message Router response, owned.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Response {
    /// General status.
    pub general: u8,
    /// Additional status words.
    pub additional: Vec<u16>,
    /// Response data.
    pub data: Vec<u8>,
}

/// A registered encapsulation session.
#[derive(Debug)]
pub struct Session {
    stream: TcpStream,
    /// The session handle the adapter gave.
    pub handle: u32,
}

fn invalid(msg: &str) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidData, msg.to_string())
}

fn wire(e: enip_stack::wire::Error) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidData, e)
}

/// The Connection Manager path.
const CONNECTION_MANAGER: [SegmentRepr<'static>; 2] = [
    SegmentRepr::Logical(LogicalType::Class, 6),
    SegmentRepr::Logical(LogicalType::Instance, 1),
];

impl Session {
    /// Connects to `target`:44818 and registers a session.
    pub fn connect(target: Ipv4Addr, timeout: Duration) -> io::Result<Session> {
        let stream =
            TcpStream::connect_timeout(&SocketAddrV4::new(target, ENCAP_PORT).into(), timeout)?;
        stream.set_read_timeout(Some(timeout))?;
        stream.set_nodelay(true)?;
        let mut s = Session { stream, handle: 0 };
        let mut buf = [0u8; 64];
        let n = originator::register_session(&mut buf).map_err(wire)?;
        let reply = s.transact(buf.get(..n).unwrap_or(&[]))?;
        let header = EncapRepr::parse_header(&reply).map_err(wire)?;
        if header.status != 0 {
            return Err(invalid(&format!(
                "RegisterSession status {:#x}",
                header.status
            )));
        }
        s.handle = header.session_handle;
        Ok(s)
    }

    /// Sends one frame and reads one reply frame.
    pub fn transact(&mut self, frame: &[u8]) -> io::Result<Vec<u8>> {
        self.stream.write_all(frame)?;
        let mut reply = vec![0u8; HEADER_LEN];
        self.stream.read_exact(&mut reply)?;
        let header = EncapRepr::parse_header(&reply).map_err(wire)?;
        reply.resize(HEADER_LEN + usize::from(header.length), 0);
        self.stream
            .read_exact(reply.get_mut(HEADER_LEN..).unwrap_or(&mut []))?;
        Ok(reply)
    }

    /// Sends a request by SendRRData and returns the response.
    pub fn request(
        &mut self,
        service: u8,
        path: &[SegmentRepr<'_>],
        data: &[u8],
    ) -> io::Result<Response> {
        let mut buf = vec![0u8; MAX_ENCAP_FRAME];
        let n = originator::send_rr_data(&mut buf, self.handle, None, |w| {
            originator::request(w, service, path, data)
        })
        .map_err(wire)?;
        let reply = self.transact(buf.get(..n).unwrap_or(&[]))?;
        let parsed = originator::parse_reply(&reply).map_err(wire)?;
        let r = parsed
            .response
            .ok_or_else(|| invalid(&format!("encapsulation status {:#x}", parsed.header.status)))?;
        Ok(Response {
            general: r.general_status,
            additional: r
                .additional_status
                .chunks_exact(2)
                .map(|c| u16::from_le_bytes([c[0], c[1]]))
                .collect(),
            data: r.data.to_vec(),
        })
    }

    /// Sends a Forward_Open (or Large_Forward_Open); Ok(Err) carries a refusal.
    pub fn forward_open(
        &mut self,
        fo: &ForwardOpenRepr<'_>,
    ) -> io::Result<Result<ForwardOpenReplyRepr<'static>, Response>> {
        let mut data = [0u8; 256];
        let mut w = Writer::new(&mut data);
        fo.emit(&mut w).map_err(wire)?;
        let n = w.len();
        let service = if fo.large { 0x5B } else { 0x54 };
        let r = self.request(service, &CONNECTION_MANAGER, data.get(..n).unwrap_or(&[]))?;
        if r.general != 0 {
            return Ok(Err(r));
        }
        let reply = ForwardOpenReplyRepr::parse(&r.data).map_err(wire)?;
        Ok(Ok(ForwardOpenReplyRepr {
            application_reply: &[],
            ..reply
        }))
    }

    /// Sends a Forward_Close for `triad`.
    pub fn forward_close(&mut self, triad: Triad) -> io::Result<Response> {
        let fc = ForwardCloseRepr {
            priority_tick: 0x0A,
            timeout_ticks: 0x0E,
            triad,
            path: &[0x20, 0x04],
        };
        let mut data = [0u8; 64];
        let mut w = Writer::new(&mut data);
        fc.emit(&mut w).map_err(wire)?;
        let n = w.len();
        self.request(0x4E, &CONNECTION_MANAGER, data.get(..n).unwrap_or(&[]))
    }
}
