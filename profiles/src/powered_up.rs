//! [`PoweredUp`]: a shipped profile built at power-up from what the board's non-volatile
//! store holds, so a board can hand its store to whichever profile it was built with.

use enip_stack::nv::SharedStore;

/// A profile that powers up from a non-volatile store and keeps its saved settings there
/// (PositionServo EPM, AKD DRV.NVSAVE parameters, Ametek NVRAM program, each one record);
/// the profiles with nothing to save ignore the store.
pub trait PoweredUp {
    /// The profile as it powers up with `store`.
    fn powered_up(store: SharedStore) -> Self;
}

#[cfg(feature = "generic")]
impl PoweredUp for super::Generic {
    fn powered_up(_store: SharedStore) -> Self {
        Self::new()
    }
}

#[cfg(feature = "parker-ipa")]
impl PoweredUp for super::ParkerIpa {
    fn powered_up(_store: SharedStore) -> Self {
        Self::new()
    }
}

#[cfg(feature = "position-servo")]
impl PoweredUp for super::PositionServo {
    fn powered_up(store: SharedStore) -> Self {
        Self::with_storage(super::position_servo::storage::EpmCopy::in_store(store))
    }
}

#[cfg(feature = "kollmorgen-akd")]
impl PoweredUp for super::KollmorgenAkd {
    fn powered_up(store: SharedStore) -> Self {
        Self::with_storage(super::kollmorgen_akd::storage::NvCopy::in_store(store))
    }
}

#[cfg(feature = "ametek-pls")]
impl PoweredUp for super::AmetekPls {
    fn powered_up(store: SharedStore) -> Self {
        Self::with_storage(super::ametek_pls::storage::Nvram::in_store(store))
    }
}
