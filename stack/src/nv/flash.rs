//! [`Flash`]: the few operations of NOR flash the store needs, and [`RamFlash`], one in RAM.

/// Largest program unit a [`Flash`] may ask for (the STM32F7 programs 32-bit words; others
/// up to 256-bit rows).
pub const MAX_WRITE_SIZE: usize = 32;

/// A flash operation failed (or, in a test, the power was cut).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FlashError;

impl core::fmt::Display for FlashError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("flash operation failed")
    }
}

impl core::error::Error for FlashError {}

/// Two erasable sectors of NOR-like flash: erasing sets every byte to 0xFF, programming
/// only clears bits, in aligned units of [`Flash::WRITE_SIZE`] bytes.
pub trait Flash {
    /// Usable bytes of each sector (a multiple of [`Flash::WRITE_SIZE`]).
    const SECTOR_SIZE: usize;
    /// Program unit in bytes: a power of two, at most [`MAX_WRITE_SIZE`].
    const WRITE_SIZE: usize;
    /// Reads `buf.len()` bytes of sector `sector` (0 or 1) from `offset`.
    fn read(&mut self, sector: u8, offset: usize, buf: &mut [u8]) -> Result<(), FlashError>;
    /// Erases sector `sector` (0 or 1).
    fn erase(&mut self, sector: u8) -> Result<(), FlashError>;
    /// Programs `data` into sector `sector` at `offset`; both are multiples of
    /// [`Flash::WRITE_SIZE`].
    fn program(&mut self, sector: u8, offset: usize, data: &[u8]) -> Result<(), FlashError>;
}

/// Flash in RAM, `S` bytes a sector: settings last as long as the process (host, QEMU);
/// [`RamFlash::sectors`] and [`RamFlash::from_sectors`] let a board keep them elsewhere.
#[derive(Debug, Clone)]
pub struct RamFlash<const S: usize> {
    sectors: [[u8; S]; 2],
}

impl<const S: usize> RamFlash<S> {
    /// Two erased sectors.
    pub const fn new() -> Self {
        RamFlash {
            sectors: [[0xFF; S]; 2],
        }
    }
    /// Flash with this content (e.g. read back from a file).
    pub const fn from_sectors(sectors: [[u8; S]; 2]) -> Self {
        RamFlash { sectors }
    }
    /// The content of both sectors.
    pub fn sectors(&self) -> &[[u8; S]; 2] {
        &self.sectors
    }

    fn range(&mut self, sector: u8, offset: usize, len: usize) -> Result<&mut [u8], FlashError> {
        let end = offset.checked_add(len).ok_or(FlashError)?;
        self.sectors
            .get_mut(usize::from(sector))
            .and_then(|s| s.get_mut(offset..end))
            .ok_or(FlashError)
    }
}

impl<const S: usize> Default for RamFlash<S> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const S: usize> Flash for RamFlash<S> {
    const SECTOR_SIZE: usize = S;
    const WRITE_SIZE: usize = 4;

    fn read(&mut self, sector: u8, offset: usize, buf: &mut [u8]) -> Result<(), FlashError> {
        buf.copy_from_slice(self.range(sector, offset, buf.len())?);
        Ok(())
    }
    fn erase(&mut self, sector: u8) -> Result<(), FlashError> {
        self.range(sector, 0, S)?.fill(0xFF);
        Ok(())
    }
    fn program(&mut self, sector: u8, offset: usize, data: &[u8]) -> Result<(), FlashError> {
        for (cell, b) in self.range(sector, offset, data.len())?.iter_mut().zip(data) {
            *cell &= *b;
        }
        Ok(())
    }
}
