//! The CIP Security settings' record in the non-volatile store ([`key::SECURITY`]): the two
//! objects' states once configured, the TLS settings in use and the Certificate Management
//! instances created. A configuration in progress is never stored: a restart finds the last
//! applied one.

use super::cert_mgmt::{CertInstance, MAX_CERTS, MAX_CERT_NAME};
use super::{ObjectMode, SecurityState, TlsSettings, AVAILABLE_SUITES};
use crate::nv::{key, NvError, NvStore};
use crate::wire::{Reader, Writer};

/// Layout version of the record.
const VERSION: u8 = 1;
/// The longest record without a pre-shared key: header, flags, instances, suites, and every
/// created instance with the longest name; it always fits.
const RECORD_MAX_NO_PSK: usize =
    9 + 2 * AVAILABLE_SUITES.len() + 1 + (MAX_CERTS - 1) * (3 + MAX_CERT_NAME);
const _: () = assert!(RECORD_MAX_NO_PSK <= crate::nv::SECURITY_RECORD_ROOM);
/// The longest record stored: with a pre-shared key (3 bytes and its identity and key) it
/// may not fit beside three created instances with long names, and then is not saved
/// (the store's room is fixed, [`crate::nv::IMAGE_SIZE`]).
pub(crate) const RECORD_MAX: usize = crate::nv::SECURITY_RECORD_ROOM;

/// Attribute 9, 10 and 11 as bits of one byte.
const VERIFY_CLIENT: u8 = 1 << 0;
const SEND_CHAIN: u8 = 1 << 1;
const CHECK_EXPIRATION: u8 = 1 << 2;
/// TCP/IP attribute 14: 44818/tcp closed.
const PLAIN_TCP_CLOSED: u8 = 1 << 3;
/// A pre-shared key follows the instances.
const PSK_FOLLOWS: u8 = 1 << 4;

/// Loads the stored settings into `st` (in use at once); false if there are none or they are
/// unreadable (the factory defaults hold).
pub(crate) fn load(st: &mut SecurityState, store: &mut dyn NvStore) -> bool {
    let loaded = crate::nv::read_decoded::<RECORD_MAX, _>(store, key::SECURITY, "security", decode);
    let Ok(Some(stored)) = loaded else {
        return false;
    };
    let (cip_mode, profiles, eip_mode, active, certs, closed) = stored;
    st.plain_tcp_closed = closed;
    st.cip_mode = cip_mode;
    st.profiles_configured = profiles;
    st.eip_mode = eip_mode;
    st.pending = active.clone();
    st.active = active;
    st.certs = certs;
    true
}

/// Saves the configured part of `st` in `store`.
pub(crate) fn save(st: &SecurityState, store: &mut dyn NvStore) -> Result<(), NvError> {
    let mut buf = [0u8; RECORD_MAX];
    let mut w = Writer::new(&mut buf);
    encode(st, &mut w).map_err(|_| NvError::NoSpace)?;
    let len = w.len();
    store.write(key::SECURITY, buf.get(..len).unwrap_or(&[]))
}

/// A mode as stored: a session in progress counts as the state it began from.
fn settled(mode: ObjectMode) -> ObjectMode {
    match mode {
        ObjectMode::InProgress => ObjectMode::FactoryDefault,
        m => m,
    }
}

fn encode(st: &SecurityState, w: &mut Writer<'_>) -> crate::wire::Result<()> {
    let a = &st.active;
    w.u8(VERSION)?;
    w.u8(settled(st.cip_mode) as u8)?;
    w.u16(st.profiles_configured)?;
    w.u8(settled(st.eip_mode) as u8)?;
    let bit = |on: bool, b: u8| if on { b } else { 0 };
    let flags = bit(a.verify_client, VERIFY_CLIENT)
        | bit(a.send_chain, SEND_CHAIN)
        | bit(a.check_expiration, CHECK_EXPIRATION)
        | bit(st.plain_tcp_closed, PLAIN_TCP_CLOSED)
        | bit(a.psk.is_some(), PSK_FOLLOWS);
    w.u8(flags)?;
    w.u8(a.active_cert.unwrap_or(0))?;
    w.u8(a.trusted_ca.unwrap_or(0))?;
    w.u8(a.allowed.len() as u8)?;
    for s in &a.allowed {
        w.u16(*s)?;
    }
    let created = st
        .certs
        .iter()
        .enumerate()
        .skip(1)
        .filter(|(_, c)| c.exists);
    w.u8(created.clone().count() as u8)?;
    for (i, c) in created {
        w.u8(i.saturating_add(1) as u8)?;
        w.u8(c.encoding)?;
        w.u8(c.name.len() as u8)?;
        w.bytes(&c.name)?;
    }
    if let Some(k) = &a.psk {
        w.u8(k.identity.len() as u8)?;
        w.bytes(&k.identity)?;
        w.u8(k.key.len() as u8)?;
        w.bytes(&k.key)?;
        w.u8(k.usage)?;
    }
    Ok(())
}

type Stored = (
    ObjectMode,
    u16,
    ObjectMode,
    TlsSettings,
    [CertInstance; MAX_CERTS],
    bool,
);

fn mode(b: u8) -> Option<ObjectMode> {
    Some(match b {
        0 => ObjectMode::FactoryDefault,
        2 => ObjectMode::Configured,
        3 => ObjectMode::Incomplete,
        _ => return None,
    })
}

