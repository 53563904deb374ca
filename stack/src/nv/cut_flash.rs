//! [`CutFlash`]: a simulated flash whose power can be cut after any number of erase and
//! program steps, to show that every interrupted save leaves a readable store.

use super::flash::{Flash, FlashError, MAX_WRITE_SIZE};
use super::IMAGE_SIZE;

/// Bytes of a [`CutFlash`] sector: a whole copy of the store.
pub const CUT_SECTOR: usize = MAX_WRITE_SIZE + IMAGE_SIZE;
/// Program unit of a [`CutFlash`].
const UNIT: usize = 4;

/// Flash whose power goes after a budget of steps (an erase, or one 4-byte program unit):
/// the step in progress is left half done (half the sector erased, half the unit
/// programmed) and every later operation fails until [`CutFlash::restore`].
#[derive(Debug, Clone)]
pub struct CutFlash {
    cells: [[u8; CUT_SECTOR]; 2],
    budget: Option<usize>,
    steps: usize,
    off: bool,
}

impl Default for CutFlash {
    fn default() -> Self {
        Self::new()
    }
}

impl CutFlash {
    /// Two erased sectors, powered with no cut to come.
    pub const fn new() -> Self {
        CutFlash {
            cells: [[0xFF; CUT_SECTOR]; 2],
            budget: None,
            steps: 0,
            off: false,
        }
    }
    /// The power goes after `steps` more steps.
    pub fn cut_after(&mut self, steps: usize) {
        self.budget = Some(steps);
    }
    /// Steps taken since the flash was made.
    pub fn steps(&self) -> usize {
        self.steps
    }
    /// Power back on, with no cut to come.
    pub fn restore(&mut self) {
        self.budget = None;
        self.off = false;
    }
    /// The cells of `sector`, e.g. to flip a bit in a test (`None` past sector 1).
    pub fn cells_mut(&mut self, sector: u8) -> Option<&mut [u8; CUT_SECTOR]> {
        self.cells.get_mut(usize::from(sector))
    }
    /// One step more; false (power gone) once the budget is spent.
    fn step(&mut self) -> bool {
        if self.off {
            return false;
        }
        self.steps = self.steps.saturating_add(1);
        match &mut self.budget {
            Some(0) => {
                self.off = true;
                false
            }
            Some(n) => {
                *n = n.saturating_sub(1);
                true
            }
            None => true,
        }
    }
    fn span(&mut self, sector: u8, offset: usize, len: usize) -> Result<&mut [u8], FlashError> {
        let end = offset.checked_add(len).ok_or(FlashError)?;
        self.cells
            .get_mut(usize::from(sector))
            .and_then(|s| s.get_mut(offset..end))
            .ok_or(FlashError)
    }
}

impl Flash for CutFlash {
    const SECTOR_SIZE: usize = CUT_SECTOR;
    const WRITE_SIZE: usize = UNIT;
    fn read(&mut self, sector: u8, offset: usize, buf: &mut [u8]) -> Result<(), FlashError> {
        if self.off {
            return Err(FlashError);
        }
        buf.copy_from_slice(self.span(sector, offset, buf.len())?);
        Ok(())
    }
    fn erase(&mut self, sector: u8) -> Result<(), FlashError> {
        let alive = self.step();
        let cells = self.span(sector, 0, CUT_SECTOR)?;
        if !alive {
            // Half erased: the first half of the sector only.
            cells
                .iter_mut()
                .take(CUT_SECTOR / 2)
                .for_each(|c| *c = 0xFF);
            return Err(FlashError);
        }
        cells.fill(0xFF);
        Ok(())
    }
    fn program(&mut self, sector: u8, offset: usize, data: &[u8]) -> Result<(), FlashError> {
        if !offset.is_multiple_of(UNIT) || !data.len().is_multiple_of(UNIT) {
            return Err(FlashError);
        }
        self.span(sector, offset, data.len())?;
        for (i, unit) in data.chunks(UNIT).enumerate() {
            let alive = self.step();
            // Inside the span checked above.
            let at = offset.saturating_add(i.saturating_mul(UNIT));
            let cells = self.span(sector, at, UNIT)?;
            // A cut unit gets its first two bytes only.
            let n = if alive { UNIT } else { UNIT / 2 };
            for (c, b) in cells.iter_mut().zip(unit).take(n) {
                *c &= *b;
            }
            if !alive {
                return Err(FlashError);
            }
        }
        Ok(())
    }
}
