//! [`OnChipFlash`]: the non-volatile store's two sectors in the STM32H743ZI's own flash:
//! sectors 6 and 7 of bank 2 (the last two, 128 KiB each, at 0x081C0000 and 0x081E0000),
//! through embassy-stm32's blocking flash driver and its `embedded-storage` `NorFlash`
//! implementation. `memory.x` keeps the program in bank 1.
//!
//! Bank 2 is erased while bank 1 stays readable, so the CPU is not stalled on instruction
//! fetches during an erase: interrupts are taken (the MAC's DMA keeps filling its receive
//! descriptors, the time driver keeps time). The store's save is synchronous, though: the
//! executor waits in the driver's busy loop for the whole erase of a 128 KiB sector (on the
//! order of a second; not measured here), so Class 1 production and the watchdog's feeding
//! pause for that long at every save. Saves happen only when a scanner sets a stored
//! attribute (TCP/IP attributes 3, 5, 6, 13) or resets to factory defaults; the A/B scheme
//! makes a power cut during one harmless. The D-cache is off (embassy-stm32 leaves it so),
//! so reads after a program see the flash itself.

use embassy_stm32::flash::{Blocking, Flash};
use embassy_stm32::peripherals::FLASH;
use embassy_stm32::Peri;
use enip_stack::nv::{AbStore, NorFlashSectors};

/// Offset from the start of flash (0x08000000) of bank 2's sector 6 (sector 7 follows it).
const BANK2_SECTOR_6: u32 = 0x1C_0000;
/// Bytes of each of those sectors.
const SECTOR_BYTES: usize = 0x2_0000;

/// Sectors 6 and 7 of bank 2 as the store's two sectors.
pub type OnChipFlash = NorFlashSectors<Flash<'static, Blocking>, BANK2_SECTOR_6, SECTOR_BYTES>;

/// The store on the on-chip flash.
pub fn store(flash: Peri<'static, FLASH>) -> AbStore<OnChipFlash> {
    AbStore::mount(NorFlashSectors::new(Flash::new_blocking(flash)))
}
