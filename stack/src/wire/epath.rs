//! EPATH segments in padded form: logical (8/16/32-bit), port, electronic key, network,
//! ANSI extended symbolic and simple data segments.

use super::{Error, Reader, Result, Writer};

/// What a logical segment addresses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LogicalType {
    /// Class ID.
    Class,
    /// Instance ID.
    Instance,
    /// Member ID.
    Member,
    /// Connection point.
    ConnectionPoint,
    /// Attribute ID.
    Attribute,
    /// Service ID.
    ServiceId,
}

impl LogicalType {
    /// The first byte of its 8-bit logical segment (also the head its 16- and 32-bit forms
    /// add their format to).
    pub(crate) const fn segment8(self) -> u8 {
        0x20 | (self.code() << 2)
    }

    const fn code(self) -> u8 {
        match self {
            LogicalType::Class => 0,
            LogicalType::Instance => 1,
            LogicalType::Member => 2,
            LogicalType::ConnectionPoint => 3,
            LogicalType::Attribute => 4,
            LogicalType::ServiceId => 6,
        }
    }
    const fn from_code(c: u8) -> Option<Self> {
        match c {
            0 => Some(LogicalType::Class),
            1 => Some(LogicalType::Instance),
            2 => Some(LogicalType::Member),
            3 => Some(LogicalType::ConnectionPoint),
            4 => Some(LogicalType::Attribute),
            6 => Some(LogicalType::ServiceId),
            _ => None,
        }
    }
}

/// An electronic key (logical segment 0x34, key format 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ElectronicKey {
    /// Vendor ID (0 = any).
    pub vendor_id: u16,
    /// Device type (0 = any).
    pub device_type: u16,
    /// Product code (0 = any).
    pub product_code: u16,
    /// Major revision (0 = any); bit 7 of the wire byte is the compatibility flag.
    pub major_revision: u8,
    /// Compatibility flag.
    pub compatibility: bool,
    /// Minor revision (0 = any).
    pub minor_revision: u8,
}

