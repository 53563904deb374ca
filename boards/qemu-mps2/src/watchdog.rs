//! The machine's CMSDK APB watchdog (0x4000_8000, clocked at 25 MHz; on mps2-an505 the
//! Secure watchdog at 0x5008_1000, 20 MHz; its interrupt is the NMI). Loaded with [`STAGE`]: unfed for one stage it raises the NMI, which logs that the
//! firmware stopped making progress and waits; unfed for a second stage it resets the
//! machine (QEMU's watchdog action: reset). [`feed`] is called by the firmware's
//! `watchdog::keep_fed` task only.

use crate::mmio::Block;

const WDOG: Block = Block::at(crate::machine::THIS.watchdog);
const LOAD: usize = 0x000;
const CTRL: usize = 0x008;
const INTCLR: usize = 0x00C;
const LOCK: usize = 0xC00;
/// CTRL: interrupt (NMI) at the first expiry, counter enabled.
const INTEN: u32 = 1 << 0;
/// CTRL: reset at the second expiry.
const RESEN: u32 = 1 << 1;
/// LOCK: the key that allows writes to the other registers; anything else locks them.
const UNLOCK: u32 = 0x1ACC_E551;
/// Counts of one stage: 2 s at the system clock (NMI after 2 s unfed, reset after 4 s).
pub const STAGE: u32 = 2 * crate::machine::THIS.clock_hz;
/// Milliseconds of one stage, for the log.
pub const STAGE_MS: u32 = 2_000;

/// Starts the watchdog.
pub fn start() {
    WDOG.write(LOCK, UNLOCK);
    WDOG.write(LOAD, STAGE);
    WDOG.write(CTRL, INTEN | RESEN);
    WDOG.write(LOCK, 0);
}

/// Reloads the counter (clearing the interrupt).
pub fn feed() {
    WDOG.write(LOCK, UNLOCK);
    WDOG.write(INTCLR, 1);
    WDOG.write(LOCK, 0);
}

/// The first expiry: the firmware has not made progress for a stage. Logs it and waits for
/// the second expiry's reset.
#[cortex_m_rt::exception]
unsafe fn NonMaskableInt() {
    crate::uart::report(format_args!(
        "WATCHDOG: no progress for {STAGE_MS} ms (executor or link task stuck); reset in {STAGE_MS} ms"
    ));
    loop {
        cortex_m::asm::nop();
    }
}
