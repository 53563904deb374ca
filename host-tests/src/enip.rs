//! A deliberately small, independent EtherNet/IP client for raw-socket tests: frames are
//! built byte by byte here (not with the stack's codecs) so that tests can also build
//! frames no well-behaved client would send.

use std::io::{self, Read, Write};
use std::net::TcpStream;
use std::time::{Duration, Instant};

use crate::netns::Namespace;
use crate::rig::board_addr;

/// Length of the encapsulation header.
pub const HEADER_LEN: usize = 24;

/// Encapsulation command codes.
pub mod command {
    /// No operation.
    pub const NOP: u16 = 0x0000;
    /// ListServices.
    pub const LIST_SERVICES: u16 = 0x0004;
    /// ListIdentity.
    pub const LIST_IDENTITY: u16 = 0x0063;
    /// ListInterfaces.
    pub const LIST_INTERFACES: u16 = 0x0064;
    /// RegisterSession.
    pub const REGISTER_SESSION: u16 = 0x0065;
    /// UnregisterSession.
    pub const UNREGISTER_SESSION: u16 = 0x0066;
    /// SendRRData.
    pub const SEND_RR_DATA: u16 = 0x006F;
}

/// An encapsulation header; `length` is what goes on the wire, true or not.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Header {
    /// Command code.
    pub command: u16,
    /// Length field.
    pub length: u16,
    /// Session handle.
    pub session: u32,
    /// Status.
    pub status: u32,
    /// Sender context.
    pub context: [u8; 8],
    /// Options.
    pub options: u32,
}

impl Header {
    /// A header for `command` with everything else zero.
    pub const fn new(command: u16) -> Self {
        Header {
            command,
            length: 0,
            session: 0,
            status: 0,
            context: [0; 8],
            options: 0,
        }
    }

    /// The 24 header bytes, with the length field as set.
    pub fn bytes(&self) -> Vec<u8> {
        let mut b = Vec::with_capacity(HEADER_LEN);
        b.extend_from_slice(&self.command.to_le_bytes());
        b.extend_from_slice(&self.length.to_le_bytes());
        b.extend_from_slice(&self.session.to_le_bytes());
        b.extend_from_slice(&self.status.to_le_bytes());
        b.extend_from_slice(&self.context);
        b.extend_from_slice(&self.options.to_le_bytes());
        b
    }

    /// A whole frame: this header with its length set to `data`'s, then `data`.
    pub fn frame(&self, data: &[u8]) -> Vec<u8> {
        let length = u16::try_from(data.len()).unwrap_or(u16::MAX);
        let mut b = Header { length, ..*self }.bytes();
        b.extend_from_slice(data);
        b
    }

    /// Parses the first 24 bytes of `b`.
    pub fn parse(b: &[u8]) -> Option<Header> {
        let u16_at = |i: usize| Some(u16::from_le_bytes(b.get(i..i + 2)?.try_into().ok()?));
        let u32_at = |i: usize| Some(u32::from_le_bytes(b.get(i..i + 4)?.try_into().ok()?));
        Some(Header {
            command: u16_at(0)?,
            length: u16_at(2)?,
            session: u32_at(4)?,
            status: u32_at(8)?,
            context: b.get(12..20)?.try_into().ok()?,
            options: u32_at(20)?,
        })
    }
}

/// A received frame.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Frame {
    /// Its header.
    pub header: Header,
    /// Its data part.
    pub data: Vec<u8>,
}

impl Frame {
    /// Parses a whole frame (a datagram); `None` if the length field disagrees with `b`.
    pub fn parse(b: &[u8]) -> Option<Frame> {
        let header = Header::parse(b)?;
        let data = b.get(HEADER_LEN..)?.to_vec();
        (data.len() == usize::from(header.length)).then_some(Frame { header, data })
    }
}

/// RegisterSession data: protocol `version`, no options.
pub fn register_data(version: u16) -> Vec<u8> {
    let mut d = version.to_le_bytes().to_vec();
    d.extend_from_slice(&[0, 0]);
    d
}

/// SendRRData data: interface handle 0, timeout 0, then the Common Packet Format `cpf`.
pub fn rr_data(cpf: &[u8]) -> Vec<u8> {
    let mut d = vec![0u8; 6];
    d.extend_from_slice(cpf);
    d
}

/// A CPF of a null address item and an unconnected data item carrying `mr`.
pub fn ucmm_cpf(mr: &[u8]) -> Vec<u8> {
    let mut c = vec![2, 0, 0, 0, 0, 0, 0xB2, 0];
    c.extend_from_slice(&u16::try_from(mr.len()).unwrap_or(u16::MAX).to_le_bytes());
    c.extend_from_slice(mr);
    c
}

/// A Message Router request: `service`, the padded `path` (its size in words), `data`.
pub fn mr_request(service: u8, path: &[u8], data: &[u8]) -> Vec<u8> {
    let mut r = vec![service, u8::try_from(path.len() / 2).unwrap_or(u8::MAX)];
    r.extend_from_slice(path);
    r.extend_from_slice(data);
    r
}

/// A logical path to `class`, `instance` and optionally `attribute` (8-bit segments).
pub fn path(class: u8, instance: u8, attribute: Option<u8>) -> Vec<u8> {
    let mut p = vec![0x20, class, 0x24, instance];
    if let Some(a) = attribute {
        p.extend_from_slice(&[0x30, a]);
    }
    p
}

