//! Forward_Open (0x54), Large_Forward_Open (0x5B) and Forward_Close (0x4E) request data,
//! and their success and failure reply data (Vol 1, 3-5.5.2).

use super::{Error, Reader, Result, Writer};

/// The connection triad that identifies a connection to its originator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Triad {
    /// Connection serial number.
    pub connection_serial: u16,
    /// Originator vendor ID.
    pub vendor_id: u16,
    /// Originator serial number.
    pub originator_serial: u32,
}

impl Triad {
    /// Bytes the triad takes.
    pub const LEN: usize = 8;
    /// Parses the triad at the front of `r`.
    pub fn parse(r: &mut Reader<'_>) -> Result<Triad> {
        Ok(Triad {
            connection_serial: r.u16()?,
            vendor_id: r.u16()?,
            originator_serial: r.u32()?,
        })
    }
    /// The triad of request data whose triad starts `at` bytes in (10 in a Forward_Open, 2 in
    /// a Forward_Close), if the data reaches that far: a request that does not parse as a
    /// whole still names its connection for the failure reply.
    pub fn at(data: &[u8], at: usize) -> Option<Triad> {
        Triad::parse(&mut Reader::new(data.get(at..)?)).ok()
    }
    /// Writes the triad.
    pub fn emit(&self, w: &mut Writer<'_>) -> Result<()> {
        w.u16(self.connection_serial)?;
        w.u16(self.vendor_id)?;
        w.u32(self.originator_serial)
    }
}

/// Connection type field of the network connection parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ConnectionType {
    /// Null (no data in this direction).
    Null,
    /// Multicast.
    Multicast,
    /// Point-to-point.
    PointToPoint,
    /// Reserved value 3.
    Reserved,
}

/// Network connection parameters, normalised from the 16-bit or 32-bit form.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct NetworkParams {
    /// Redundant owner bit.
    pub redundant_owner: bool,
    /// Connection type.
    pub connection_type: ConnectionType,
    /// Priority (0 low, 1 high, 2 scheduled, 3 urgent).
    pub priority: u8,
    /// Variable (true) or fixed (false) size.
    pub variable: bool,
    /// Connection size in bytes.
    pub size: u16,
}

impl NetworkParams {
    const fn kind(bits: u32) -> ConnectionType {
        match bits & 3 {
            0 => ConnectionType::Null,
            1 => ConnectionType::Multicast,
            2 => ConnectionType::PointToPoint,
            _ => ConnectionType::Reserved,
        }
    }
    /// Decodes the 16-bit form (Forward_Open): size in bits 0-8.
    pub const fn from_u16(v: u16) -> Self {
        let v = v as u32;
        NetworkParams {
            redundant_owner: v & 0x8000 != 0,
            connection_type: Self::kind(v >> 13),
            priority: ((v >> 10) & 3) as u8,
            variable: v & 0x0200 != 0,
            size: (v & 0x01FF) as u16,
        }
    }
    /// Decodes the 32-bit form (Large_Forward_Open): size in bits 0-15.
    pub const fn from_u32(v: u32) -> Self {
        NetworkParams {
            redundant_owner: v & 0x8000_0000 != 0,
            connection_type: Self::kind(v >> 29),
            priority: ((v >> 26) & 3) as u8,
            variable: v & 0x0200_0000 != 0,
            size: (v & 0xFFFF) as u16,
        }
    }
    const fn type_bits(&self) -> u32 {
        match self.connection_type {
            ConnectionType::Null => 0,
            ConnectionType::Multicast => 1,
            ConnectionType::PointToPoint => 2,
            ConnectionType::Reserved => 3,
        }
    }
    /// Encodes the 16-bit form (size must fit in 9 bits).
    pub fn to_u16(&self) -> Result<u16> {
        if self.size > 0x01FF {
            return Err(Error::Malformed);
        }
        Ok(((self.redundant_owner as u16) << 15)
            | ((self.type_bits() as u16) << 13)
            | (u16::from(self.priority & 3) << 10)
            | ((self.variable as u16) << 9)
            | self.size)
    }
    /// Encodes the 32-bit form.
    pub const fn to_u32(&self) -> u32 {
        ((self.redundant_owner as u32) << 31)
            | (self.type_bits() << 29)
            | ((self.priority as u32 & 3) << 26)
            | ((self.variable as u32) << 25)
            | self.size as u32
    }
}

