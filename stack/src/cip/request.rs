//! A Message Router request as objects see it: service, decoded request path, data.

use super::status::{CipError, CipResult, General};
use crate::wire::epath::{ElectronicKey, LogicalType, SegmentRepr, Segments};
use crate::wire::message_router::{RequestPacket, RequestRepr};

/// The addressing parts of a request path.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Path<'a> {
    /// The electronic key the path starts with, if any: the Message Router checks it
    /// against the Identity object before the request runs.
    pub key: Option<ElectronicKey>,
    /// Class ID.
    pub class: Option<u32>,
    /// Instance ID.
    pub instance: Option<u32>,
    /// Attribute ID.
    pub attribute: Option<u32>,
    /// Member ID.
    pub member: Option<u32>,
    /// Connection point (treated as an instance by the Assembly object).
    pub connection_point: Option<u32>,
    /// ANSI extended symbolic name (vendor tag services).
    pub symbol: Option<&'a [u8]>,
}

impl<'a> Path<'a> {
    /// Decodes a padded request path; anything but an electronic key as the first segment
    /// and logical and symbolic segments after it, a repeated segment, or a path with
    /// neither class nor symbol is a path segment error (0x04).
    #[inline]
    pub fn parse(raw: &'a [u8]) -> CipResult<Path<'a>> {
        let mut p = Path::default();
        p.decode(raw)?;
        Ok(p)
    }

    /// [`Self::parse`] into this (default) path, where it lies: a request's path is decoded
    /// in place rather than moved into it.
    #[inline]
    fn decode(&mut self, raw: &'a [u8]) -> CipResult {
        let p = self;
        // Most paths are 8-bit class, instance, attribute (member, connection point)
        // segments only: those are read straight from the bytes.
        let mut rest = raw;
        while let [b, v, ref tail @ ..] = *rest {
            let slot = match b {
                CLASS8 => &mut p.class,
                INSTANCE8 => &mut p.instance,
                MEMBER8 => &mut p.member,
                POINT8 => &mut p.connection_point,
                ATTRIBUTE8 => &mut p.attribute,
                _ => break,
            };
            set_once(slot, u32::from(v))?;
            rest = tail;
        }
        let mut first = rest.len() == raw.len();
        let mut segments = Segments::new(rest);
        loop {
            // 8-bit logical segments after a key skip the general decoder too.
            let seg = match segments.next_logical8() {
                Some((kind, v)) => SegmentRepr::Logical(kind, v),
                None => match segments.next() {
                    Some(seg) => seg.map_err(|_| CipError::new(General::PathSegmentError))?,
                    None => break,
                },
            };
            match seg {
                SegmentRepr::Logical(kind, v) => {
                    let slot = match kind {
                        LogicalType::Class => &mut p.class,
                        LogicalType::Instance => &mut p.instance,
                        LogicalType::Attribute => &mut p.attribute,
                        LogicalType::Member => &mut p.member,
                        LogicalType::ConnectionPoint => &mut p.connection_point,
                        LogicalType::ServiceId => {
                            return Err(CipError::new(General::PathSegmentError))
                        }
                    };
                    set_once(slot, v)?;
                }
                SegmentRepr::ElectronicKey(k) if first => p.key = Some(k),
                SegmentRepr::Symbolic(s) if p.symbol.is_none() && p.class.is_none() => {
                    p.symbol = Some(s);
                }
                _ => return Err(CipError::new(General::PathSegmentError)),
            }
            first = false;
        }
        if p.class.is_none() && p.symbol.is_none() {
            return Err(CipError::new(General::PathSegmentError));
        }
        Ok(())
    }

    /// The instance, or the connection point when only that was given.
    pub fn instance_or_point(&self) -> Option<u32> {
        self.instance.or(self.connection_point)
    }
}

/// The first bytes of the 8-bit logical segments [`Path::parse`] reads directly.
const CLASS8: u8 = LogicalType::Class.segment8();
const INSTANCE8: u8 = LogicalType::Instance.segment8();
const MEMBER8: u8 = LogicalType::Member.segment8();
const POINT8: u8 = LogicalType::ConnectionPoint.segment8();
const ATTRIBUTE8: u8 = LogicalType::Attribute.segment8();

fn set_once(slot: &mut Option<u32>, v: u32) -> CipResult {
    if slot.is_some() {
        return Err(CipError::new(General::PathSegmentError));
    }
    *slot = Some(v);
    Ok(())
}

/// A decoded Message Router request.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Request<'a> {
    /// Service code.
    pub service: u8,
    /// Decoded request path.
    pub path: Path<'a>,
    /// The raw request path bytes.
    pub raw_path: &'a [u8],
    /// Request data.
    pub data: &'a [u8],
}

