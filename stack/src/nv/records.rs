//! The records inside one stored copy: `key: u16, length: u16, value` one after another,
//! little-endian; looked up, replaced and removed in place without panicking.

use super::NvError;

/// Bytes before each record's value.
pub(crate) const RECORD_HEADER: usize = 4;

/// The records of `area` as (key, value), up to the first malformed one.
fn iter(area: &[u8]) -> impl Iterator<Item = (usize, u16, &[u8])> {
    let mut at = 0usize;
    core::iter::from_fn(move || {
        let head = area.get(at..at.checked_add(RECORD_HEADER)?)?;
        let (key, len) = match head {
            [k0, k1, l0, l1] => (
                u16::from_le_bytes([*k0, *k1]),
                usize::from(u16::from_le_bytes([*l0, *l1])),
            ),
            _ => return None,
        };
        let start = at.checked_add(RECORD_HEADER)?;
        let value = area.get(start..start.checked_add(len)?)?;
        let here = at;
        at = start.saturating_add(len);
        Some((here, key, value))
    })
}

/// The value of record `key` in `area`.
pub(crate) fn find(area: &[u8], key: u16) -> Option<&[u8]> {
    iter(area).find(|(_, k, _)| *k == key).map(|(_, _, v)| v)
}

/// Replaces (or with `None` removes) record `key` in `buf[..used]`; the new used length.
/// Nothing changes if the result would not fit in `buf`.
pub(crate) fn replace(
    buf: &mut [u8],
    used: usize,
    key: u16,
    value: Option<&[u8]>,
) -> Result<usize, NvError> {
    let area = buf.get(..used).ok_or(NvError::NoSpace)?;
    let old = iter(area)
        .find(|(_, k, _)| *k == key)
        .map(|(at, _, v)| (at, RECORD_HEADER.saturating_add(v.len())));
    let removed = old.map_or(0, |(_, size)| size);
    let added = match value {
        Some(v) => {
            u16::try_from(v.len()).map_err(|_| NvError::NoSpace)?;
            RECORD_HEADER.saturating_add(v.len())
        }
        None => 0,
    };
    let new_used = used
        .saturating_sub(removed)
        .checked_add(added)
        .filter(|n| *n <= buf.len())
        .ok_or(NvError::NoSpace)?;
    let mut end = used;
    if let Some((at, size)) = old {
        buf.copy_within(at.saturating_add(size)..used, at);
        end = used.saturating_sub(size);
    }
    if let Some(v) = value {
        let len = (v.len() as u16).to_le_bytes();
        let slot = buf.get_mut(end..new_used).ok_or(NvError::NoSpace)?;
        let (head, rest) = slot.split_at_mut(RECORD_HEADER);
        head.copy_from_slice(&[key.to_le_bytes()[0], key.to_le_bytes()[1], len[0], len[1]]);
        rest.copy_from_slice(v);
    }
    Ok(new_used)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replace_find_remove() {
        let mut buf = [0u8; 20];
        let used = replace(&mut buf, 0, 1, Some(b"abc")).unwrap();
        let used = replace(&mut buf, used, 2, Some(b"xy")).unwrap();
        assert_eq!(used, 13);
        let used = replace(&mut buf, used, 1, Some(b"defg")).unwrap();
        assert_eq!(find(&buf[..used], 1), Some(&b"defg"[..]));
        assert_eq!(find(&buf[..used], 2), Some(&b"xy"[..]));
        assert_eq!(
            replace(&mut buf, used, 3, Some(b"too long")),
            Err(NvError::NoSpace)
        );
        assert_eq!(find(&buf[..used], 1), Some(&b"defg"[..]));
        let used = replace(&mut buf, used, 2, None).unwrap();
        assert_eq!((used, find(&buf[..used], 2)), (8, None));
        assert_eq!(find(&[1, 0, 9, 0, 1], 1), None);
    }
}