/// One EPATH segment, parsed or to emit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SegmentRepr<'a> {
    /// A logical segment with its value.
    Logical(LogicalType, u32),
    /// An electronic key.
    ElectronicKey(ElectronicKey),
    /// A port segment: port number and link address.
    Port {
        /// Port number.
        port: u16,
        /// Link address bytes.
        link: &'a [u8],
    },
    /// A network segment (subtype byte and its data), e.g. 0x43 production inhibit time.
    Network {
        /// Segment byte (0x41..=0x5F).
        kind: u8,
        /// Its data.
        data: &'a [u8],
    },
    /// An ANSI extended symbolic segment (0x91).
    Symbolic(&'a [u8]),
    /// A simple data segment (0x80); its data is a whole number of 16-bit words.
    Data(&'a [u8]),
}

/// Segment byte of an electronic key.
const KEY_SEGMENT: u8 = 0x34;
/// Electronic key format 4.
const KEY_FORMAT: u8 = 4;
/// Simple data segment byte.
const DATA_SEGMENT: u8 = 0x80;
/// ANSI extended symbolic segment byte.
const SYMBOLIC_SEGMENT: u8 = 0x91;
/// Network segment: production inhibit time in milliseconds.
pub const NETWORK_PRODUCTION_INHIBIT_MS: u8 = 0x43;

impl<'a> SegmentRepr<'a> {
    /// Parses one segment from the front of `r`.
    pub fn parse(r: &mut Reader<'a>) -> Result<SegmentRepr<'a>> {
        let b = r.u8()?;
        match b >> 5 {
            0 => Self::parse_port(b, r),
            1 => Self::parse_logical(b, r),
            2 => Self::parse_network(b, r),
            4 => match b {
                DATA_SEGMENT => {
                    let words = usize::from(r.u8()?);
                    Ok(SegmentRepr::Data(r.take(words * 2)?))
                }
                SYMBOLIC_SEGMENT => {
                    let n = usize::from(r.u8()?);
                    let s = r.take(n)?;
                    if n % 2 == 1 {
                        r.u8()?;
                    }
                    if s.is_empty() {
                        return Err(Error::Malformed);
                    }
                    Ok(SegmentRepr::Symbolic(s))
                }
                _ => Err(Error::Malformed),
            },
            _ => Err(Error::Malformed),
        }
    }

    fn parse_port(b: u8, r: &mut Reader<'a>) -> Result<SegmentRepr<'a>> {
        let extended_link = b & 0x10 != 0;
        let link_len = if extended_link {
            usize::from(r.u8()?)
        } else {
            1
        };
        let port = match b & 0x0F {
            0 => return Err(Error::Malformed),
            0x0F => match r.u16()? {
                0 => return Err(Error::Malformed),
                p => p,
            },
            p => u16::from(p),
        };
        let link = r.take(link_len)?;
        // Padded to an even length: the segment byte, the link size byte if any, the 16-bit
        // port if any (even) and the link address.
        if (1 ^ usize::from(extended_link) ^ link_len) & 1 == 1 {
            r.u8()?;
        }
        Ok(SegmentRepr::Port { port, link })
    }

    fn parse_logical(b: u8, r: &mut Reader<'a>) -> Result<SegmentRepr<'a>> {
        if b == KEY_SEGMENT {
            if r.u8()? != KEY_FORMAT {
                return Err(Error::Malformed);
            }
            let vendor_id = r.u16()?;
            let device_type = r.u16()?;
            let product_code = r.u16()?;
            let major = r.u8()?;
            let minor_revision = r.u8()?;
            return Ok(SegmentRepr::ElectronicKey(ElectronicKey {
                vendor_id,
                device_type,
                product_code,
                major_revision: major & 0x7F,
                compatibility: major & 0x80 != 0,
                minor_revision,
            }));
        }
        let kind = LogicalType::from_code((b >> 2) & 0x07).ok_or(Error::Malformed)?;
        let value = match b & 0x03 {
            0 => u32::from(r.u8()?),
            1 => {
                r.u8()?;
                u32::from(r.u16()?)
            }
            2 => {
                r.u8()?;
                r.u32()?
            }
            _ => return Err(Error::Malformed),
        };
        Ok(SegmentRepr::Logical(kind, value))
    }

    fn parse_network(b: u8, r: &mut Reader<'a>) -> Result<SegmentRepr<'a>> {
        let data = match b {
            0x41..=0x43 => r.take(1)?,
            0x50 | 0x51 => {
                let words = usize::from(r.u8()?);
                r.take(words * 2)?
            }
            _ => return Err(Error::Malformed),
        };
        Ok(SegmentRepr::Network { kind: b, data })
    }

    /// Bytes the segment takes in padded form.
    pub fn buffer_len(&self) -> usize {
        match *self {
            SegmentRepr::Logical(_, v) if v <= 0xFF => 2,
            SegmentRepr::Logical(_, v) if v <= 0xFFFF => 4,
            SegmentRepr::Logical(..) => 6,
            SegmentRepr::ElectronicKey(_) => 10,
            SegmentRepr::Port { port, link } => {
                let size_byte = usize::from(link.len() != 1);
                let port_word = if port >= 0x0F { 2 } else { 0 };
                let n = link
                    .len()
                    .saturating_add(1)
                    .saturating_add(size_byte)
                    .saturating_add(port_word);
                n.saturating_add(n % 2)
            }
            SegmentRepr::Network { kind, data } => match kind {
                0x50 | 0x51 => data.len().saturating_add(2),
                _ => data.len().saturating_add(1),
            },
            SegmentRepr::Symbolic(s) => s.len().saturating_add(2).saturating_add(s.len() % 2),
            SegmentRepr::Data(d) => d.len().saturating_add(2),
        }
    }

    /// Writes the segment in padded form.
    pub fn emit(&self, w: &mut Writer<'_>) -> Result<()> {
        match *self {
            SegmentRepr::Logical(kind, v) => {
                let head = kind.segment8();
                if let Ok(v8) = u8::try_from(v) {
                    w.bytes(&[head, v8])
                } else if let Ok(v16) = u16::try_from(v) {
                    w.bytes(&[head | 1, 0])?;
                    w.u16(v16)
                } else {
                    w.bytes(&[head | 2, 0])?;
                    w.u32(v)
                }
            }
            SegmentRepr::ElectronicKey(k) => {
                w.bytes(&[KEY_SEGMENT, KEY_FORMAT])?;
                w.u16(k.vendor_id)?;
                w.u16(k.device_type)?;
                w.u16(k.product_code)?;
                w.u8(k.major_revision | if k.compatibility { 0x80 } else { 0 })?;
                w.u8(k.minor_revision)
            }
            SegmentRepr::Port { port, link } => {
                let start = w.len();
                let ext = link.len() != 1;
                let id = if port >= 0x0F { 0x0F } else { port as u8 };
                w.u8(id | if ext { 0x10 } else { 0 })?;
                if ext {
                    w.u8(u8::try_from(link.len()).map_err(|_| Error::Malformed)?)?;
                }
                if port >= 0x0F {
                    w.u16(port)?;
                }
                w.bytes(link)?;
                if w.len().saturating_sub(start) % 2 == 1 {
                    w.u8(0)?;
                }
                Ok(())
            }
            SegmentRepr::Network { kind, data } => {
                w.u8(kind)?;
                if matches!(kind, 0x50 | 0x51) {
                    w.u8(u8::try_from(data.len() / 2).map_err(|_| Error::Malformed)?)?;
                }
                w.bytes(data)
            }
            SegmentRepr::Symbolic(s) => {
                w.u8(SYMBOLIC_SEGMENT)?;
                w.u8(u8::try_from(s.len()).map_err(|_| Error::Malformed)?)?;
                w.bytes(s)?;
                if s.len() % 2 == 1 {
                    w.u8(0)?;
                }
                Ok(())
            }
            SegmentRepr::Data(d) => {
                if d.len() % 2 == 1 {
                    return Err(Error::Malformed);
                }
                w.u8(DATA_SEGMENT)?;
                w.u8(u8::try_from(d.len() / 2).map_err(|_| Error::Malformed)?)?;
                w.bytes(d)
            }
        }
    }
}

/// Iterator over the segments of an EPATH; yields one error and then stops.
#[derive(Debug, Clone)]
pub struct Segments<'a> {
    r: Reader<'a>,
    failed: bool,
}

impl<'a> Segments<'a> {
    /// Segments of `path` (already cut to the path size the message declared).
    pub const fn new(path: &'a [u8]) -> Self {
        Segments {
            r: Reader::new(path),
            failed: false,
        }
    }
    /// Takes the next segment if it is an 8-bit logical segment (class, instance, attribute,
    /// member, connection point, service ID): the common case, decoded without building a
    /// [`SegmentRepr`]. Anything else is left for [`Iterator::next`].
    #[inline]
    pub fn next_logical8(&mut self) -> Option<(LogicalType, u32)> {
        let [b, v] = *self.r.rest().first_chunk::<2>()?;
        if b & 0xE3 != 0x20 || b == KEY_SEGMENT {
            return None;
        }
        let kind = LogicalType::from_code((b >> 2) & 0x07)?;
        self.r.take(2).ok()?;
        Some((kind, u32::from(v)))
    }
}

impl<'a> Iterator for Segments<'a> {
    type Item = Result<SegmentRepr<'a>>;
    fn next(&mut self) -> Option<Self::Item> {
        if self.failed || self.r.remaining() == 0 {
            return None;
        }
        let s = SegmentRepr::parse(&mut self.r);
        self.failed = s.is_err();
        Some(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trip(s: SegmentRepr<'_>, wire: &[u8]) {
        let mut buf = [0u8; 32];
        let mut w = Writer::new(&mut buf);
        s.emit(&mut w).unwrap();
        assert_eq!(w.written(), wire);
        assert_eq!(s.buffer_len(), wire.len());
        let mut r = Reader::new(wire);
        assert_eq!(SegmentRepr::parse(&mut r), Ok(s));
        assert_eq!(r.remaining(), 0);
    }

    #[test]
    fn the_logical8_fast_path_agrees_with_the_decoder() {
        let mut taken = 0;
        for b in 0..=255u8 {
            for v in [0u8, 1, 0x7F, 0xFF] {
                let raw = [b, v, 0, 0, 0, 0, 0, 0, 0, 0];
                let general = SegmentRepr::parse(&mut Reader::new(&raw));
                let mut fast = Segments::new(&raw);
                match fast.next_logical8() {
                    Some((kind, value)) => {
                        taken += 1;
                        assert_eq!(general, Ok(SegmentRepr::Logical(kind, value)), "{b:#04x}");
                        assert_eq!(fast.r.remaining(), raw.len() - 2);
                    }
                    None => {
                        assert_eq!(fast.r.remaining(), raw.len(), "nothing consumed");
                        let is_logical8 =
                            matches!(general, Ok(SegmentRepr::Logical(..))) && b & 0x03 == 0;
                        assert!(!is_logical8, "{b:#04x} left to the general decoder");
                    }
                }
            }
        }
        // Six logical types, one 8-bit format each.
        assert_eq!(taken, 6 * 4);
    }

    #[test]
    fn logical_widths() {
        round_trip(SegmentRepr::Logical(LogicalType::Class, 1), &[0x20, 1]);
        round_trip(
            SegmentRepr::Logical(LogicalType::Instance, 0x1234),
            &[0x25, 0, 0x34, 0x12],
        );
        round_trip(
            SegmentRepr::Logical(LogicalType::ConnectionPoint, 0x10000),
            &[0x2E, 0, 0, 0, 1, 0],
        );
        round_trip(SegmentRepr::Logical(LogicalType::Attribute, 7), &[0x30, 7]);
        round_trip(SegmentRepr::Logical(LogicalType::Member, 2), &[0x28, 2]);
    }

    #[test]
    fn other_segments() {
        round_trip(
            SegmentRepr::Port {
                port: 1,
                link: &[0],
            },
            &[0x01, 0],
        );
        round_trip(
            SegmentRepr::Port {
                port: 2,
                link: &[10, 0, 0, 1],
            },
            &[0x12, 4, 10, 0, 0, 1],
        );
        round_trip(
            SegmentRepr::Port {
                port: 2,
                link: b"1.2.3",
            },
            &[0x12, 5, b'1', b'.', b'2', b'.', b'3', 0],
        );
        round_trip(
            SegmentRepr::Port {
                port: 20,
                link: &[3],
            },
            &[0x0F, 20, 0, 3],
        );
        round_trip(
            SegmentRepr::Symbolic(b"P4012"),
            &[0x91, 5, b'P', b'4', b'0', b'1', b'2', 0],
        );
        round_trip(SegmentRepr::Data(&[1, 2, 3, 4]), &[0x80, 2, 1, 2, 3, 4]);
        round_trip(
            SegmentRepr::Network {
                kind: 0x43,
                data: &[10],
            },
            &[0x43, 10],
        );
        round_trip(
            SegmentRepr::ElectronicKey(ElectronicKey {
                vendor_id: 1,
                device_type: 12,
                product_code: 3,
                major_revision: 2,
                compatibility: true,
                minor_revision: 1,
            }),
            &[0x34, 4, 1, 0, 12, 0, 3, 0, 0x82, 1],
        );
    }

    #[test]
    fn rejects_odd_paths() {
        for bad in [
            &[0x23u8, 1][..],
            &[0x20],
            &[0x21, 0, 1],
            &[0x34, 5, 0, 0],
            &[0x00, 0],
            &[0x91, 0],
            &[0xFF, 0],
            &[0x80, 3, 0],
        ] {
            assert!(Segments::new(bad).any(|s| s.is_err()), "{bad:02x?}");
        }
    }
}
