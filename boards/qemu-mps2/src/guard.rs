//! A no-access MPU region over the lowest [`GUARD`] bytes of the stack. flip-link puts the
//! stack at the start of RAM so that an overflow runs off it, but QEMU's mps2-an386 answers
//! the addresses just below RAM as an "unimplemented device" (reads zero, writes ignored)
//! instead of faulting; this guard makes the overflowing push fault (MemManage, escalated to
//! HardFault) as it does on hardware whose RAM has nothing below it. The ARMv8-M MPU of
//! the Cortex-M33 has no "no access" permission: there the guard is read-only, which is
//! enough, as an overflow is a push (a write).

use crate::mmio::Block;

/// The MPU's registers: control, region number, then (ARMv7-M) base address and
/// attributes with size, or (ARMv8-M) base address with permissions and limit address.
const MPU: Block = Block::at(0xE000_ED94);
const CTRL: usize = 0x0;
const RNR: usize = 0x4;
const RBAR: usize = 0x8;
const RASR: usize = 0xC;
const RLAR: usize = 0xC;
const MAIR0: usize = 0x2C;
/// CTRL: MPU on, the default memory map for privileged code outside the regions.
const ENABLE: u32 = 1 << 0;
const PRIVDEFENA: u32 = 1 << 2;
/// RASR: region enabled, never executed, no access (AP = 0).
const REGION_ON: u32 = 1 << 0;
const XN: u32 = 1 << 28;
/// ARMv8-M RBAR: never executed, read-only at any privilege (AP = 0b11).
const V8_XN: u32 = 1 << 0;
const V8_READ_ONLY: u32 = 0b11 << 1;
/// ARMv8-M RLAR: region enabled, memory attributes from MAIR0's byte 0.
const V8_REGION_ON: u32 = 1 << 0;
/// ARMv8-M MAIR0 byte 0: normal memory, write-back (as the RAM it covers).
const V8_NORMAL: u32 = 0xFF;
/// Bytes of the guard (a power of two, at least 32); RASR.SIZE is log2 of it minus one.
pub const GUARD: u32 = 1024;

/// Makes the lowest [`GUARD`] bytes of the stack region inaccessible.
pub fn install() {
    let (bottom, _) = crate::stack::region();
    let base = (bottom as u32) & !(GUARD - 1);
    MPU.write(RNR, 0);
    if crate::machine::THIS.armv8m_mpu {
        // Base and limit are 32-byte granules: the limit names the last one.
        MPU.write(MAIR0, V8_NORMAL);
        MPU.write(RBAR, base | V8_READ_ONLY | V8_XN);
        MPU.write(RLAR, (base + GUARD - 32) | V8_REGION_ON);
    } else {
        let size_field = GUARD.trailing_zeros() - 1;
        MPU.write(RBAR, base);
        MPU.write(RASR, XN | (size_field << 1) | REGION_ON);
    }
    MPU.write(CTRL, ENABLE | PRIVDEFENA);
    cortex_m::asm::dsb();
    cortex_m::asm::isb();
}
