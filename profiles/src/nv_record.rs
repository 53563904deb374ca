//! [`Record`]: a profile's saved settings as one record of the adapter's non-volatile store
//! ([`enip_stack::nv`]): the same store, A/B copies and CRC as the TCP/IP object's settings,
//! so a power cut during a save leaves the previous settings, and a restart finds them.

use enip_stack::nv::{NvError, NvStore, SharedStore};

/// Record `key` of a shared store.
#[derive(Debug, Clone, Copy)]
pub struct Record {
    store: SharedStore,
    key: u16,
}

impl Record {
    /// Record `key` (one of [`enip_stack::nv::key`]) of `store`.
    pub const fn new(store: SharedStore, key: u16) -> Self {
        Record { store, key }
    }

    /// The record's bytes if it holds exactly `N` of them (anything else: none saved, or a
    /// layout this build does not know, and the defaults hold).
    pub fn load<const N: usize>(&self) -> Option<[u8; N]> {
        let mut store = self.store;
        let mut buf = [0u8; N];
        match store.read(self.key, &mut buf) {
            Ok(Some(n)) if n == N => Some(buf),
            _ => None,
        }
    }

    /// Replaces the record with `bytes`, all or nothing.
    pub fn save(&self, bytes: &[u8]) -> Result<(), NvError> {
        let mut store = self.store;
        store.write(self.key, bytes)
    }

    /// Removes the record (factory defaults).
    pub fn clear(&self) -> Result<(), NvError> {
        let mut store = self.store;
        store.remove(self.key)
    }
}

/// Stores for the profiles' tests, and the power-cut check of a profile's record.
#[cfg(all(
    test,
    any(
        feature = "position-servo",
        feature = "kollmorgen-akd",
        feature = "ametek-pls"
    )
))]
pub(crate) mod testing {
    use core::cell::RefCell;
    use core::fmt::Debug;

    extern crate std;
    use std::boxed::Box;

    use enip_stack::nv::{AbStore, CutFlash, SharedStore};

    /// A store over `flash` (leaked: a test's store lives as long as the test).
    pub(crate) fn store_on(flash: CutFlash) -> (SharedStore, &'static RefCell<AbStore<CutFlash>>) {
        let cell: &'static RefCell<AbStore<CutFlash>> =
            Box::leak(Box::new(RefCell::new(AbStore::mount(flash))));
        (SharedStore::new(cell), cell)
    }

    /// A store over erased flash.
    pub(crate) fn store() -> SharedStore {
        store_on(CutFlash::new()).0
    }

    /// The flash of `cell` as a restart finds it: powered again.
    fn restarted(cell: &RefCell<AbStore<CutFlash>>) -> CutFlash {
        let mut flash = cell.borrow().flash().clone();
        flash.restore();
        flash
    }

    /// `prepare` saves the old settings, `save` the new ones (true if it succeeded) and
    /// `observe` powers a profile up from a store and reads its settings. The power is cut
    /// at every step of `save`; each time, the restarted profile must see exactly the old
    /// or the new settings. Returns the number of steps `save` takes.
    pub(crate) fn every_power_cut<T: PartialEq + Debug>(
        prepare: impl Fn(SharedStore),
        save: impl Fn(SharedStore) -> bool,
        observe: impl Fn(SharedStore) -> T,
    ) -> usize {
        let (store, cell) = store_on(CutFlash::new());
        prepare(store);
        let before = restarted(cell);
        let old = observe(store_on(before.clone()).0);
        let (probe, probe_cell) = store_on(before.clone());
        assert!(save(probe), "the save fails without a power cut");
        let steps = probe_cell.borrow().flash().steps() - before.steps();
        let new = observe(store_on(restarted(probe_cell)).0);
        assert_ne!(old, new, "the save changes nothing to observe");
        for cut in 0..steps {
            let mut flash = before.clone();
            flash.cut_after(cut);
            let (store, cell) = store_on(flash);
            assert!(
                !save(store),
                "cut after {cut} of {steps} steps: the save succeeded"
            );
            let seen = observe(store_on(restarted(cell)).0);
            assert!(
                seen == old || seen == new,
                "cut after {cut} of {steps} steps: {seen:?}, neither {old:?} nor {new:?}"
            );
        }
        steps
    }
}
