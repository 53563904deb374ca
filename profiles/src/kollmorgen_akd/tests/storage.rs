//! DRV.NVSAVE and the non-volatile copy: across Identity Resets, across restarts on one
//! store, and every power cut during a save or a factory reset.

use super::*;

#[test]
fn nvsave_survives_a_reset_and_factory_reset_clears_it() {
    let mut b = Bench::new();
    let set = |b: &mut Bench, i: u16, d: &[u8]| b.explicit(0x10, 0x0F, i, Some(1), d).0.unwrap();
    set(&mut b, id::EIP_POSUNIT, &1000u32.to_le_bytes());
    set(&mut b, 1, &1234u32.to_le_bytes());
    set(&mut b, id::DRV_NVSAVE, &[1]);
    set(&mut b, 1, &1u32.to_le_bytes());
    b.akd.reset(0).unwrap();
    let get = |b: &mut Bench, i: u16| b.explicit(0x0E, 0x0F, i, Some(1), &[]).1;
    assert_eq!(get(&mut b, 1), 1234u32.to_le_bytes());
    assert_eq!(get(&mut b, id::EIP_POSUNIT), 1000u32.to_le_bytes());
    b.akd.reset(1).unwrap();
    assert_eq!(get(&mut b, 1), 5_000_000u32.to_le_bytes());
}

/// Parameter 1 as a fresh drive powered up from `store` reads it.
fn parameter_1_after_power_up(store: SharedStore) -> Vec<u8> {
    let mut akd = KollmorgenAkd::with_storage(NvCopy::in_store(store));
    execute(&mut akd, &request(0x0E, 0x0F, 1, Some(1), &[]), 0).1
}

/// Sets parameter 1 to `value` and saves with DRV.NVSAVE; true if both succeeded.
fn set_and_save(store: SharedStore, value: u32) -> bool {
    let mut akd = KollmorgenAkd::with_storage(NvCopy::in_store(store));
    let mut ok = |i: u16, d: &[u8]| execute(&mut akd, &request(0x10, 0x0F, i, Some(1), d), 0).0;
    ok(1, &value.to_le_bytes()).is_ok() && ok(id::DRV_NVSAVE, &[1]).is_ok()
}

#[test]
fn nvsave_survives_a_restart_in_the_store() {
    let store = testing::store();
    assert!(set_and_save(store, 1234));
    assert_eq!(parameter_1_after_power_up(store), 1234u32.to_le_bytes());
    let mut akd = KollmorgenAkd::with_storage(NvCopy::in_store(store));
    akd.reset(1).unwrap();
    assert_eq!(
        parameter_1_after_power_up(store),
        5_000_000u32.to_le_bytes()
    );
    // A store that cannot write refuses DRV.NVSAVE.
    let mut dead = CutFlash::new();
    dead.cut_after(0);
    assert!(!set_and_save(testing::store_on(dead).0, 7));
}

#[test]
fn every_power_cut_during_nvsave_keeps_the_old_or_the_new_parameters() {
    let steps = testing::every_power_cut(
        |store| assert!(set_and_save(store, 1234)),
        |store| set_and_save(store, 4321),
        parameter_1_after_power_up,
    );
    assert!(steps > 50, "{steps} steps");
}

/// Sends `bytes` to an adapter of a drive powered up from `store`, with the store attached
/// to the adapter too; whether it succeeded.
fn execute_on_store(store: SharedStore, bytes: &[u8]) -> bool {
    let mut akd = KollmorgenAkd::with_storage(NvCopy::in_store(store));
    execute_with_store(&mut akd, Some(store), bytes, 0)
        .0
        .is_ok()
}

/// Identity Reset type 1 (factory defaults) through the adapter.
fn factory_reset(store: SharedStore) -> bool {
    execute_on_store(store, &request(0x05, 0x01, 1, None, &[1]))
}

#[test]
fn every_power_cut_during_a_factory_reset_keeps_the_parameters_and_the_address_together() {
    use enip_stack::objects::TcpIpState;
    let host_name = request(0x10, 0xF5, 1, Some(6), &[4, 0, b'a', b'k', b'd', b'1']);
    let steps = testing::every_power_cut(
        |store| {
            assert!(set_and_save(store, 1234));
            assert!(execute_on_store(store, &host_name));
        },
        factory_reset,
        |mut store| {
            let tcpip = TcpIpState::stored(&mut store).ok().flatten().is_some();
            (parameter_1_after_power_up(store), tcpip)
        },
    );
    // One save: the erase, the copy's header and CRC (3 units), the commit word.
    assert_eq!(steps, 5);
}
