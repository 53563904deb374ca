//! The 24-byte encapsulation header and the encapsulation command and status codes.

use super::bytes::{get_u16, get_u32, put_u16, put_u32};
use super::{Error, Result, Writer};

/// Length of the encapsulation header.
pub const HEADER_LEN: usize = 24;
/// TCP and UDP port of the encapsulation protocol.
pub const ENCAP_PORT: u16 = 44818;

mod field {
    pub const COMMAND: usize = 0;
    pub const LENGTH: usize = 2;
    pub const SESSION: usize = 4;
    pub const STATUS: usize = 8;
    pub const CONTEXT: core::ops::Range<usize> = 12..20;
    pub const OPTIONS: usize = 20;
}

/// Encapsulation command codes (Vol 2, table 2-3.2).
pub mod command {
    /// No operation; never answered.
    pub const NOP: u16 = 0x0000;
    /// Lists the encapsulation services (TCP or UDP).
    pub const LIST_SERVICES: u16 = 0x0004;
    /// Lists the device identity (TCP or UDP, often broadcast).
    pub const LIST_IDENTITY: u16 = 0x0063;
    /// Lists non-CIP interfaces (TCP or UDP).
    pub const LIST_INTERFACES: u16 = 0x0064;
    /// Opens a session (TCP only).
    pub const REGISTER_SESSION: u16 = 0x0065;
    /// Closes a session (TCP only).
    pub const UNREGISTER_SESSION: u16 = 0x0066;
    /// Unconnected request/reply (TCP only).
    pub const SEND_RR_DATA: u16 = 0x006F;
    /// Connected data (TCP only).
    pub const SEND_UNIT_DATA: u16 = 0x0070;
}

/// Encapsulation status codes (Vol 2, table 2-3.3).
pub mod status {
    /// Success.
    pub const SUCCESS: u32 = 0x0000;
    /// Invalid or unsupported command.
    pub const INVALID_COMMAND: u32 = 0x0001;
    /// No memory resources to handle the command.
    pub const INSUFFICIENT_MEMORY: u32 = 0x0002;
    /// Poorly formed or incorrect data in the data part.
    pub const INCORRECT_DATA: u32 = 0x0003;
    /// Invalid session handle.
    pub const INVALID_SESSION: u32 = 0x0064;
    /// Invalid length in the header.
    pub const INVALID_LENGTH: u32 = 0x0065;
    /// Unsupported encapsulation protocol revision.
    pub const UNSUPPORTED_PROTOCOL: u32 = 0x0069;
}

/// A view over an encapsulation frame (header plus data).
#[derive(Debug, Clone)]
pub struct Packet<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> Packet<T> {
    /// Wraps a buffer without checking it.
    pub const fn new_unchecked(buffer: T) -> Self {
        Packet { buffer }
    }
    /// Wraps a buffer that holds at least the header and the data its length field claims.
    pub fn new_checked(buffer: T) -> Result<Self> {
        let p = Self::new_unchecked(buffer);
        p.check_len()?;
        Ok(p)
    }
    /// Checks that the header and the declared data fit in the buffer.
    pub fn check_len(&self) -> Result<()> {
        let len = self.buffer.as_ref().len();
        if len < HEADER_LEN || len < HEADER_LEN + usize::from(self.length()) {
            Err(Error::Truncated)
        } else {
            Ok(())
        }
    }
    /// The command code.
    pub fn command(&self) -> u16 {
        get_u16(self.buffer.as_ref(), field::COMMAND)
    }
    /// Length of the data part.
    pub fn length(&self) -> u16 {
        get_u16(self.buffer.as_ref(), field::LENGTH)
    }
    /// Session handle.
    pub fn session_handle(&self) -> u32 {
        get_u32(self.buffer.as_ref(), field::SESSION)
    }
    /// Status.
    pub fn status(&self) -> u32 {
        get_u32(self.buffer.as_ref(), field::STATUS)
    }
    /// Sender context, echoed in replies.
    pub fn sender_context(&self) -> [u8; 8] {
        let mut c = [0u8; 8];
        if let Some(s) = self.buffer.as_ref().get(field::CONTEXT) {
            c.copy_from_slice(s);
        }
        c
    }
    /// Options (must be zero).
    pub fn options(&self) -> u32 {
        get_u32(self.buffer.as_ref(), field::OPTIONS)
    }
    /// The data part, as long as the length field says (or what is there, if shorter).
    pub fn data(&self) -> &[u8] {
        let b = self.buffer.as_ref();
        let end = HEADER_LEN
            .saturating_add(usize::from(self.length()))
            .min(b.len());
        b.get(HEADER_LEN..end).unwrap_or(&[])
    }
}

/// An encapsulation header, parsed or to emit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EncapRepr {
    /// Command code.
    pub command: u16,
    /// Length of the data part.
    pub length: u16,
    /// Session handle.
    pub session_handle: u32,
    /// Status.
    pub status: u32,
    /// Sender context.
    pub sender_context: [u8; 8],
    /// Options.
    pub options: u32,
}

