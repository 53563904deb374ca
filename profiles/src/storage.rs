//! [`Saved`]: a profile's saved settings (the PositionServo's EPM copy, the AKD's
//! DRV.NVSAVE parameters, the Ametek's NVRAM program) in RAM and, once the board hands the
//! profile the adapter's non-volatile store ([`enip_stack::nv`]), as one record of that store:
//! the same store, A/B copies and CRC as the TCP/IP object's settings, so a power cut during a
//! save leaves the previous settings, and a restart finds them.
//!
//! Each profile that saves something says what in its own `storage.rs`: a type implementing
//! [`Record`] (its bytes and its [`key`]), kept in a [`Saved`].

use enip_stack::nv::{NvError, NvStore, SharedStore, PROFILE_RECORD_ROOM};

/// The profiles' record keys in the adapter's store, from the stack's
/// [`enip_stack::nv::key::PROFILE_BASE`] up (the stack's own records are below it).
pub mod key {
    use enip_stack::nv::key::PROFILE_BASE;

    /// The PositionServo profile's EPM copy of its variables.
    pub const POSITION_SERVO_EPM: u16 = PROFILE_BASE;
    /// The Kollmorgen AKD profile's parameters saved by DRV.NVSAVE.
    pub const KOLLMORGEN_AKD_PARAMETERS: u16 = PROFILE_BASE + 1;
    /// The Ametek PLS profile's program saved to NVRAM.
    pub const AMETEK_PLS_PROGRAM: u16 = PROFILE_BASE + 2;
}

/// Settings a profile saves as one record of exactly `N` bytes.
pub trait Record<const N: usize>: Sized {
    /// The record's key in the store (one of [`key`]).
    const KEY: u16;
    /// The record's bytes.
    fn encode(&self) -> [u8; N];
    /// The settings a record holds.
    fn decode(bytes: &[u8; N]) -> Self;
}

/// Saved settings `T` (a record of `N` bytes): in RAM and, given the adapter's store
/// ([`Saved::in_store`]), in record `T::KEY` there. Without a store they survive an
/// Identity Reset type 0, not a power cycle.
#[derive(Debug, Clone)]
pub struct Saved<T, const N: usize> {
    value: Option<T>,
    store: Option<SharedStore>,
}

impl<T: Record<N>, const N: usize> Saved<T, N> {
    /// The record must fit in the store beside the TCP/IP settings.
    const FITS: () = assert!(
        N <= PROFILE_RECORD_ROOM,
        "a profile's record must fit in the store beside the TCP/IP settings"
    );

    /// Nothing saved, and no store: the profile powers up with its defaults.
    pub const fn new() -> Self {
        Saved {
            value: None,
            store: None,
        }
    }

    /// The settings saved in `store` (none, or a record of another size, which this build
    /// did not write: the defaults hold), saved there from now on.
    pub fn in_store(store: SharedStore) -> Self {
        #[allow(clippy::let_unit_value)]
        let () = Self::FITS;
        let mut bytes = [0u8; N];
        let value = match { store }.read(T::KEY, &mut bytes) {
            Ok(Some(n)) if n == N => Some(T::decode(&bytes)),
            _ => None,
        };
        Saved {
            value,
            store: Some(store),
        }
    }

    /// The saved settings, if any.
    pub fn load(&self) -> Option<&T> {
        self.value.as_ref()
    }

    /// Saves `value` in place of the settings saved before, all or nothing: if the store
    /// refuses, the previous settings stay.
    pub fn save(&mut self, value: T) -> Result<(), NvError> {
        if let Some(mut store) = self.store {
            store.write(T::KEY, &value.encode())?;
        }
        self.value = Some(value);
        Ok(())
    }

    /// Forgets the saved settings (factory defaults).
    pub fn clear(&mut self) -> Result<(), NvError> {
        if let Some(mut store) = self.store {
            store.remove(T::KEY)?;
        }
        self.value = None;
        Ok(())
    }
}

impl<T: Record<N>, const N: usize> Default for Saved<T, N> {
    fn default() -> Self {
        Self::new()
    }
}

/// Two copies are equal when they hold the same settings (where they are saved is not
/// compared).
impl<T: PartialEq, const N: usize> PartialEq for Saved<T, N> {
    fn eq(&self, other: &Self) -> bool {
        self.value == other.value
    }
}

impl<T: Eq, const N: usize> Eq for Saved<T, N> {}

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