/// Forward_Open or Large_Forward_Open request data, parsed or to emit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ForwardOpenRepr<'a> {
    /// True for Large_Forward_Open (32-bit network parameters).
    pub large: bool,
    /// Priority/time tick byte.
    pub priority_tick: u8,
    /// Timeout ticks.
    pub timeout_ticks: u8,
    /// O->T connection ID proposed by the originator (the target chooses its own).
    pub o_t_connection_id: u32,
    /// T->O connection ID chosen by the originator (kept for point-to-point).
    pub t_o_connection_id: u32,
    /// The connection triad.
    pub triad: Triad,
    /// Connection timeout multiplier code (0 = x4 ... 7 = x512).
    pub timeout_multiplier: u8,
    /// O->T requested packet interval in microseconds.
    pub o_t_rpi: u32,
    /// O->T network parameters.
    pub o_t_params: NetworkParams,
    /// T->O requested packet interval in microseconds.
    pub t_o_rpi: u32,
    /// T->O network parameters.
    pub t_o_params: NetworkParams,
    /// Transport class and trigger byte.
    pub transport: u8,
    /// Connection path (padded EPATH).
    pub path: &'a [u8],
}

impl<'a> ForwardOpenRepr<'a> {
    /// Parses request data; `large` selects the 32-bit parameter form. The connection path
    /// must fill the data exactly.
    pub fn parse(data: &'a [u8], large: bool) -> Result<ForwardOpenRepr<'a>> {
        let mut r = Reader::new(data);
        let priority_tick = r.u8()?;
        let timeout_ticks = r.u8()?;
        let o_t_connection_id = r.u32()?;
        let t_o_connection_id = r.u32()?;
        let triad = Triad::parse(&mut r)?;
        let timeout_multiplier = r.u8()?;
        r.take(3)?;
        let o_t_rpi = r.u32()?;
        let o_t_params = if large {
            NetworkParams::from_u32(r.u32()?)
        } else {
            NetworkParams::from_u16(r.u16()?)
        };
        let t_o_rpi = r.u32()?;
        let t_o_params = if large {
            NetworkParams::from_u32(r.u32()?)
        } else {
            NetworkParams::from_u16(r.u16()?)
        };
        let transport = r.u8()?;
        let words = usize::from(r.u8()?);
        let path = r.take(words * 2)?;
        if r.remaining() != 0 {
            return Err(Error::Malformed);
        }
        Ok(ForwardOpenRepr {
            large,
            priority_tick,
            timeout_ticks,
            o_t_connection_id,
            t_o_connection_id,
            triad,
            timeout_multiplier,
            o_t_rpi,
            o_t_params,
            t_o_rpi,
            t_o_params,
            transport,
            path,
        })
    }

    /// Bytes the request data takes.
    pub const fn buffer_len(&self) -> usize {
        // Ticks, IDs, triad, multiplier and reserved, RPIs, transport and path size, then
        // both network parameters (16 or 32 bits each).
        let fixed = if self.large {
            2 + 8 + Triad::LEN + 4 + 8 + 2 + 8
        } else {
            2 + 8 + Triad::LEN + 4 + 8 + 2 + 4
        };
        self.path.len().saturating_add(fixed)
    }
    /// Writes the request data.
    pub fn emit(&self, w: &mut Writer<'_>) -> Result<()> {
        if !self.path.len().is_multiple_of(2) {
            return Err(Error::Malformed);
        }
        w.u8(self.priority_tick)?;
        w.u8(self.timeout_ticks)?;
        w.u32(self.o_t_connection_id)?;
        w.u32(self.t_o_connection_id)?;
        self.triad.emit(w)?;
        w.u8(self.timeout_multiplier)?;
        w.zeros(3)?;
        w.u32(self.o_t_rpi)?;
        self.emit_params(w, &self.o_t_params)?;
        w.u32(self.t_o_rpi)?;
        self.emit_params(w, &self.t_o_params)?;
        w.u8(self.transport)?;
        w.u8(u8::try_from(self.path.len() / 2).map_err(|_| Error::Malformed)?)?;
        w.bytes(self.path)
    }

    fn emit_params(&self, w: &mut Writer<'_>, p: &NetworkParams) -> Result<()> {
        if self.large {
            w.u32(p.to_u32())
        } else {
            w.u16(p.to_u16()?)
        }
    }

    /// Transport class (low nibble of the transport byte).
    pub const fn transport_class(&self) -> u8 {
        self.transport & 0x0F
    }
    /// Production trigger (bits 4-6): 0 cyclic, 1 change of state, 2 application.
    pub const fn trigger(&self) -> u8 {
        (self.transport >> 4) & 0x07
    }
}

/// Success reply data of a Forward_Open, parsed or to emit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ForwardOpenReplyRepr<'a> {
    /// O->T connection ID the target chose.
    pub o_t_connection_id: u32,
    /// T->O connection ID in use.
    pub t_o_connection_id: u32,
    /// The triad.
    pub triad: Triad,
    /// Actual O->T packet interval in microseconds.
    pub o_t_api: u32,
    /// Actual T->O packet interval in microseconds.
    pub t_o_api: u32,
    /// Application reply data (whole words).
    pub application_reply: &'a [u8],
}