fn instance(b: u8) -> Option<Option<u8>> {
    match b {
        0 => Some(None),
        1..=MAX_CERTS_U8 => Some(Some(b)),
        _ => None,
    }
}

const MAX_CERTS_U8: u8 = MAX_CERTS as u8;

/// A stored record; `None` if malformed or out of range.
fn decode(bytes: &[u8]) -> Option<Stored> {
    let mut r = Reader::new(bytes);
    if r.u8().ok()? != VERSION {
        return None;
    }
    let cip_mode = mode(r.u8().ok()?)?;
    let profiles = r.u16().ok()?;
    let eip_mode = mode(r.u8().ok()?).filter(|m| *m != ObjectMode::Incomplete)?;
    let flags = r.u8().ok()?;
    let mut active = TlsSettings {
        allowed: heapless::Vec::new(),
        active_cert: instance(r.u8().ok()?)?,
        trusted_ca: instance(r.u8().ok()?)?,
        verify_client: flags & VERIFY_CLIENT != 0,
        send_chain: flags & SEND_CHAIN != 0,
        check_expiration: flags & CHECK_EXPIRATION != 0,
        psk: None,
    };
    for _ in 0..r.u8().ok()? {
        let s = r.u16().ok()?;
        if !AVAILABLE_SUITES.contains(&s) || active.allowed.contains(&s) {
            return None;
        }
        active.allowed.push(s).ok()?;
    }
    let mut certs = super::cert_mgmt::factory_instances();
    for _ in 0..r.u8().ok()? {
        let i = usize::from(r.u8().ok()?)
            .checked_sub(1)
            .filter(|i| *i >= 1)?;
        let encoding = r.u8().ok()?;
        let len = usize::from(r.u8().ok()?);
        let name = r.take(len).ok()?;
        let c = certs.get_mut(i)?;
        *c = CertInstance::created(name, encoding)?;
    }
    if flags & PSK_FOLLOWS != 0 {
        let n = usize::from(r.u8().ok()?);
        let identity = heapless::Vec::from_slice(r.take(n).ok()?).ok()?;
        let n = usize::from(r.u8().ok()?);
        let key = heapless::Vec::from_slice(r.take(n).ok()?).ok()?;
        let usage = r.u8().ok()?;
        active.psk = Some(super::Psk {
            identity,
            key,
            usage,
        });
    }
    if r.remaining() != 0 {
        return None;
    }
    let closed = flags & PLAIN_TCP_CLOSED != 0;
    Some((cip_mode, profiles, eip_mode, active, certs, closed))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nv::{AbStore, RamFlash, IMAGE_SIZE, MAX_WRITE_SIZE};

    #[test]
    fn settings_and_instances_round_trip_and_bad_records_are_not_believed() {
        let mut store = AbStore::mount(RamFlash::<{ MAX_WRITE_SIZE + IMAGE_SIZE }>::new());
        let mut st = SecurityState::new();
        assert!(!load(&mut st, &mut store));
        st.cip_mode = ObjectMode::Configured;
        st.profiles_configured = super::super::PROFILE_CONFIDENTIALITY;
        st.eip_mode = ObjectMode::Configured;
        st.active.allowed = heapless::Vec::from_slice(&[0xC02C, 0xC023]).unwrap();
        st.active.verify_client = true;
        st.active.check_expiration = true;
        st.certs[2] = CertInstance::created(&[b'x'; MAX_CERT_NAME], 0).unwrap();
        st.active.trusted_ca = Some(3);
        st.plain_tcp_closed = true;
        st.active.psk = Some(super::super::Psk {
            identity: heapless::Vec::from_slice(b"plant-1").unwrap(),
            key: heapless::Vec::from_slice(&[0x5A; 32]).unwrap(),
            usage: 4,
        });
        save(&st, &mut store).unwrap();
        let mut store = AbStore::mount(store.into_flash());
        let mut back = SecurityState::new();
        assert!(load(&mut back, &mut store));
        assert_eq!(back.active, st.active);
        assert_eq!(back.certs, st.certs);
        assert!(back.plain_tcp_closed);
        assert_eq!((back.cip_mode, back.eip_mode), (st.cip_mode, st.eip_mode));
        // A suite not available, a duplicate, a trailing byte, another version: defaults.
        for bad in [
            &[1, 2, 2, 0, 2, 0, 1, 0, 1, 0x3C, 0x00, 0][..],
            &[1, 2, 2, 0, 2, 0, 1, 0, 2, 0x23, 0xC0, 0x23, 0xC0, 0],
            &[1, 2, 2, 0, 2, 0, 1, 0, 1, 0x23, 0xC0, 0, 0],
            &[2, 2, 2, 0, 2, 0, 1, 0, 1, 0x23, 0xC0, 0],
        ] {
            store.write(key::SECURITY, bad).unwrap();
            assert!(!load(&mut SecurityState::new(), &mut store), "{bad:?}");
        }
        store
            .write(key::SECURITY, &[1, 2, 2, 0, 2, 0, 1, 0, 1, 0x23, 0xC0, 0])
            .unwrap();
        assert!(load(&mut SecurityState::new(), &mut store));
    }
}
