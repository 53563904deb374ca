//! The call stack's high-water mark, shared by the embedded boards (`#[path]`-included).
//!
//! The boards link with flip-link, which puts the stack at the start of RAM below the
//! statics and defines `_stack_end` (its lowest address, the start of RAM) and
//! `_stack_start` (its top, where the statics begin). [`paint`] fills the window of
//! [`WINDOW`] bytes below the current stack pointer with [`PAINT`] at boot; [`measure`]
//! finds the lowest word that is no longer paint: everything above it has been used.

use core::sync::atomic::{AtomicUsize, Ordering};

use enip_firmware::diagnostics::StackUse;

extern "C" {
    /// Top of the stack (the stack grows down from here).
    static _stack_start: u32;
    /// Bottom of the stack region.
    static _stack_end: u32;
}

/// The pattern painted below the stack pointer.
pub const PAINT: u32 = 0xC5AC_CE55;
/// Bytes painted at most below the stack pointer at boot: above the deepest use measured
/// (94 KiB with the Parker IPA profile on the emulated board, 35 KiB of it before the
/// painting), and quick enough to scan (a read of the mark walks the untouched part of it:
/// at most 32 K words).
pub const WINDOW: usize = 128 * 1024;
/// Bytes just below the painting function's stack pointer left alone.
const GAP: usize = 64;

/// The lowest painted address (0: not painted).
static PAINTED_FROM: AtomicUsize = AtomicUsize::new(0);

/// The stack region `(bottom, top)`.
pub fn region() -> (usize, usize) {
    // Only the addresses of the linker's symbols are taken, never their contents.
    (
        core::ptr::addr_of!(_stack_end) as usize,
        core::ptr::addr_of!(_stack_start) as usize,
    )
}

/// Paints up to [`WINDOW`] bytes below the current stack pointer. Call it once, first thing
/// in the board's start-up, before any interrupt is enabled (an interrupt's frame there
/// would be painted over): it runs with interrupts off.
pub fn paint() {
    cortex_m::interrupt::free(|_| {
        let (bottom, _) = region();
        let sp = cortex_m::register::msp::read() as usize;
        let top = sp.saturating_sub(GAP) & !3;
        let from = top.saturating_sub(WINDOW).max(bottom);
        let mut at = from;
        while at < top {
            // SAFETY: `[from, top)` is stack memory below every live frame (interrupts are
            // off and this loop calls nothing), word-aligned.
            unsafe { core::ptr::write_volatile(at as *mut u32, PAINT) };
            at += 4;
        }
        PAINTED_FROM.store(from, Ordering::Relaxed);
    });
}

/// The stack's size, the painted part of it and its deepest use since [`paint`] (bytes).
pub fn measure() -> StackUse {
    let (bottom, top) = region();
    let bytes = |n: usize| u32::try_from(n).unwrap_or(u32::MAX);
    let from = PAINTED_FROM.load(Ordering::Relaxed);
    if from == 0 {
        return StackUse {
            size: bytes(top - bottom),
            painted: 0,
            deepest: 0,
        };
    }
    let mut at = from;
    // SAFETY: volatile reads of words of the stack region painted at boot (some may be in a
    // live frame by now: they are only read).
    while at < top && unsafe { core::ptr::read_volatile(at as *const u32) } == PAINT {
        at += 4;
    }
    StackUse {
        size: bytes(top - bottom),
        painted: bytes(top - from),
        deepest: bytes(top - at),
    }
}