impl<'a> ForwardOpenReplyRepr<'a> {
    /// Bytes the reply data takes.
    pub const fn buffer_len(&self) -> usize {
        // IDs, triad, APIs, application reply size and reserved byte.
        self.application_reply
            .len()
            .saturating_add(8 + Triad::LEN + 8 + 2)
    }
    /// Writes the reply data.
    pub fn emit(&self, w: &mut Writer<'_>) -> Result<()> {
        w.u32(self.o_t_connection_id)?;
        w.u32(self.t_o_connection_id)?;
        self.triad.emit(w)?;
        w.u32(self.o_t_api)?;
        w.u32(self.t_o_api)?;
        w.u8(u8::try_from(self.application_reply.len() / 2).map_err(|_| Error::Malformed)?)?;
        w.u8(0)?;
        w.bytes(self.application_reply)
    }
    /// Parses reply data.
    pub fn parse(data: &'a [u8]) -> Result<ForwardOpenReplyRepr<'a>> {
        let mut r = Reader::new(data);
        let o_t_connection_id = r.u32()?;
        let t_o_connection_id = r.u32()?;
        let triad = Triad::parse(&mut r)?;
        let o_t_api = r.u32()?;
        let t_o_api = r.u32()?;
        let words = usize::from(r.u8()?);
        r.u8()?;
        let application_reply = r.take(words * 2)?;
        Ok(ForwardOpenReplyRepr {
            o_t_connection_id,
            t_o_connection_id,
            triad,
            o_t_api,
            t_o_api,
            application_reply,
        })
    }
}

/// Failure reply data of Forward_Open and Forward_Close, parsed or to emit: the triad and
/// the remaining path size.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FailureReplyRepr {
    /// The triad of the request.
    pub triad: Triad,
    /// Remaining path size in words (routing; 0 here).
    pub remaining_path_words: u8,
}

