//! The HardFault entry of the Cortex-M0+. ARMv6-M has none of the v7-M fault status registers
//! the other boards' `boards/shared/fault.rs` reads, so this entry only moves the stack
//! pointer back to the top of the stack and calls the board's `hard_fault(sp)` with the
//! stack pointer the fault was taken with, which logs it and resets.
//!
//! An overflow of the stack (flip-link put it at the start of RAM) faults on the push below
//! RAM; on ARMv6-M the exception entry's own stacking then faults too and the core locks
//! up instead of getting here: the watchdog (running outside the core) then resets the chip,
//! and `probe-rs run` reports the lock-up.

core::arch::global_asm!(
    ".section .HardFault.user, \"ax\"",
    ".global HardFault",
    ".type HardFault, %function",
    ".thumb_func",
    "HardFault:",
    "mrs r0, msp",
    "ldr r1, =_stack_start",
    "msr msp, r1",
    "ldr r1, ={handler}",
    "bx r1",
    ".ltorg",
    handler = sym crate::hard_fault,
);

/// True if a fault taken with stack pointer `sp` is a stack overflow: `sp` at or below the
/// bottom of the stack (1 KiB of slack).
pub fn overflowed(sp: u32) -> bool {
    let (bottom, _) = crate::stack::region();
    let bottom = u32::try_from(bottom).unwrap_or(0);
    sp <= bottom.saturating_add(1024)
}
