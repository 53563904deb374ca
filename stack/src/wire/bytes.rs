//! Bounds-checked little-endian readers and writers over byte slices.

use super::{Error, Result};

/// Reads the little-endian `u16` at `at`, or 0 if out of range (callers check length first).
pub(crate) fn get_u16(buf: &[u8], at: usize) -> u16 {
    match buf.get(at..at.wrapping_add(2)) {
        Some(&[a, b]) => u16::from_le_bytes([a, b]),
        _ => 0,
    }
}

/// Reads the little-endian `u32` at `at`, or 0 if out of range (callers check length first).
pub(crate) fn get_u32(buf: &[u8], at: usize) -> u32 {
    match buf.get(at..at.wrapping_add(4)) {
        Some(&[a, b, c, d]) => u32::from_le_bytes([a, b, c, d]),
        _ => 0,
    }
}

/// Writes `v` little-endian at `at` if it fits (callers check length first).
pub(crate) fn put_u16(buf: &mut [u8], at: usize, v: u16) {
    if let Some(d) = buf.get_mut(at..at.wrapping_add(2)) {
        d.copy_from_slice(&v.to_le_bytes());
    }
}

/// Writes `v` little-endian at `at` if it fits (callers check length first).
pub(crate) fn put_u32(buf: &mut [u8], at: usize, v: u32) {
    if let Some(d) = buf.get_mut(at..at.wrapping_add(4)) {
        d.copy_from_slice(&v.to_le_bytes());
    }
}

/// A forward-only cursor over untrusted bytes; every read is length-checked.
#[derive(Clone, Debug)]
pub struct Reader<'a> {
    data: &'a [u8],
}

impl<'a> Reader<'a> {
    /// A reader over `data`.
    pub const fn new(data: &'a [u8]) -> Self {
        Reader { data }
    }
    /// Bytes not yet read.
    pub const fn remaining(&self) -> usize {
        self.data.len()
    }
    /// The unread bytes.
    pub const fn rest(&self) -> &'a [u8] {
        self.data
    }
    /// Takes the next `n` bytes.
    pub fn take(&mut self, n: usize) -> Result<&'a [u8]> {
        if n > self.data.len() {
            return Err(Error::Truncated);
        }
        let (head, tail) = self.data.split_at(n);
        self.data = tail;
        Ok(head)
    }
    /// Reads one byte.
    pub fn u8(&mut self) -> Result<u8> {
        match self.data.split_first() {
            Some((&b, tail)) => {
                self.data = tail;
                Ok(b)
            }
            None => Err(Error::Truncated),
        }
    }
    /// Reads a little-endian `u16`.
    pub fn u16(&mut self) -> Result<u16> {
        let b = self.take(2)?;
        Ok(get_u16(b, 0))
    }
    /// Reads a little-endian `u32`.
    pub fn u32(&mut self) -> Result<u32> {
        let b = self.take(4)?;
        Ok(get_u32(b, 0))
    }
    /// Reads `N` bytes into an array.
    pub fn array<const N: usize>(&mut self) -> Result<[u8; N]> {
        let mut out = [0u8; N];
        out.copy_from_slice(self.take(N)?);
        Ok(out)
    }
}

/// A forward-only cursor writing into a caller's buffer; it never writes past the end.
#[derive(Debug)]
pub struct Writer<'a> {
    buf: &'a mut [u8],
    len: usize,
}

