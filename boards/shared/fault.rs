//! The HardFault entry shared by the embedded boards (`#[path]`-included): it first moves
//! the stack pointer back to the top of the stack, so that the handler runs even when the
//! fault is a stack overflow (flip-link put the stack at the start of RAM: the overflowing
//! push faulted below it, and the exception frame could not be stacked), then calls the
//! board's `hard_fault(sp)` with the stack pointer the fault was taken with, which logs what
//! it can and resets. This is the vector itself (cortex-m-rt's default `HardFault` gives way
//! to it); nothing on the old stack is touched. The boards run on the main stack only.

core::arch::global_asm!(
    ".section .HardFault.user, \"ax\"",
    ".global HardFault",
    ".type HardFault, %function",
    ".thumb_func",
    "HardFault:",
    "mrs r0, msp",
    "ldr r1, =_stack_start",
    "msr msp, r1",
    "b {handler}",
    handler = sym crate::hard_fault,
);

/// The fault status registers and the stack pointer at the fault.
#[derive(Debug, Clone, Copy)]
pub struct Fault {
    /// Configurable Fault Status Register (MemManage, BusFault, UsageFault bits).
    pub cfsr: u32,
    /// HardFault Status Register.
    pub hfsr: u32,
    /// The data address that faulted: MemManage's (MMFAR) or the BusFault's (BFAR), whichever
    /// CFSR says is valid; 0 if neither.
    pub address: u32,
    /// The stack pointer when the fault was taken.
    pub sp: u32,
    /// True if that pointer was at or below the bottom of the stack: an overflow.
    pub overflow: bool,
}

/// Reads the fault registers; `sp` is the stack pointer the fault was taken with.
pub fn fault(sp: u32) -> Fault {
    const CFSR: *const u32 = 0xE000_ED28 as *const u32;
    const HFSR: *const u32 = 0xE000_ED2C as *const u32;
    const MMFAR: *const u32 = 0xE000_ED34 as *const u32;
    const BFAR: *const u32 = 0xE000_ED38 as *const u32;
    /// CFSR: MMFAR, BFAR hold the faulting address.
    const MMARVALID: u32 = 1 << 7;
    const BFARVALID: u32 = 1 << 15;
    let (bottom, _) = crate::stack::region();
    let bottom = u32::try_from(bottom).unwrap_or(0);
    // SAFETY: the System Control Block's fault registers, always readable in handler mode.
    unsafe {
        let cfsr = core::ptr::read_volatile(CFSR);
        let address = if cfsr & MMARVALID != 0 {
            core::ptr::read_volatile(MMFAR)
        } else if cfsr & BFARVALID != 0 {
            core::ptr::read_volatile(BFAR)
        } else {
            0
        };
        Fault {
            cfsr,
            hfsr: core::ptr::read_volatile(HFSR),
            address,
            sp,
            overflow: sp <= bottom.saturating_add(OVERFLOW_SLACK),
        }
    }
}

/// A fault this close above the bottom of the stack is counted as an overflow too: the
/// emulated board's MPU guard covers that much of it.
const OVERFLOW_SLACK: u32 = 1024;
