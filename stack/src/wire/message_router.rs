//! Message Router request and response framing (Vol 1, 2-4.1 and 2-4.2).

use super::{Error, Reader, Result, Writer};

/// Bit set in the service code of every reply.
pub const REPLY_BIT: u8 = 0x80;

/// A view over a Message Router request: service, request path and request data.
#[derive(Debug, Clone)]
pub struct RequestPacket<T: AsRef<[u8]>> {
    buffer: T,
}

/// Where the request path of `words` 16-bit words ends: after the service and size bytes.
#[allow(clippy::arithmetic_side_effects)] // At most 2 + 2 x 255.
const fn path_end(words: u8) -> usize {
    2 + 2 * words as usize
}

impl<T: AsRef<[u8]>> RequestPacket<T> {
    /// Wraps a request whose path fits in the buffer.
    pub fn new_checked(buffer: T) -> Result<Self> {
        let b = buffer.as_ref();
        let words = *b.get(1).ok_or(Error::Truncated)?;
        if b.len() < path_end(words) {
            return Err(Error::Truncated);
        }
        Ok(RequestPacket { buffer })
    }
    /// Service code.
    pub fn service(&self) -> u8 {
        self.buffer.as_ref().first().copied().unwrap_or(0)
    }
    /// Request path size in 16-bit words.
    pub fn path_words(&self) -> u8 {
        self.buffer.as_ref().get(1).copied().unwrap_or(0)
    }
    /// The request path bytes.
    pub fn path(&self) -> &[u8] {
        let end = path_end(self.path_words());
        self.buffer.as_ref().get(2..end).unwrap_or(&[])
    }
    /// The request data after the path.
    pub fn data(&self) -> &[u8] {
        let start = path_end(self.path_words());
        self.buffer.as_ref().get(start..).unwrap_or(&[])
    }
}

/// A parsed request.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RequestRepr<'a> {
    /// Service code.
    pub service: u8,
    /// Request path (padded EPATH).
    pub path: &'a [u8],
    /// Request data.
    pub data: &'a [u8],
}

impl<'a> RequestRepr<'a> {
    /// Parses a checked request.
    pub fn parse(p: &RequestPacket<&'a [u8]>) -> RequestRepr<'a> {
        let b: &'a [u8] = p.buffer;
        let end = path_end(p.path_words());
        RequestRepr {
            service: p.service(),
            path: b.get(2..end).unwrap_or(&[]),
            data: b.get(end..).unwrap_or(&[]),
        }
    }
    /// Bytes the request takes.
    pub const fn buffer_len(&self) -> usize {
        self.path
            .len()
            .saturating_add(self.data.len())
            .saturating_add(2)
    }
    /// Writes the request (the path must be a whole number of words).
    pub fn emit(&self, w: &mut Writer<'_>) -> Result<()> {
        if !self.path.len().is_multiple_of(2) {
            return Err(Error::Malformed);
        }
        w.u8(self.service)?;
        w.u8(u8::try_from(self.path.len() / 2).map_err(|_| Error::Malformed)?)?;
        w.bytes(self.path)?;
        w.bytes(self.data)
    }
}

/// A Message Router response, parsed or to emit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ResponseRepr<'a> {
    /// Service code with the reply bit set ([`REPLY_BIT`]).
    pub service: u8,
    /// General status.
    pub general_status: u8,
    /// Additional status words, as raw little-endian bytes (a whole number of words).
    pub additional_status: &'a [u8],
    /// Response data.
    pub data: &'a [u8],
}

impl<'a> ResponseRepr<'a> {
    /// Parses a response.
    pub fn parse(buf: &'a [u8]) -> Result<ResponseRepr<'a>> {
        let mut r = Reader::new(buf);
        let service = r.u8()?;
        r.u8()?;
        let general_status = r.u8()?;
        let words = usize::from(r.u8()?);
        let additional_status = r.take(words * 2)?;
        Ok(ResponseRepr {
            service,
            general_status,
            additional_status,
            data: r.rest(),
        })
    }
    /// The first additional status word, if any.
    pub fn extended_status(&self) -> Option<u16> {
        match self.additional_status {
            [a, b, ..] => Some(u16::from_le_bytes([*a, *b])),
            _ => None,
        }
    }
    /// Bytes the response takes.
    pub const fn buffer_len(&self) -> usize {
        self.additional_status
            .len()
            .saturating_add(self.data.len())
            .saturating_add(4)
    }
    /// Writes the response: service, reserved byte, general status, additional status, data.
    pub fn emit(&self, w: &mut Writer<'_>) -> Result<()> {
        if !self.additional_status.len().is_multiple_of(2) {
            return Err(Error::Malformed);
        }
        let words = u8::try_from(self.additional_status.len() / 2).map_err(|_| Error::Malformed)?;
        w.bytes(&[self.service, 0, self.general_status, words])?;
        w.bytes(self.additional_status)?;
        w.bytes(self.data)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn request_round_trip() {
        let wire = [0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x07, 9];
        let p = RequestPacket::new_checked(&wire[..]).unwrap();
        let r = RequestRepr::parse(&p);
        assert_eq!(r.service, 0x0E);
        assert_eq!(r.path, &wire[2..8]);
        assert_eq!(r.data, &[9]);
        let mut buf = [0u8; 16];
        let mut w = Writer::new(&mut buf);
        r.emit(&mut w).unwrap();
        assert_eq!(w.written(), &wire);
    }

    #[test]
    fn path_longer_than_request() {
        assert_eq!(
            RequestPacket::new_checked(&[0x0E, 3, 0x20, 1][..]).unwrap_err(),
            Error::Truncated
        );
        assert_eq!(
            RequestPacket::new_checked(&[0x0E][..]).unwrap_err(),
            Error::Truncated
        );
    }

    #[test]
    fn response_round_trip() {
        let response = ResponseRepr {
            service: 0x54 | REPLY_BIT,
            general_status: 0x01,
            additional_status: &[0x00, 0x01],
            data: &[0xAA],
        };
        let mut buf = [0u8; 16];
        let mut w = Writer::new(&mut buf);
        response.emit(&mut w).unwrap();
        let n = w.len();
        assert_eq!(n, response.buffer_len());
        assert_eq!(&buf[..n], &[0xD4, 0, 1, 1, 0x00, 0x01, 0xAA]);
        let r = ResponseRepr::parse(&buf[..n]).unwrap();
        assert_eq!(r, response);
        assert_eq!(r.extended_status(), Some(0x0100));
        let odd = ResponseRepr {
            additional_status: &[1],
            ..response
        };
        assert_eq!(odd.emit(&mut Writer::new(&mut buf)), Err(Error::Malformed));
    }
}
