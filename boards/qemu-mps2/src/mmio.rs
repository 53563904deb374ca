//! Memory-mapped register blocks: the only raw pointer access of the board.

use core::arch::asm;

/// `$n` bursts in one `asm!` loop: eight words loaded from `$src` (`ldm $load`), then stored
/// to `$dst` (`stm $store`); the memory side's pointer is written back (`!`), the FIFO
/// port's is not. Registers r6, r7 and r9 are left alone (LLVM's own).
macro_rules! burst_loop {
    ($load:literal, $store:literal, $src:expr, $dst:expr, $n:expr) => {
        asm!(
            "2:",
            concat!("ldm ", $load, ", {{r0, r1, r2, r3, r4, r5, r8, r12}}"),
            concat!("stm ", $store, ", {{r0, r1, r2, r3, r4, r5, r8, r12}}"),
            "subs {n}, {n}, #1",
            "bne 2b",
            src = inout(reg) $src as usize => _,
            dst = inout(reg) $dst as usize => _,
            n = inout(reg) $n => _,
            out("r0") _, out("r1") _, out("r2") _, out("r3") _,
            out("r4") _, out("r5") _, out("r8") _, out("r12") _,
            options(nostack),
        )
    };
}

/// A block of 32-bit device registers at a fixed address.
#[derive(Debug, Clone, Copy)]
pub struct Block {
    base: usize,
}

impl Block {
    /// The block at `base`, which must be a device of the mps2-an386 memory map.
    pub const fn at(base: usize) -> Self {
        Block { base }
    }

    /// Reads the register at byte offset `offset`.
    pub fn read(self, offset: usize) -> u32 {
        // SAFETY: every `Block` is a device of the machine's memory map, and `offset` a
        // register of it (the constants next to each block); device reads are volatile.
        unsafe { core::ptr::read_volatile((self.base + offset) as *const u32) }
    }

    /// Writes `value` to the register at byte offset `offset`.
    pub fn write(self, offset: usize, value: u32) {
        // SAFETY: as for `read`.
        unsafe { core::ptr::write_volatile((self.base + offset) as *mut u32, value) }
    }

    /// Reads the whole bursts `dst` begins with (eight words each, one `ldm` and one `stm`)
    /// from the eight aliases of one FIFO port at `window`..`window + 32`; returns the bytes
    /// read (none unless `dst` is word-aligned): the caller reads the rest a word at a time.
    pub fn read_bursts(self, window: usize, dst: &mut [u8]) -> usize {
        let n = bursts(dst);
        if n > 0 {
            // SAFETY: `window` is the first of eight aliased registers of one FIFO port (the
            // LAN9118's receive data port; reading any of them pops the next word, in
            // address order for `ldm`). `dst` is writable and word-aligned and holds `n` x
            // 32 bytes (`bursts`); the registers named are declared clobbered.
            unsafe { burst_loop!("{src}", "{dst}!", self.base + window, dst.as_mut_ptr(), n) }
        }
        n * BURST
    }

    /// Writes the whole bursts `src` begins with (eight words each, one `ldm` and one `stm`)
    /// to the eight aliases of one FIFO port at `window`..`window + 32`; returns the bytes
    /// written (none unless `src` is word-aligned): the caller writes the rest a word at a
    /// time.
    pub fn write_bursts(self, window: usize, src: &[u8]) -> usize {
        let n = bursts(src);
        if n > 0 {
            // SAFETY: `window` is the first of eight aliased registers of one FIFO port (the
            // LAN9118's transmit data port; writing any of them pushes a word, in address
            // order for `stm`). `src` is readable and word-aligned and holds `n` x 32 bytes
            // (`bursts`); the registers named are declared clobbered.
            unsafe { burst_loop!("{src}!", "{dst}", src.as_ptr(), self.base + window, n) }
        }
        n * BURST
    }
}

/// Bytes of one burst: eight 32-bit words, as many as a FIFO port has aliases.
pub const BURST: usize = 32;

/// How many whole bursts `buf` begins with, if it is word-aligned (else none).
fn bursts(buf: &[u8]) -> usize {
    if (buf.as_ptr() as usize).is_multiple_of(4) {
        buf.len() / BURST
    } else {
        0
    }
}
