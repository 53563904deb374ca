//! The attribute services every object shares: Get/Set_Attribute_Single, Get/Set_Attribute_List
//! and Get_Attributes_All, written once over a small per-object trait.

use super::service;
use super::status::{CipError, CipResult, General};
use crate::config::MAX_MULTIPLE_SERVICES;
use crate::wire::{Reader, Writer};

/// Attribute access for one object instance (or the class, instance 0).
pub(crate) trait Attributes {
    /// Writes attribute `id`; `AttributeNotSupported` if it does not exist.
    fn get(&mut self, id: u16, w: &mut Writer<'_>) -> CipResult;
    /// Sets attribute `id` from the front of `data` and returns the bytes used. With `exact`
    /// (Set_Attribute_Single) any byte left over is `TooMuchData`.
    fn set(&mut self, id: u16, data: &[u8], exact: bool) -> CipResult<usize>;
    /// Attributes returned by Get_Attributes_All, in order; empty if the service is unsupported.
    fn all(&self) -> &'static [u16];
}

/// Takes the `n` bytes an attribute needs from `data`: `NotEnoughData` if short, and with
/// `exact`, `TooMuchData` if longer.
pub(crate) fn take(data: &[u8], n: usize, exact: bool) -> CipResult<&[u8]> {
    match data.get(..n) {
        None => Err(General::NotEnoughData.into()),
        Some(_) if exact && data.len() > n => Err(General::TooMuchData.into()),
        Some(v) => Ok(v),
    }
}

/// Error for a Set of an attribute that exists but is read-only.
pub(crate) const fn read_only() -> CipError {
    CipError::new(General::AttributeNotSettable)
}

/// Error for a Set on an object whose attributes `1..=last` are all read-only.
pub(crate) fn read_only_up_to(id: u16, last: u16) -> CipError {
    if (1..=last).contains(&id) {
        read_only()
    } else {
        unsupported()
    }
}

/// Error for an attribute that does not exist.
pub(crate) const fn unsupported() -> CipError {
    CipError::new(General::AttributeNotSupported)
}

/// Runs one of the shared attribute services on `obj`, or `None` if `svc` is not one of them.
pub(crate) fn handle(
    obj: &mut impl Attributes,
    svc: u8,
    attribute: Option<u32>,
    data: &[u8],
    w: &mut Writer<'_>,
) -> Option<CipResult> {
    Some(match svc {
        service::GET_ATTRIBUTE_SINGLE => {
            attribute_id(attribute).and_then(|id| no_data(data).and_then(|_| obj.get(id, w)))
        }
        service::SET_ATTRIBUTE_SINGLE => {
            attribute_id(attribute).and_then(|id| obj.set(id, data, true).map(|_| ()))
        }
        service::GET_ATTRIBUTES_ALL if !obj.all().is_empty() => get_all(obj, w),
        service::GET_ATTRIBUTE_LIST => get_list(obj, data, w),
        service::SET_ATTRIBUTE_LIST => set_list(obj, data, w),
        _ => return None,
    })
}

fn attribute_id(attribute: Option<u32>) -> CipResult<u16> {
    match attribute {
        None => Err(General::PathDestinationUnknown.into()),
        Some(a) => u16::try_from(a).map_err(|_| unsupported()),
    }
}

fn no_data(data: &[u8]) -> CipResult {
    if data.is_empty() {
        Ok(())
    } else {
        Err(General::TooMuchData.into())
    }
}

fn get_all(obj: &mut impl Attributes, w: &mut Writer<'_>) -> CipResult {
    for &id in obj.all() {
        obj.get(id, w)?;
    }
    Ok(())
}

fn list_count(r: &mut Reader<'_>) -> CipResult<u16> {
    let count = r.u16()?;
    if usize::from(count) > MAX_MULTIPLE_SERVICES {
        return Err(General::ResourceUnavailable.into());
    }
    Ok(count)
}

/// Get_Attribute_List: count, then per attribute its id, status and (on success) value.
fn get_list(obj: &mut impl Attributes, data: &[u8], w: &mut Writer<'_>) -> CipResult {
    let mut r = Reader::new(data);
    let count = list_count(&mut r)?;
    if r.remaining() != usize::from(count) * 2 {
        return Err(if r.remaining() < usize::from(count) * 2 {
            General::NotEnoughData
        } else {
            General::TooMuchData
        }
        .into());
    }
    w.u16(count)?;
    let mut failed = false;
    for _ in 0..count {
        let id = r.u16()?;
        w.u16(id)?;
        let status_at = w.len();
        w.u16(0)?;
        let value_at = w.len();
        if let Err(e) = obj.get(id, w) {
            if e.general == General::ReplyDataTooLarge as u8 {
                return Err(e);
            }
            w.truncate(value_at);
            w.patch_u16(status_at, u16::from(e.general));
            failed = true;
        }
    }
    if failed {
        return Err(CipError::new(General::AttributeListError).keeping_data());
    }
    Ok(())
}

/// Set_Attribute_List: count, then per attribute its id and value; replies id and status each.
/// An attribute whose value length cannot be known (unsupported) ends the list there.
fn set_list(obj: &mut impl Attributes, data: &[u8], w: &mut Writer<'_>) -> CipResult {
    let mut r = Reader::new(data);
    let count = list_count(&mut r)?;
    let count_at = w.len();
    w.u16(count)?;
    let mut failed = false;
    for done in 0..count {
        let id = r.u16()?;
        w.u16(id)?;
        match obj.set(id, r.rest(), false) {
            Ok(used) => {
                r.take(used)?;
                w.u16(0)?;
            }
            Err(e) => {
                w.u16(u16::from(e.general))?;
                failed = true;
                if e.general == General::AttributeNotSupported as u8
                    || e.general == General::NotEnoughData as u8
                {
                    w.patch_u16(count_at, done + 1);
                    break;
                }
                // A read-only or invalid value of known size: skip it by reading it.
                let mut scratch = [0u8; 64];
                let mut sw = Writer::new(&mut scratch);
                let skip = obj.get(id, &mut sw).map(|_| sw.len()).unwrap_or(0);
                if r.take(skip).is_err() {
                    w.patch_u16(count_at, done + 1);
                    break;
                }
            }
        }
    }
    if failed {
        return Err(CipError::new(General::AttributeListError).keeping_data());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Two {
        a: u16,
    }
    impl Attributes for Two {
        fn get(&mut self, id: u16, w: &mut Writer<'_>) -> CipResult {
            match id {
                1 => w.u16(self.a).map_err(Into::into),
                2 => w.u8(9).map_err(Into::into),
                _ => Err(unsupported()),
            }
        }
        fn set(&mut self, id: u16, data: &[u8], exact: bool) -> CipResult<usize> {
            match id {
                1 => {
                    let v = take(data, 2, exact)?;
                    self.a = u16::from_le_bytes([v[0], v[1]]);
                    Ok(2)
                }
                2 => Err(read_only()),
                _ => Err(unsupported()),
            }
        }
        fn all(&self) -> &'static [u16] {
            &[1, 2]
        }
    }

    fn run(svc: u8, attr: Option<u32>, data: &[u8]) -> (CipResult, heapless::Vec<u8, 64>) {
        let mut o = Two { a: 5 };
        let mut buf = [0u8; 64];
        let mut w = Writer::new(&mut buf);
        let r = handle(&mut o, svc, attr, data, &mut w).unwrap();
        (r, heapless::Vec::from_slice(w.written()).unwrap())
    }

    #[test]
    fn single_services() {
        assert_eq!(run(0x0E, Some(1), &[]).1, [5, 0]);
        assert_eq!(run(0x0E, Some(3), &[]).0.unwrap_err().general, 0x14);
        assert_eq!(run(0x10, Some(1), &[1]).0.unwrap_err().general, 0x13);
        assert_eq!(run(0x10, Some(1), &[1, 2, 3]).0.unwrap_err().general, 0x15);
        assert_eq!(run(0x10, Some(2), &[1]).0.unwrap_err().general, 0x0E);
        assert!(run(0x10, Some(1), &[1, 2]).0.is_ok());
        assert_eq!(run(0x01, None, &[]).1, [5, 0, 9]);
    }

    #[test]
    fn get_list_reports_each_status() {
        let (r, data) = run(0x03, None, &[2, 0, 1, 0, 7, 0]);
        assert!(r.unwrap_err().keeps_data());
        assert_eq!(data, [2, 0, 1, 0, 0, 0, 5, 0, 7, 0, 0x14, 0]);
        assert_eq!(run(0x03, None, &[2, 0, 1, 0]).0.unwrap_err().general, 0x13);
    }

    #[test]
    fn set_list_skips_read_only_and_stops_at_unknown() {
        let (r, data) = run(0x04, None, &[3, 0, 2, 0, 1, 1, 0, 7, 0, 9, 0, 1, 2]);
        assert!(r.is_err());
        assert_eq!(data, [3, 0, 2, 0, 0x0E, 0, 1, 0, 0, 0, 9, 0, 0x14, 0]);
    }
}
