//! The non-volatile copy of the parameters DRV.NVSAVE stores and a power-up loads: a small
//! trait so a board can put it in flash, and a RAM implementation for the simulation.

use super::params::TABLE;

/// One value per parameter of [`TABLE`] (commands and read-only ones hold 0).
pub type Image = [i64; TABLE.len()];

/// The storage could not save (DRV.NVSAVE answers 0x02, resource unavailable).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NvError;

/// Where DRV.NVSAVE keeps the parameter values.
pub trait NvStorage {
    /// The saved values, if a save happened.
    fn load(&self) -> Option<Image>;
    /// Saves `image`; an error refuses DRV.NVSAVE.
    fn save(&mut self, image: &Image) -> Result<(), NvError>;
    /// Forgets the saved values (factory defaults).
    fn clear(&mut self);
}

/// Non-volatile storage in RAM: survives an Identity Reset type 0, not a power cycle.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct RamNv {
    image: Option<Image>,
}

impl RamNv {
    /// Empty storage (factory defaults).
    pub const fn new() -> Self {
        RamNv { image: None }
    }
}

impl NvStorage for RamNv {
    fn load(&self) -> Option<Image> {
        self.image
    }
    fn save(&mut self, image: &Image) -> Result<(), NvError> {
        self.image = Some(*image);
        Ok(())
    }
    fn clear(&mut self) {
        self.image = None;
    }
}
