//! [`OnChipFlash`]: the non-volatile store's two sectors in the STM32H563ZI's own flash:
//! sectors 126 and 127 of bank 2 (the last two, 8 KiB each, at 0x081FC000 and 0x081FE000),
//! through embassy-stm32's blocking flash driver and its `embedded-storage` `NorFlash`
//! implementation. `memory.x` keeps the program in bank 1.
//!
//! The store's image (2 KiB) fits an 8 KiB sector, so a save erases 8 KiB only: a
//! stall expected in milliseconds (not measured here), not the second a 128 KiB
//! sector of the H743 or the 256 KiB one of the F767 takes. The store's save is
//! synchronous: the executor, and with it Class 1, waits for that erase and the programming;
//! bank 2 being erased while bank 1 stays readable, the CPU keeps fetching instructions and
//! taking interrupts meanwhile. Saves happen only when a scanner sets a stored attribute
//! (TCP/IP attributes 3, 5, 6, 13) or resets to factory defaults; the A/B scheme makes a
//! power cut during one harmless. The instruction cache is off (embassy-stm32 leaves it so),
//! so reads after a program see the flash itself.

use embassy_stm32::flash::{Blocking, Flash};
use embassy_stm32::peripherals::FLASH;
use embassy_stm32::Peri;
use enip_stack::nv::{AbStore, NorFlashSectors};

/// Offset from the start of flash (0x08000000) of bank 2's sector 126 (sector 127 follows).
const BANK2_SECTOR_126: u32 = 0x1F_C000;
/// Bytes of each of those sectors.
const SECTOR_BYTES: usize = 0x2000;

/// Sectors 126 and 127 of bank 2 as the store's two sectors.
pub type OnChipFlash = NorFlashSectors<Flash<'static, Blocking>, BANK2_SECTOR_126, SECTOR_BYTES>;

/// The store on the on-chip flash.
pub fn store(flash: Peri<'static, FLASH>) -> AbStore<OnChipFlash> {
    AbStore::mount(NorFlashSectors::new(Flash::new_blocking(flash)))
}
