//! A no-access MPU region over the lowest [`GUARD`] bytes of the stack. flip-link puts the
//! stack at the start of RAM so that an overflow runs off it, but QEMU's mps2-an386 answers
//! the addresses just below RAM as an "unimplemented device" (reads zero, writes ignored)
//! instead of faulting; this guard makes the overflowing push fault (MemManage, escalated to
//! HardFault) as it does on hardware whose RAM has nothing below it.

use crate::mmio::Block;

/// The MPU's registers (ARMv7-M): control, region number, base address, attributes and size.
const MPU: Block = Block::at(0xE000_ED94);
const CTRL: usize = 0x0;
const RNR: usize = 0x4;
const RBAR: usize = 0x8;
const RASR: usize = 0xC;
/// CTRL: MPU on, the default memory map for privileged code outside the regions.
const ENABLE: u32 = 1 << 0;
const PRIVDEFENA: u32 = 1 << 2;
/// RASR: region enabled, never executed, no access (AP = 0).
const REGION_ON: u32 = 1 << 0;
const XN: u32 = 1 << 28;
/// Bytes of the guard (a power of two, at least 32); RASR.SIZE is log2 of it minus one.
pub const GUARD: u32 = 1024;

/// Makes the lowest [`GUARD`] bytes of the stack region inaccessible.
pub fn install() {
    let (bottom, _) = crate::stack::region();
    let size_field = GUARD.trailing_zeros() - 1;
    MPU.write(RNR, 0);
    MPU.write(RBAR, (bottom as u32) & !(GUARD - 1));
    MPU.write(RASR, XN | (size_field << 1) | REGION_ON);
    MPU.write(CTRL, ENABLE | PRIVDEFENA);
    cortex_m::asm::dsb();
    cortex_m::asm::isb();
}
