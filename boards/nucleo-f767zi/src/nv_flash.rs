//! [`OnChipFlash`]: the non-volatile store's two sectors in the STM32F767ZI's own flash,
//! sectors 10 and 11 (the last two, 256 KiB each, single-bank mode; `memory.x` keeps the
//! program out of them), through embassy-stm32's blocking flash driver and its
//! `embedded-storage` `NorFlash` implementation.
//!
//! Erasing a 256 KiB sector takes about 1 to 2 s, during which the single bank cannot be
//! read: the CPU (and so all I/O) stalls for that long at every save. Saves happen only when
//! a scanner sets a stored attribute (TCP/IP attributes 3, 5, 6, 13) or resets to factory
//! defaults; the A/B scheme makes a power cut during one harmless. The D-cache is off, so
//! reads after a program see the flash itself.

use embassy_stm32::flash::{Blocking, Flash};
use embassy_stm32::peripherals::FLASH;
use embassy_stm32::Peri;
use enip_stack::nv::{AbStore, NorFlashSectors};

/// Offset from the start of flash of sector 10 (sector 11 follows it).
const SECTOR_10: u32 = 0x18_0000;
/// Bytes of each of those sectors.
const SECTOR_BYTES: usize = 0x4_0000;

/// Sectors 10 and 11 of the on-chip flash as the store's two sectors.
pub type OnChipFlash = NorFlashSectors<Flash<'static, Blocking>, SECTOR_10, SECTOR_BYTES>;

/// The store on the on-chip flash.
pub fn store(flash: Peri<'static, FLASH>) -> AbStore<OnChipFlash> {
    AbStore::mount(NorFlashSectors::new(Flash::new_blocking(flash)))
}