impl EncapRepr {
    /// Parses the header of a packet (checking that its data is there too).
    pub fn parse<T: AsRef<[u8]>>(p: &Packet<T>) -> Result<EncapRepr> {
        p.check_len()?;
        Self::parse_header(p.buffer.as_ref())
    }
    /// Parses just the 24 header bytes at the start of `buf` (the data may not be there yet).
    pub fn parse_header(buf: &[u8]) -> Result<EncapRepr> {
        let head = buf.get(..HEADER_LEN).ok_or(Error::Truncated)?;
        let p = Packet::new_unchecked(head);
        Ok(EncapRepr {
            command: p.command(),
            length: p.length(),
            session_handle: p.session_handle(),
            status: p.status(),
            sender_context: p.sender_context(),
            options: p.options(),
        })
    }
    /// Bytes the header takes.
    pub const fn buffer_len(&self) -> usize {
        HEADER_LEN
    }
    /// Writes the 24 header bytes.
    pub fn emit(&self, w: &mut Writer<'_>) -> Result<()> {
        let buf = w.reserve(HEADER_LEN)?;
        put_u16(buf, field::COMMAND, self.command);
        put_u16(buf, field::LENGTH, self.length);
        put_u32(buf, field::SESSION, self.session_handle);
        put_u32(buf, field::STATUS, self.status);
        if let Some(c) = buf.get_mut(field::CONTEXT) {
            c.copy_from_slice(&self.sender_context);
        }
        put_u32(buf, field::OPTIONS, self.options);
        Ok(())
    }
    /// Writes a whole frame: this header, with its length set to that of the data part
    /// `body` writes after it. The one writer of encapsulation frames with a body, for
    /// replies and requests alike.
    pub fn emit_with_body(
        &self,
        w: &mut Writer<'_>,
        body: impl FnOnce(&mut Writer<'_>) -> Result<()>,
    ) -> Result<()> {
        let at = w.len();
        self.emit(w)?;
        body(w)?;
        let data = w.len().saturating_sub(at).saturating_sub(HEADER_LEN);
        let length = u16::try_from(data).map_err(|_| Error::Exhausted)?;
        w.patch_u16(at.saturating_add(field::LENGTH), length);
        Ok(())
    }
    /// The header of a reply to `self` with `status` and `length` bytes of data.
    pub const fn reply(&self, status: u32, length: u16) -> EncapRepr {
        EncapRepr {
            command: self.command,
            length,
            session_handle: self.session_handle,
            status,
            sender_context: self.sender_context,
            options: 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const REGISTER: [u8; 28] = [
        0x65, 0x00, 0x04, 0x00, 0, 0, 0, 0, 0, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7, 8, 0, 0, 0, 0, 1, 0,
        0, 0,
    ];

    #[test]
    fn emits_a_frame_with_its_body_length() {
        let mut buf = [0u8; 40];
        let mut w = Writer::new(&mut buf);
        let h = EncapRepr::parse(&Packet::new_checked(&REGISTER[..]).unwrap()).unwrap();
        h.emit_with_body(&mut w, |w| w.u32(1)).unwrap();
        assert_eq!(w.written(), &REGISTER[..]);
        let mut short = [0u8; 27];
        let mut w = Writer::new(&mut short);
        assert_eq!(
            h.emit_with_body(&mut w, |w| w.u32(1)),
            Err(Error::Exhausted)
        );
        let mut big = [0u8; 70_000];
        let mut w = Writer::new(&mut big);
        let huge = h.emit_with_body(&mut w, |w| w.zeros(65_536));
        assert_eq!(
            huge,
            Err(Error::Exhausted),
            "data longer than the length field"
        );
    }

    #[test]
    fn parses_register_session() {
        let p = Packet::new_checked(&REGISTER[..]).unwrap();
        let r = EncapRepr::parse(&p).unwrap();
        assert_eq!(r.command, command::REGISTER_SESSION);
        assert_eq!(r.length, 4);
        assert_eq!(r.sender_context, [1, 2, 3, 4, 5, 6, 7, 8]);
        assert_eq!(p.data(), &[1, 0, 0, 0]);
    }

    #[test]
    fn rejects_length_lie() {
        assert_eq!(
            Packet::new_checked(&REGISTER[..27]).unwrap_err(),
            Error::Truncated
        );
        assert_eq!(
            Packet::new_checked(&REGISTER[..10]).unwrap_err(),
            Error::Truncated
        );
    }

    #[test]
    fn round_trips() {
        let r = EncapRepr::parse_header(&REGISTER).unwrap();
        let mut out = [0u8; 24];
        r.emit(&mut Writer::new(&mut out)).unwrap();
        assert_eq!(&out[..], &REGISTER[..24]);
        assert_eq!(r.buffer_len(), HEADER_LEN);
        let mut short = [0u8; 23];
        assert_eq!(r.emit(&mut Writer::new(&mut short)), Err(Error::Exhausted));
        assert_eq!(short, [0; 23]);
    }
}
