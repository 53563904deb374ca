//! [`Flash`]: the few operations of NOR flash the store needs; [`NorFlashSectors`], two
//! sectors of any `embedded-storage` [`NorFlash`] driver as one; [`RamFlash`], one in RAM.
//!
//! The store keeps its own two-sector trait rather than taking a [`NorFlash`] directly: its
//! test flashes (RAM, power cut, file) are two arrays, and a sector number is what the A/B
//! scheme speaks in; a board with a HAL flash driver wraps it in [`NorFlashSectors`].

use embedded_storage::nor_flash::NorFlash;

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

/// Two adjacent sectors of `S` bytes of a [`NorFlash`] driver (a HAL's on-chip flash, an SPI
/// NOR chip), the first at offset `AT`, as the store's [`Flash`]; the offsets are constants,
/// so it costs no RAM beyond the driver. `AT` must be an erase boundary of the driver and `S`
/// a whole number of its erase units; the driver must read at any offset (`READ_SIZE` 1,
/// checked when this is built) and program at most [`MAX_WRITE_SIZE`] bytes at a time
/// (checked by [`super::AbStore::mount`]).
#[derive(Debug)]
pub struct NorFlashSectors<F, const AT: u32, const S: usize> {
    flash: F,
}

impl<F: NorFlash, const AT: u32, const S: usize> NorFlashSectors<F, AT, S> {
    /// Sectors 0 and 1 at offsets `AT` and `AT + S` of `flash`.
    pub const fn new(flash: F) -> Self {
        const {
            assert!(
                F::READ_SIZE == 1,
                "NorFlashSectors: the store reads at any offset"
            )
        };
        NorFlashSectors { flash }
    }

    /// The driver.
    pub fn flash(&self) -> &F {
        &self.flash
    }

    /// The driver's offset of `offset` in sector `sector`, if `len` bytes fit in the sector.
    fn at(sector: u8, offset: usize, len: usize) -> Result<u32, FlashError> {
        if sector > 1 || offset.checked_add(len).is_none_or(|end| end > S) {
            return Err(FlashError);
        }
        let from_start = S
            .checked_mul(usize::from(sector))
            .and_then(|s| s.checked_add(offset))
            .and_then(|o| u32::try_from(o).ok());
        from_start.and_then(|o| AT.checked_add(o)).ok_or(FlashError)
    }
}

impl<F: NorFlash, const AT: u32, const S: usize> Flash for NorFlashSectors<F, AT, S> {
    const SECTOR_SIZE: usize = S;
    const WRITE_SIZE: usize = F::WRITE_SIZE;

    fn read(&mut self, sector: u8, offset: usize, buf: &mut [u8]) -> Result<(), FlashError> {
        let at = Self::at(sector, offset, buf.len())?;
        self.flash.read(at, buf).map_err(|_| FlashError)
    }
    fn erase(&mut self, sector: u8) -> Result<(), FlashError> {
        let from = Self::at(sector, 0, S)?;
        let to = Self::at(sector, S, 0)?;
        self.flash.erase(from, to).map_err(|_| FlashError)
    }
    fn program(&mut self, sector: u8, offset: usize, data: &[u8]) -> Result<(), FlashError> {
        let at = Self::at(sector, offset, data.len())?;
        self.flash.write(at, data).map_err(|_| FlashError)
    }
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

#[cfg(test)]
mod tests {
    use embedded_storage::nor_flash::{
        check_erase, check_read, check_write, ErrorType, NorFlashErrorKind, ReadNorFlash,
    };

    use super::*;
    use crate::nv::{AbStore, NvStore};

    const SECTOR: usize = 4096;
    /// A NOR chip of 1 KiB erase units with the store's sectors after one unit of other data.
    struct Nor {
        cells: [u8; 1024 + 2 * SECTOR],
        erases: usize,
    }

    impl ErrorType for Nor {
        type Error = NorFlashErrorKind;
    }

    impl ReadNorFlash for Nor {
        const READ_SIZE: usize = 1;
        fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), Self::Error> {
            check_read(self, offset, bytes.len())?;
            let at = offset as usize;
            bytes.copy_from_slice(&self.cells[at..at + bytes.len()]);
            Ok(())
        }
        fn capacity(&self) -> usize {
            self.cells.len()
        }
    }

    impl NorFlash for Nor {
        const WRITE_SIZE: usize = 4;
        const ERASE_SIZE: usize = 1024;
        fn erase(&mut self, from: u32, to: u32) -> Result<(), Self::Error> {
            check_erase(self, from, to)?;
            self.cells[from as usize..to as usize].fill(0xFF);
            self.erases += 1;
            Ok(())
        }
        fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), Self::Error> {
            check_write(self, offset, bytes.len())?;
            let at = offset as usize;
            for (cell, b) in self.cells[at..at + bytes.len()].iter_mut().zip(bytes) {
                *cell &= *b;
            }
            Ok(())
        }
    }

    #[test]
    fn the_store_runs_on_two_sectors_of_a_nor_flash_driver() {
        let nor = Nor {
            cells: [0xFF; 1024 + 2 * SECTOR],
            erases: 0,
        };
        let sectors = NorFlashSectors::<_, 1024, SECTOR>::new(nor);
        let mut store = AbStore::mount(sectors);
        store.write(0x0100, b"saved").unwrap();
        store.write(0x0100, b"again").unwrap();
        let mut store = AbStore::mount(store.into_flash());
        let mut buf = [0u8; 8];
        assert_eq!(store.read(0x0100, &mut buf), Ok(Some(5)));
        assert_eq!(&buf[..5], b"again");
        let nor = store.flash().flash();
        assert_eq!(nor.erases, 2, "one whole sector erased per write");
        assert!(
            nor.cells[..1024].iter().all(|&b| b == 0xFF),
            "nothing before the sectors"
        );
        // Past a sector's end is refused, not passed on to the driver.
        let mut sectors = store.into_flash();
        assert_eq!(sectors.read(1, SECTOR - 2, &mut buf), Err(FlashError));
        assert_eq!(sectors.read(2, 0, &mut buf), Err(FlashError));
    }
}
