//! The non-volatile record decoders of the TCP/IP, LLDP Management, QoS, Address Conflict
//! Detection and CIP Security settings: the input's first byte picks the record, the rest is stored as its
//! value in an erased store and read back by the object's `stored`. Whatever it decodes to
//! must save and read back as the same settings (a record the device wrote itself is never
//! refused), and nothing that is not a valid record may panic.
#![no_main]

use enip_fuzz::store;
use enip_stack::acd::AcdSettings;
use enip_stack::nv::{key, NvStore};
use enip_stack::objects::security::SecurityState;
use enip_stack::objects::{LldpConfig, QosState, TcpIpState};
use libfuzzer_sys::fuzz_target;

/// Decodes, and if that gave settings, saves them and decodes them again.
fn round_trip<T: PartialEq + std::fmt::Debug>(
    s: &mut dyn NvStore,
    stored: fn(&mut dyn NvStore) -> Result<Option<T>, enip_stack::nv::NvError>,
    save: fn(&T, &mut dyn NvStore) -> Result<(), enip_stack::nv::NvError>,
) {
    let first = stored(s).expect("the store reads");
    if let Some(v) = first {
        save(&v, s).expect("settings decoded from a record save again");
        let again = stored(s).expect("the store reads");
        assert_eq!(
            again.as_ref(),
            Some(&v),
            "saved settings read back the same"
        );
    }
}

fuzz_target!(|data: &[u8]| {
    let Some((&which, value)) = data.split_first() else {
        return;
    };
    let mut s = store::erased();
    let keys = [key::TCP_IP, key::LLDP, key::QOS, key::ACD, key::SECURITY];
    let key = keys[usize::from(which) % keys.len()];
    if s.write(key, value).is_err() {
        // Longer than the record's room: refused by the store, nothing to read.
        return;
    }
    match key {
        key::TCP_IP => round_trip(&mut s, TcpIpState::stored, TcpIpState::save),
        key::LLDP => round_trip(&mut s, LldpConfig::stored, LldpConfig::save),
        key::QOS => round_trip(&mut s, QosState::stored, QosState::save),
        key::SECURITY => round_trip(&mut s, SecurityState::stored, SecurityState::save),
        _ => round_trip(&mut s, AcdSettings::stored, AcdSettings::save),
    }
});
