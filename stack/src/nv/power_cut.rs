//! The power-cut test: the store's flash ([`CutFlash`]) loses power at every erase and program
//! step, and the store must then boot with either the old or the new records.
//! (Test code only: `nv` declares it `#[cfg(test)]`.)

#[cfg(test)]
use super::*;

fn value(store: &mut AbStore<CutFlash>, key: u16) -> Option<Vec<u8, IMAGE_SIZE>> {
    let mut buf = [0u8; IMAGE_SIZE];
    let n = store.read(key, &mut buf).unwrap()?;
    Vec::from_slice(&buf[..n]).ok()
}

use heapless::Vec;

/// Saves `new` as record 1 from the state in `before`, cutting the power after every
/// possible number of steps; each boot after a cut must see record 1 old or new and
/// record 2 untouched.
fn cut_everywhere(before: &CutFlash, new: &[u8]) -> usize {
    let mut probe = AbStore::mount(before.clone());
    let old = value(&mut probe, 1);
    let other = value(&mut probe, 2);
    let start = probe.flash().steps();
    probe.write(1, new).unwrap();
    let steps = probe.flash().steps() - start;
    for cut in 0..steps {
        let mut flash = before.clone();
        flash.cut_after(cut);
        let mut store = AbStore::mount(flash);
        assert!(store.write(1, new).is_err(), "cut after {cut} of {steps}");
        let mut flash = store.into_flash();
        flash.restore();
        let mut booted = AbStore::mount(flash);
        let got = value(&mut booted, 1);
        assert!(
            got == old || got.as_deref() == Some(new),
            "cut after {cut} of {steps}: {got:?}"
        );
        assert_eq!(value(&mut booted, 2), other, "cut after {cut}");
        // And the store keeps working after the cut.
        booted.write(1, b"after").unwrap();
        let mut again = AbStore::mount(booted.into_flash());
        assert_eq!(value(&mut again, 1).as_deref(), Some(&b"after"[..]));
        assert_eq!(value(&mut again, 2), other);
    }
    steps
}

#[test]
fn every_power_cut_leaves_the_old_or_the_new_records() {
    let mut flash = CutFlash::new();
    // The first save ever: nothing before it.
    assert!(cut_everywhere(&flash, b"first") > 2);
    let mut store = AbStore::mount(flash);
    store.write(2, b"untouched").unwrap();
    for generation in 0..4u8 {
        flash = store.into_flash();
        let long = [generation; 200];
        cut_everywhere(&flash, &long);
        cut_everywhere(&flash, &[generation]);
        store = AbStore::mount(flash);
        store.write(1, &long).unwrap();
    }
    assert_eq!(store.sequence(), 5);
}

#[test]
fn saves_alternate_between_the_sectors() {
    let mut store = AbStore::mount(CutFlash::new());
    for i in 0..6u8 {
        store.write(1, &[i]).unwrap();
        let mut again = AbStore::mount(store.flash().clone());
        assert_eq!(value(&mut again, 1), Vec::from_slice(&[i]).ok());
    }
    // Three erases each.
    assert_eq!(store.sequence(), 6);
    assert_eq!(store.remove(1), Ok(()));
    assert_eq!(value(&mut AbStore::mount(store.into_flash()), 1), None);
}

#[test]
fn a_batch_is_one_save_and_an_abandoned_one_leaves_nothing() {
    let mut store = AbStore::mount(CutFlash::new());
    store.write(1, b"one").unwrap();
    store.write(2, b"two").unwrap();
    store.begin().unwrap();
    store.remove(1).unwrap();
    store.write(2, b"new").unwrap();
    // Reads see the batch; the flash does not yet.
    assert_eq!(value(&mut store, 1), None);
    assert_eq!(value(&mut store, 2).as_deref(), Some(&b"new"[..]));
    let mut restarted = AbStore::mount(store.flash().clone());
    assert_eq!(value(&mut restarted, 1).as_deref(), Some(&b"one"[..]));
    assert_eq!(store.sequence(), 2);
    store.commit().unwrap();
    assert_eq!(store.sequence(), 3, "one save for the batch");
    let mut restarted = AbStore::mount(store.flash().clone());
    assert_eq!(value(&mut restarted, 1), None);
    assert_eq!(value(&mut restarted, 2).as_deref(), Some(&b"new"[..]));
    // Abandoned: neither RAM nor flash keeps the changes.
    store.begin().unwrap();
    store.write(1, b"gone").unwrap();
    store.abandon();
    assert_eq!(value(&mut store, 1), None);
    assert_eq!(store.sequence(), 3);
    // An empty batch saves nothing; after a batch, writes save at once again.
    store.begin().unwrap();
    store.commit().unwrap();
    assert_eq!(store.sequence(), 3);
    store.write(1, b"now").unwrap();
    assert_eq!(store.sequence(), 4);
}

#[test]
fn a_corrupted_current_copy_falls_back_to_the_previous_one() {
    let mut store = AbStore::mount(CutFlash::new());
    store.write(1, b"old").unwrap();
    store.write(1, b"new").unwrap();
    let mut flash = store.into_flash();
    // The newer copy (sector 1) loses a bit of its records.
    flash.cells_mut(1).unwrap()[MAX_WRITE_SIZE + 12] ^= 0x01;
    assert_eq!(
        value(&mut AbStore::mount(flash), 1).as_deref(),
        Some(&b"old"[..])
    );
}

#[test]
fn ram_flash_and_full_store() {
    let mut store = AbStore::mount(RamFlash::<{ MAX_WRITE_SIZE + IMAGE_SIZE }>::new());
    assert_eq!(store.write(1, &[0; IMAGE_SIZE]), Err(NvError::NoSpace));
    store.write(1, b"kept").unwrap();
    let mut small = [0u8; 2];
    assert_eq!(store.read(1, &mut small), Err(NvError::BufferTooSmall));
    let mut store = AbStore::mount(store.into_flash());
    let mut buf = [0u8; 8];
    assert_eq!(store.read(1, &mut buf), Ok(Some(4)));
    assert_eq!(&buf[..4], b"kept");
}