impl FailureReplyRepr {
    /// Parses reply data.
    pub fn parse(data: &[u8]) -> Result<FailureReplyRepr> {
        let mut r = Reader::new(data);
        let triad = Triad::parse(&mut r)?;
        let remaining_path_words = r.u8()?;
        r.u8()?;
        if r.remaining() != 0 {
            return Err(Error::Malformed);
        }
        Ok(FailureReplyRepr {
            triad,
            remaining_path_words,
        })
    }
    /// Bytes the reply data takes.
    pub const fn buffer_len(&self) -> usize {
        Triad::LEN + 2
    }
    /// Writes the reply data.
    pub fn emit(&self, w: &mut Writer<'_>) -> Result<()> {
        self.triad.emit(w)?;
        w.u8(self.remaining_path_words)?;
        w.u8(0)
    }
}

/// Forward_Close request data, parsed or to emit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ForwardCloseRepr<'a> {
    /// Priority/time tick byte.
    pub priority_tick: u8,
    /// Timeout ticks.
    pub timeout_ticks: u8,
    /// The triad of the connection to close.
    pub triad: Triad,
    /// Connection path.
    pub path: &'a [u8],
}

impl<'a> ForwardCloseRepr<'a> {
    /// Parses request data.
    pub fn parse(data: &'a [u8]) -> Result<ForwardCloseRepr<'a>> {
        let mut r = Reader::new(data);
        let priority_tick = r.u8()?;
        let timeout_ticks = r.u8()?;
        let triad = Triad::parse(&mut r)?;
        let words = usize::from(r.u8()?);
        r.u8()?;
        let path = r.take(words * 2)?;
        if r.remaining() != 0 {
            return Err(Error::Malformed);
        }
        Ok(ForwardCloseRepr {
            priority_tick,
            timeout_ticks,
            triad,
            path,
        })
    }
    /// Bytes the request data takes.
    pub const fn buffer_len(&self) -> usize {
        // Ticks, triad, path size and reserved byte.
        self.path.len().saturating_add(2 + Triad::LEN + 2)
    }
    /// Writes the request data.
    pub fn emit(&self, w: &mut Writer<'_>) -> Result<()> {
        w.u8(self.priority_tick)?;
        w.u8(self.timeout_ticks)?;
        self.triad.emit(w)?;
        w.u8(u8::try_from(self.path.len() / 2).map_err(|_| Error::Malformed)?)?;
        w.u8(0)?;
        w.bytes(self.path)
    }
}

/// Success reply data of a Forward_Close, parsed or to emit: the triad and the application
/// reply (none from this adapter).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ForwardCloseReplyRepr<'a> {
    /// The triad of the closed connection.
    pub triad: Triad,
    /// Application reply data (whole words).
    pub application_reply: &'a [u8],
}

