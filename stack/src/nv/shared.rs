//! [`SharedStore`]: one [`NvStore`] used by several owners of records (the adapter's TCP/IP
//! object and the device profile) from the one task that runs them both.

use core::cell::RefCell;

use super::{NvError, NvStore};

/// A handle to a store in a `RefCell`: each call borrows it for that call only, so owners
/// in one task never overlap; a call made while another is running fails with
/// [`NvError::Busy`] instead of panicking.
#[derive(Clone, Copy)]
pub struct SharedStore {
    cell: &'static RefCell<dyn NvStore>,
}

impl SharedStore {
    /// A handle to the store in `cell`.
    pub fn new(cell: &'static RefCell<dyn NvStore>) -> Self {
        SharedStore { cell }
    }
}

impl core::fmt::Debug for SharedStore {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("SharedStore")
    }
}

impl NvStore for SharedStore {
    fn read(&mut self, key: u16, buf: &mut [u8]) -> Result<Option<usize>, NvError> {
        let mut store = self.cell.try_borrow_mut().map_err(|_| NvError::Busy)?;
        store.read(key, buf)
    }
    fn write(&mut self, key: u16, value: &[u8]) -> Result<(), NvError> {
        let mut store = self.cell.try_borrow_mut().map_err(|_| NvError::Busy)?;
        store.write(key, value)
    }
    fn remove(&mut self, key: u16) -> Result<(), NvError> {
        let mut store = self.cell.try_borrow_mut().map_err(|_| NvError::Busy)?;
        store.remove(key)
    }
    fn begin(&mut self) -> Result<(), NvError> {
        let mut store = self.cell.try_borrow_mut().map_err(|_| NvError::Busy)?;
        store.begin()
    }
    fn commit(&mut self) -> Result<(), NvError> {
        let mut store = self.cell.try_borrow_mut().map_err(|_| NvError::Busy)?;
        store.commit()
    }
    fn abandon(&mut self) {
        if let Ok(mut store) = self.cell.try_borrow_mut() {
            store.abandon();
        }
    }
}
