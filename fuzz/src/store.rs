//! The non-volatile store the fuzzed profiles keep their saved settings in: one per thread,
//! erased before every input, so each run starts from factory defaults and saves for real
//! (records, A/B copies, CRC) without leaking memory from run to run.

use std::cell::RefCell;

use enip_stack::nv::{AbStore, RamFlash, SharedStore, IMAGE_SIZE, MAX_WRITE_SIZE};

/// Flash of the fuzzed store.
type Flash = RamFlash<{ MAX_WRITE_SIZE + IMAGE_SIZE }>;

thread_local! {
    static STORE: &'static RefCell<AbStore<Flash>> =
        Box::leak(Box::new(RefCell::new(AbStore::mount(Flash::new()))));
}

/// The thread's store, erased: no record saved.
pub fn erased() -> SharedStore {
    STORE.with(|cell| {
        let cell: &'static RefCell<AbStore<Flash>> = cell;
        *cell.borrow_mut() = AbStore::mount(Flash::new());
        SharedStore::new(cell)
    })
}
