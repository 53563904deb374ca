//! Memory-mapped register blocks: the only raw pointer access of the board.

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
}
