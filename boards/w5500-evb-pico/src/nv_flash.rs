//! [`QspiFlash`]: the non-volatile store's two sectors in the board's 2 MiB QSPI flash (a
//! W25Q16JV behind the RP2040's XIP), the last two 4 KiB erase sectors: offsets 0x1F_E000 and
//! 0x1F_F000 (0x101F_E000 to 0x1020_0000 in the address map; `memory.x` keeps the program
//! below them), through embassy-rp's blocking flash driver and its `embedded-storage`
//! `NorFlash` implementation.
//!
//! While the flash is erased or programmed it cannot be read, and the RP2040 runs its code
//! from it: embassy-rp runs the operation from RAM with interrupts off, so the CPU (and all
//! I/O) stalls for it: a 4 KiB sector erase takes 45 ms typically, 400 ms at most (W25Q16JV
//! datasheet), a 256-byte page program 0.4 ms (3 ms at most). Saves happen only when a
//! scanner sets a stored attribute (TCP/IP attributes 3, 5, 6, 13) or resets to factory
//! defaults; the A/B scheme makes a power cut during one harmless.

use embassy_rp::flash::{Blocking, Flash};
use embassy_rp::peripherals::FLASH;
use enip_stack::nv::{AbStore, NorFlashSectors};

/// Bytes of the board's flash.
pub const FLASH_BYTES: usize = 2 * 1024 * 1024;
/// Bytes of each of the store's sectors: one erase sector of the flash.
const SECTOR_BYTES: usize = embassy_rp::flash::ERASE_SIZE;
/// Offset from the start of flash of the store's first sector (the second follows it).
const STORE_AT: u32 = (FLASH_BYTES - 2 * SECTOR_BYTES) as u32;

/// The board's flash driver.
pub type QspiDriver = Flash<'static, FLASH, Blocking, FLASH_BYTES>;
/// The last two sectors of the QSPI flash as the store's two sectors.
pub type QspiFlash = NorFlashSectors<QspiDriver, STORE_AT, SECTOR_BYTES>;

/// The store on the QSPI flash.
pub fn store(flash: QspiDriver) -> AbStore<QspiFlash> {
    AbStore::mount(NorFlashSectors::new(flash))
}