impl<'a> ForwardCloseReplyRepr<'a> {
    /// Parses reply data.
    pub fn parse(data: &'a [u8]) -> Result<ForwardCloseReplyRepr<'a>> {
        let mut r = Reader::new(data);
        let triad = Triad::parse(&mut r)?;
        let words = usize::from(r.u8()?);
        r.u8()?;
        let application_reply = r.take(words * 2)?;
        if r.remaining() != 0 {
            return Err(Error::Malformed);
        }
        Ok(ForwardCloseReplyRepr {
            triad,
            application_reply,
        })
    }
    /// Bytes the reply data takes.
    pub const fn buffer_len(&self) -> usize {
        self.application_reply.len().saturating_add(Triad::LEN + 2)
    }
    /// Writes the reply data.
    pub fn emit(&self, w: &mut Writer<'_>) -> Result<()> {
        if !self.application_reply.len().is_multiple_of(2) {
            return Err(Error::Malformed);
        }
        self.triad.emit(w)?;
        w.u8(u8::try_from(self.application_reply.len() / 2).map_err(|_| Error::Malformed)?)?;
        w.u8(0)?;
        w.bytes(self.application_reply)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(large: bool) -> ForwardOpenRepr<'static> {
        ForwardOpenRepr {
            large,
            priority_tick: 0x0A,
            timeout_ticks: 0x0E,
            o_t_connection_id: 0,
            t_o_connection_id: 0x1234_5678,
            triad: Triad {
                connection_serial: 7,
                vendor_id: 0x1337,
                originator_serial: 42,
            },
            timeout_multiplier: 2,
            o_t_rpi: 10_000,
            o_t_params: NetworkParams::from_u16(0x4826),
            t_o_rpi: 10_000,
            t_o_params: NetworkParams::from_u16(0x2822),
            transport: 0x01,
            path: &[0x20, 0x04, 0x24, 0x97, 0x2C, 0x96, 0x2C, 0x64],
        }
    }

    #[test]
    fn network_params_decode() {
        let p = NetworkParams::from_u16(0x4826);
        assert_eq!(p.connection_type, ConnectionType::PointToPoint);
        assert_eq!(p.priority, 2);
        assert!(!p.variable);
        assert_eq!(p.size, 0x26);
        assert_eq!(p.to_u16(), Ok(0x4826));
        assert_eq!(
            NetworkParams::from_u16(0x2822).connection_type,
            ConnectionType::Multicast
        );
        let l = NetworkParams::from_u32(0x4800_0190);
        assert_eq!(
            (l.connection_type, l.size),
            (ConnectionType::PointToPoint, 400)
        );
        assert_eq!(l.to_u32(), 0x4800_0190);
    }

    #[test]
    fn round_trips_both_forms() {
        for large in [false, true] {
            let fo = sample(large);
            let mut buf = [0u8; 64];
            let mut w = Writer::new(&mut buf);
            fo.emit(&mut w).unwrap();
            let n = w.len();
            assert_eq!(n, if large { 36 + 8 + 4 } else { 32 + 8 + 4 });
            assert_eq!(n, fo.buffer_len());
            assert_eq!(ForwardOpenRepr::parse(&buf[..n], large), Ok(fo));
            assert!(ForwardOpenRepr::parse(&buf[..n - 1], large).is_err());
            assert!(ForwardOpenRepr::parse(&buf[..n - 9], large).is_err());
        }
    }

    #[test]
    fn forward_close_round_trip() {
        let fc = ForwardCloseRepr {
            priority_tick: 1,
            timeout_ticks: 2,
            triad: sample(false).triad,
            path: &[0x20, 4],
        };
        let mut buf = [0u8; 32];
        let mut w = Writer::new(&mut buf);
        fc.emit(&mut w).unwrap();
        let n = w.len();
        assert_eq!(n, fc.buffer_len());
        assert_eq!(ForwardCloseRepr::parse(&buf[..n]), Ok(fc));
    }

    #[test]
    fn replies_round_trip() {
        let triad = sample(false).triad;
        let mut buf = [0u8; 64];

        let open = ForwardOpenReplyRepr {
            o_t_connection_id: 1,
            t_o_connection_id: 2,
            triad,
            o_t_api: 10_000,
            t_o_api: 20_000,
            application_reply: &[1, 2],
        };
        let mut w = Writer::new(&mut buf);
        open.emit(&mut w).unwrap();
        let n = w.len();
        assert_eq!(n, open.buffer_len());
        assert_eq!(ForwardOpenReplyRepr::parse(&buf[..n]), Ok(open));

        let failure = FailureReplyRepr {
            triad,
            remaining_path_words: 0,
        };
        let mut w = Writer::new(&mut buf);
        failure.emit(&mut w).unwrap();
        let n = w.len();
        assert_eq!(n, failure.buffer_len());
        assert_eq!(FailureReplyRepr::parse(&buf[..n]), Ok(failure));

        let close = ForwardCloseReplyRepr {
            triad,
            application_reply: &[],
        };
        let mut w = Writer::new(&mut buf);
        close.emit(&mut w).unwrap();
        let n = w.len();
        assert_eq!(n, close.buffer_len());
        assert_eq!(&buf[..n], &[7, 0, 0x37, 0x13, 42, 0, 0, 0, 0, 0]);
        assert_eq!(ForwardCloseReplyRepr::parse(&buf[..n]), Ok(close));
    }
}