impl<'a> Writer<'a> {
    /// A writer at the start of `buf`.
    pub fn new(buf: &'a mut [u8]) -> Self {
        Writer { buf, len: 0 }
    }
    /// Bytes written so far.
    pub const fn len(&self) -> usize {
        self.len
    }
    /// True if nothing was written.
    pub const fn is_empty(&self) -> bool {
        self.len == 0
    }
    /// Bytes still free.
    pub fn capacity_left(&self) -> usize {
        self.buf.len().saturating_sub(self.len)
    }
    /// The bytes written so far.
    pub fn written(&self) -> &[u8] {
        self.buf.get(..self.len).unwrap_or(&[])
    }
    /// Reserves `n` bytes and returns them for the caller to fill.
    pub fn reserve(&mut self, n: usize) -> Result<&mut [u8]> {
        let end = self.len.checked_add(n).ok_or(Error::Exhausted)?;
        let start = self.len;
        match self.buf.get_mut(start..end) {
            Some(s) => {
                self.len = end;
                Ok(s)
            }
            None => Err(Error::Exhausted),
        }
    }
    /// Appends bytes. Never inlined on a bare-metal target (nor are `u8`, `u16`, `u32`): the
    /// encoders' many small writes share one copy there, where flash is short (the Class 1
    /// path writes its header through [`Self::reserve`], which stays inlined). A host's
    /// inliner keeps its own choice: there, the attribute shifted the code LLVM generated
    /// for the `io_cycle` bench's inlined loop (+9 instructions a cycle, none of them in
    /// these functions).
    #[cfg_attr(target_os = "none", inline(never))]
    pub fn bytes(&mut self, b: &[u8]) -> Result<()> {
        self.reserve(b.len())?.copy_from_slice(b);
        Ok(())
    }
    /// Appends the `N` bytes of `v` as one fixed-size store (no call to a copy loop, as a
    /// slice of unknown length would take).
    fn array<const N: usize>(&mut self, v: [u8; N]) -> Result<()> {
        match self.reserve(N)?.first_chunk_mut::<N>() {
            Some(d) => {
                *d = v;
                Ok(())
            }
            None => Err(Error::Exhausted),
        }
    }
    /// Appends one byte.
    #[cfg_attr(target_os = "none", inline(never))]
    pub fn u8(&mut self, v: u8) -> Result<()> {
        self.array([v])
    }
    /// Appends a little-endian `u16`.
    #[cfg_attr(target_os = "none", inline(never))]
    pub fn u16(&mut self, v: u16) -> Result<()> {
        self.array(v.to_le_bytes())
    }
    /// Appends a little-endian `u32`.
    #[cfg_attr(target_os = "none", inline(never))]
    pub fn u32(&mut self, v: u32) -> Result<()> {
        self.array(v.to_le_bytes())
    }
    /// Appends one signed byte (CIP SINT).
    pub fn i8(&mut self, v: i8) -> Result<()> {
        self.u8(v as u8)
    }
    /// Appends a little-endian `i16` (CIP INT).
    pub fn i16(&mut self, v: i16) -> Result<()> {
        self.u16(v as u16)
    }
    /// Appends a little-endian `i32` (CIP DINT).
    pub fn i32(&mut self, v: i32) -> Result<()> {
        self.u32(v as u32)
    }
    /// Appends `n` zero bytes.
    pub fn zeros(&mut self, n: usize) -> Result<()> {
        self.reserve(n)?.fill(0);
        Ok(())
    }
    /// Overwrites a little-endian `u16` already written at `at`.
    pub fn patch_u16(&mut self, at: usize, v: u16) {
        if at.saturating_add(2) <= self.len {
            put_u16(self.buf, at, v);
        }
    }
    /// Writes how many bytes were written since `at` into the `u16` just before it: a CPF
    /// item's length, once its data is complete.
    pub fn patch_item_len(&mut self, at: usize) {
        let len = self.len.saturating_sub(at);
        self.patch_u16(at.saturating_sub(2), len as u16);
    }
    /// Inserts `bytes` at offset `at`, moving what was written after it to the right.
    pub fn insert(&mut self, at: usize, bytes: &[u8]) -> Result<()> {
        let old = self.len;
        if at > old {
            return Err(Error::Exhausted);
        }
        self.reserve(bytes.len())?;
        // `reserve` succeeded, so at + bytes.len() <= old + bytes.len() fits the buffer.
        let end = at.saturating_add(bytes.len());
        self.buf.copy_within(at..old, end);
        if let Some(dst) = self.buf.get_mut(at..end) {
            dst.copy_from_slice(bytes);
        }
        Ok(())
    }
    /// Drops everything written after `len`.
    pub fn truncate(&mut self, len: usize) {
        self.len = self.len.min(len);
    }
    /// A writer over the free tail of the buffer (its length is added back by [`Self::advance`]).
    pub fn tail(&mut self) -> &mut [u8] {
        let start = self.len.min(self.buf.len());
        self.buf.get_mut(start..).unwrap_or(&mut [])
    }
    /// Marks `n` more bytes (filled through [`Self::tail`]) as written.
    pub fn advance(&mut self, n: usize) -> Result<()> {
        self.reserve(n).map(|_| ())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reader_never_reads_past_end() {
        let mut r = Reader::new(&[1, 2, 3]);
        assert_eq!(r.u16(), Ok(0x0201));
        assert_eq!(r.u16(), Err(Error::Truncated));
        assert_eq!(r.u8(), Ok(3));
        assert_eq!(r.u8(), Err(Error::Truncated));
    }

    #[test]
    fn writer_inserts() {
        let mut buf = [0u8; 6];
        let mut w = Writer::new(&mut buf);
        w.bytes(&[1, 2, 3]).unwrap();
        w.insert(1, &[8, 9]).unwrap();
        assert_eq!(w.written(), &[1, 8, 9, 2, 3]);
        assert_eq!(w.insert(0, &[7, 7]), Err(Error::Exhausted));
        assert_eq!(w.written(), &[1, 8, 9, 2, 3]);
    }

    #[test]
    fn writer_never_writes_past_end() {
        let mut buf = [0u8; 3];
        let mut w = Writer::new(&mut buf);
        assert!(w.u16(0xBEEF).is_ok());
        assert_eq!(w.u16(1), Err(Error::Exhausted));
        assert_eq!(w.len(), 2);
        assert!(w.u8(7).is_ok());
        assert_eq!(buf, [0xEF, 0xBE, 7]);
    }

    #[test]
    fn signed_writers_are_little_endian_twos_complement() {
        let mut buf = [0u8; 7];
        let mut w = Writer::new(&mut buf);
        assert!(w.i8(-2).is_ok() && w.i16(-300).is_ok() && w.i32(-70_000).is_ok());
        assert_eq!(w.i8(0), Err(Error::Exhausted));
        assert_eq!(buf, [0xFE, 0xD4, 0xFE, 0x90, 0xEE, 0xFE, 0xFF]);
    }
}