/// A Message Router reply.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MrReply {
    /// Reply service code (request service | 0x80).
    pub service: u8,
    /// General status.
    pub general: u8,
    /// Additional status words.
    pub additional: Vec<u16>,
    /// Reply data.
    pub data: Vec<u8>,
}

impl MrReply {
    /// Extracts the reply from SendRRData reply data (null address + unconnected data item).
    pub fn from_rr_data(d: &[u8]) -> Option<MrReply> {
        let item = d.get(6..)?;
        if item.get(..8)? != [2, 0, 0, 0, 0, 0, 0xB2, 0] {
            return None;
        }
        let len = usize::from(u16::from_le_bytes(item.get(8..10)?.try_into().ok()?));
        let mr = item.get(10..)?;
        if mr.len() != len {
            return None;
        }
        let n = usize::from(*mr.get(3)?);
        let additional = mr
            .get(4..4 + 2 * n)?
            .chunks(2)
            .map(|w| u16::from_le_bytes([w[0], w[1]]))
            .collect();
        Some(MrReply {
            service: *mr.first()?,
            general: *mr.get(2)?,
            additional,
            data: mr.get(4 + 2 * n..)?.to_vec(),
        })
    }
}

/// A TCP connection to the board, opened from inside the test namespace.
#[derive(Debug)]
pub struct Client {
    stream: TcpStream,
    /// The registered session handle (0 before RegisterSession).
    pub session: u32,
}

impl Client {
    /// Connects to the board within `timeout`.
    pub fn connect(ns: &Namespace, timeout: Duration) -> io::Result<Client> {
        let stream = ns.inside(|| TcpStream::connect_timeout(&board_addr(), timeout))??;
        stream.set_nodelay(true)?;
        Ok(Self::from_stream(stream))
    }

    /// Wraps an already connected stream (no session yet).
    pub fn from_stream(stream: TcpStream) -> Client {
        Client { stream, session: 0 }
    }

    /// Sends raw bytes.
    pub fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.stream.write_all(bytes)
    }

    /// Receives one whole frame within `timeout`.
    pub fn recv(&mut self, timeout: Duration) -> io::Result<Frame> {
        let deadline = Instant::now() + timeout;
        let mut head = [0u8; HEADER_LEN];
        self.read_exact_by(&mut head, deadline)?;
        let header = Header::parse(&head).ok_or(io::ErrorKind::InvalidData)?;
        let mut data = vec![0u8; usize::from(header.length)];
        self.read_exact_by(&mut data, deadline)?;
        Ok(Frame { header, data })
    }

    fn read_exact_by(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<()> {
        let mut got = 0;
        while got < buf.len() {
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Err(io::ErrorKind::TimedOut.into());
            }
            self.stream.set_read_timeout(Some(left))?;
            match self.stream.read(&mut buf[got..]) {
                Ok(0) => return Err(io::ErrorKind::UnexpectedEof.into()),
                Ok(n) => got += n,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
        Ok(())
    }

    /// Sends `header` with `data` and returns the reply frame.
    pub fn exchange(
        &mut self,
        header: Header,
        data: &[u8],
        timeout: Duration,
    ) -> io::Result<Frame> {
        self.send(&header.frame(data))?;
        self.recv(timeout)
    }

    /// Registers a session; fails unless the board accepts it.
    pub fn register(&mut self, timeout: Duration) -> io::Result<u32> {
        let reply = self.exchange(
            Header::new(command::REGISTER_SESSION),
            &register_data(1),
            timeout,
        )?;
        if reply.header.status != 0 || reply.header.session == 0 {
            return Err(io::Error::other(format!(
                "RegisterSession refused: {reply:?}"
            )));
        }
        self.session = reply.header.session;
        Ok(self.session)
    }

    /// Sends the Message Router request `mr` by SendRRData in this session; returns the
    /// encapsulation reply frame.
    pub fn send_rr(&mut self, mr: &[u8], timeout: Duration) -> io::Result<Frame> {
        let header = Header {
            session: self.session,
            ..Header::new(command::SEND_RR_DATA)
        };
        self.exchange(header, &rr_data(&ucmm_cpf(mr)), timeout)
    }

    /// Sends `mr` by SendRRData and returns the Message Router reply.
    pub fn request(&mut self, mr: &[u8], timeout: Duration) -> io::Result<MrReply> {
        let frame = self.send_rr(mr, timeout)?;
        if frame.header.status != 0 {
            return Err(io::Error::other(format!("SendRRData failed: {frame:?}")));
        }
        MrReply::from_rr_data(&frame.data)
            .ok_or_else(|| io::Error::other(format!("bad SendRRData reply: {frame:?}")))
    }

    /// Waits up to `timeout` for the board to close the connection: true if it did (FIN or
    /// reset), false if it stayed open; any data received first is an error.
    pub fn closed_within(&mut self, timeout: Duration) -> io::Result<bool> {
        self.stream.set_read_timeout(Some(timeout))?;
        let mut b = [0u8; 64];
        match self.stream.read(&mut b) {
            Ok(0) => Ok(true),
            Ok(n) => Err(io::Error::other(format!(
                "unexpected data: {:02x?}",
                &b[..n]
            ))),
            Err(e) if e.kind() == io::ErrorKind::ConnectionReset => Ok(true),
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut
                ) =>
            {
                Ok(false)
            }
            Err(e) => Err(e),
        }
    }
}