impl<'a> Request<'a> {
    /// Frames a request: Err carries the service code (if any) and the status to answer with:
    /// no path size byte is not enough data (0x13), a path size beyond the request path size
    /// invalid (0x26), a segment that cannot be decoded a path segment error (0x04).
    pub fn parse(buf: &'a [u8]) -> Result<Request<'a>, (u8, CipError)> {
        let mut request = Request::default();
        request.parse_from(buf)?;
        Ok(request)
    }

    /// [`Self::parse`] into this (default) request, where it lies: the Message Router's
    /// request is decoded in place rather than moved out of a result.
    pub(crate) fn parse_from(&mut self, buf: &'a [u8]) -> Result<(), (u8, CipError)> {
        let service = buf.first().copied().unwrap_or(0);
        let packet = RequestPacket::new_checked(buf).map_err(|_| {
            let general = if buf.len() < 2 {
                General::NotEnoughData
            } else {
                General::PathSizeInvalid
            };
            (service, CipError::new(general))
        })?;
        let repr = RequestRepr::parse(&packet);
        self.service = repr.service;
        self.raw_path = repr.path;
        self.data = repr.data;
        self.path.decode(repr.path).map_err(|e| (service, e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decodes_class_instance_attribute() {
        let r = Request::parse(&[0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x07]).unwrap();
        assert_eq!(r.path.class, Some(1));
        assert_eq!(r.path.instance, Some(1));
        assert_eq!(r.path.attribute, Some(7));
    }

    #[test]
    fn symbolic_path() {
        let r = Request::parse(&[0x4C, 4, 0x91, 5, b'P', b'4', b'0', b'1', b'2', 0, 1, 0]).unwrap();
        assert_eq!(r.path.symbol, Some(&b"P4012"[..]));
        assert_eq!(r.data, &[1, 0]);
    }

    /// Key format 4 for vendor 1, device type 12, product 65001, revision 1.2.
    const KEY: [u8; 10] = [0x34, 4, 1, 0, 12, 0, 0xE9, 0xFD, 1, 2];

    #[test]
    fn a_key_first_in_the_path_is_kept_for_the_router() {
        let raw = [&[0x0E, 8][..], &KEY, &[0x20, 0x01, 0x24, 0x01, 0x30, 0x07]].concat();
        let r = Request::parse(&raw).unwrap();
        let key = r.path.key.unwrap();
        assert_eq!(
            (key.vendor_id, key.device_type, key.product_code),
            (1, 12, 65001)
        );
        assert_eq!((key.major_revision, key.minor_revision), (1, 2));
        assert!(!key.compatibility);
        assert_eq!(
            (r.path.class, r.path.instance, r.path.attribute),
            (Some(1), Some(1), Some(7))
        );
        // The compatibility flag is bit 7 of the major revision byte.
        let mut compatible = raw.clone();
        compatible[10] |= 0x80;
        let key = Request::parse(&compatible).unwrap().path.key.unwrap();
        assert!(key.compatibility);
        assert_eq!(key.major_revision, 1);
        // Before a symbolic segment too.
        let raw = [
            &[0x4C, 9][..],
            &KEY,
            &[0x91, 5, b'P', b'4', b'0', b'1', b'2', 0],
        ]
        .concat();
        let r = Request::parse(&raw).unwrap();
        assert!(r.path.key.is_some());
        assert_eq!(r.path.symbol, Some(&b"P4012"[..]));
    }

    #[test]
    fn a_key_anywhere_but_first_is_a_path_segment_error() {
        let e = |b: &[u8]| Request::parse(b).unwrap_err().1.general as u8;
        let after_class = [
            &[0x0E, 8][..],
            &[0x20, 0x01],
            &KEY,
            &[0x24, 0x01, 0x30, 0x07],
        ]
        .concat();
        assert_eq!(e(&after_class), 0x04);
        let twice = [&[0x0E, 12][..], &KEY, &KEY, &[0x20, 0x01, 0x24, 0x01]].concat();
        assert_eq!(e(&twice), 0x04);
        // A key alone addresses nothing.
        assert_eq!(e(&[&[0x0E, 5][..], &KEY].concat()), 0x04);
        // Key formats other than 4 are not decoded.
        let mut format5 = [&[0x0E, 8][..], &KEY, &[0x20, 0x01, 0x24, 0x01, 0x30, 0x07]].concat();
        format5[3] = 5;
        assert_eq!(e(&format5), 0x04);
    }

    #[test]
    fn path_errors() {
        let e = |b: &[u8]| Request::parse(b).unwrap_err().1.general as u8;
        assert_eq!(e(&[0x0E, 2, 0x20, 1, 0x20, 2]), 0x04); // class twice
        assert_eq!(e(&[0x0E, 1, 0x24, 1]), 0x04); // no class
        assert_eq!(e(&[0x0E, 2, 0x20, 1, 0x01, 0]), 0x04); // port segment
        assert_eq!(e(&[0x0E, 5, 0x20, 1]), 0x26); // path longer than message
        assert_eq!(e(&[0x0E]), 0x13);
    }

    #[test]
    fn eight_bit_segments_then_wider_ones_decode_as_one_path() {
        // 8-bit class, 16-bit instance, 8-bit attribute, 8-bit member.
        let raw = [0x0E, 5, 0x20, 0x04, 0x25, 0, 0x34, 0x12, 0x30, 3, 0x28, 9];
        let p = Request::parse(&raw).unwrap().path;
        assert_eq!(p.class, Some(4));
        assert_eq!(p.instance, Some(0x1234));
        assert_eq!(p.attribute, Some(3));
        assert_eq!(p.member, Some(9));
        assert_eq!(
            Request::parse(&[0x0E, 2, 0x20, 4, 0x2C, 0x65])
                .unwrap()
                .path
                .connection_point,
            Some(0x65)
        );
        let e = |b: &[u8]| Request::parse(b).unwrap_err().1.general as u8;
        // The same segment in two widths, a service ID segment, a symbol after a class.
        assert_eq!(e(&[0x0E, 3, 0x20, 4, 0x21, 0, 4, 0]), 0x04);
        assert_eq!(e(&[0x0E, 2, 0x20, 4, 0x38, 1]), 0x04);
        assert_eq!(e(&[0x0E, 3, 0x20, 4, 0x91, 1, b'A', 0]), 0x04);
    }
}
