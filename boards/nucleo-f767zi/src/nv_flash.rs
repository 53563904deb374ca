//! [`OnChipFlash`]: the non-volatile store's two sectors in the STM32F767ZI's own flash,
//! sectors 10 and 11 (the last two, 256 KiB each, single-bank mode; `memory.x` keeps the
//! program out of them), through embassy-stm32's blocking flash driver.
//!
//! Erasing a 256 KiB sector takes about 1 to 2 s, during which the single bank cannot be
//! read: the CPU (and so all I/O) stalls for that long at every save. Saves happen only when
//! a scanner sets a stored attribute (TCP/IP attributes 3, 5, 6, 13) or resets to factory
//! defaults; the A/B scheme makes a power cut during one harmless. The D-cache is off, so
//! reads after a program see the flash itself.

use embassy_stm32::flash::{Blocking, Flash as Stm32Flash, WRITE_SIZE};
use embassy_stm32::peripherals::FLASH;
use embassy_stm32::Peri;
use enip_stack::nv::{AbStore, Flash, FlashError};

/// Offsets from the start of flash of sectors 10 and 11.
const SECTORS: [u32; 2] = [0x18_0000, 0x1C_0000];
/// Bytes of each of those sectors.
const SECTOR_BYTES: u32 = 0x4_0000;

/// Sectors 10 and 11 of the on-chip flash as the store's two sectors.
pub struct OnChipFlash {
    flash: Stm32Flash<'static, Blocking>,
}

impl OnChipFlash {
    /// Takes the flash controller.
    pub fn new(flash: Peri<'static, FLASH>) -> Self {
        OnChipFlash {
            flash: Stm32Flash::new_blocking(flash),
        }
    }

    /// The flash offset of `offset` in store sector `sector`, if `len` bytes fit there.
    fn at(sector: u8, offset: usize, len: usize) -> Result<u32, FlashError> {
        let base = SECTORS.get(usize::from(sector)).ok_or(FlashError)?;
        let offset = u32::try_from(offset).map_err(|_| FlashError)?;
        let len = u32::try_from(len).map_err(|_| FlashError)?;
        if offset.checked_add(len).is_none_or(|end| end > SECTOR_BYTES) {
            return Err(FlashError);
        }
        Ok(base + offset)
    }
}

impl Flash for OnChipFlash {
    const SECTOR_SIZE: usize = SECTOR_BYTES as usize;
    const WRITE_SIZE: usize = WRITE_SIZE;

    fn read(&mut self, sector: u8, offset: usize, buf: &mut [u8]) -> Result<(), FlashError> {
        let at = Self::at(sector, offset, buf.len())?;
        self.flash.blocking_read(at, buf).map_err(|_| FlashError)
    }
    fn erase(&mut self, sector: u8) -> Result<(), FlashError> {
        let at = Self::at(sector, 0, SECTOR_BYTES as usize)?;
        self.flash
            .blocking_erase(at, at + SECTOR_BYTES)
            .map_err(|_| FlashError)
    }
    fn program(&mut self, sector: u8, offset: usize, data: &[u8]) -> Result<(), FlashError> {
        let at = Self::at(sector, offset, data.len())?;
        self.flash.blocking_write(at, data).map_err(|_| FlashError)
    }
}

/// The store on the on-chip flash.
pub fn store(flash: Peri<'static, FLASH>) -> AbStore<OnChipFlash> {
    AbStore::mount(OnChipFlash::new(flash))
}
