//! How the emulated board ends a fault in a known, logged state: a panic and a HardFault
//! (a stack overflow among them, see the shared `fault` entry) are reported on UART0 and
//! reset the machine; a stuck firmware is reset by the [`crate::watchdog`]. Test images
//! (`ENIP_TEST_FAULTS=on`) can be made to fault on purpose over CIP ([`provoke`]).

use cortex_m::peripheral::SCB;

/// The fault kinds of [`provoke`]: a firmware that hangs in the executor.
pub const HANG: u8 = 1;
/// A recursion that runs off the bottom of the stack.
pub const OVERFLOW: u8 = 2;
/// A panic.
pub const PANIC: u8 = 3;

/// Faults on purpose (the diagnostics object's test service): [`HANG`], [`OVERFLOW`] or
/// [`PANIC`]; other kinds do nothing.
pub fn provoke(kind: u8) {
    match kind {
        HANG => {
            log::warn!("provoked: hanging the executor");
            loop {
                core::hint::spin_loop();
            }
        }
        OVERFLOW => {
            log::warn!("provoked: recursing until the stack overflows");
            core::hint::black_box(dive(0));
        }
        PANIC => panic!("provoked panic"),
        _ => {}
    }
}

/// Recurses with a frame of 64 bytes per call until the stack runs out.
#[inline(never)]
fn dive(depth: u32) -> u32 {
    let frame = core::hint::black_box([depth; 16]);
    if depth == u32::MAX {
        return 0;
    }
    dive(depth.wrapping_add(1)).wrapping_add(frame[15])
}

/// The HardFault handler proper, entered on a fresh stack with the faulting stack pointer:
/// reports the fault and resets.
pub extern "C" fn hard_fault(sp: u32) -> ! {
    let f = crate::fault::fault(sp);
    let what = if f.overflow {
        "stack overflow"
    } else {
        "fault"
    };
    crate::uart::report(format_args!(
        "HARDFAULT: {what} (sp {:#010x}, CFSR {:#010x}, HFSR {:#010x}, address {:#010x}): resetting",
        f.sp, f.cfsr, f.hfsr, f.address
    ));
    SCB::sys_reset()
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo<'_>) -> ! {
    crate::uart::report(format_args!("PANIC: {info}: resetting"));
    SCB::sys_reset()
}
