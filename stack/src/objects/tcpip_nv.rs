//! The TCP/IP object's settings that survive a power cycle: attribute 5's interface
//! configuration and its validity rules, and the [`crate::nv`] record holding attributes 3,
//! 5, 6, 8, 9 and 13.

use core::net::Ipv4Addr;

use super::tcpip::{valid_mcast, TcpIpState};
use crate::cip::encoding::{ip, padded_string};
use crate::cip::status::{CipResult, General};
use crate::config::{MAX_DOMAIN_NAME, MAX_HOST_NAME};
use crate::device::MulticastConfig;
use crate::nv::{key, NvError, NvStore};
use crate::wire::bytes::{get_u16, get_u32};
use crate::wire::{Reader, Writer};

/// Bytes of attribute 5 before the domain name: address, mask, gateway, two name servers.
pub const INTERFACE_FIXED: u16 = 20;
/// Layout version of the stored record: 2 adds attributes 8 and 9 to version 1's.
const RECORD_VERSION: u8 = 2;
/// Largest stored record.
pub(crate) const RECORD_MAX: usize =
    1 + 4 + 20 + 1 + MAX_DOMAIN_NAME + 1 + MAX_HOST_NAME + 2 + 1 + 8;
const _: () = assert!(RECORD_MAX <= crate::nv::TCP_IP_RECORD_ROOM);

/// Attribute 5: the interface configuration (all zero: none configured).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InterfaceConfig {
    /// IP address.
    pub ip: Ipv4Addr,
    /// Network mask.
    pub netmask: Ipv4Addr,
    /// Default gateway (0.0.0.0: none).
    pub gateway: Ipv4Addr,
    /// Primary and secondary name servers (0.0.0.0: none).
    pub dns: [Ipv4Addr; 2],
    /// Default domain name.
    pub domain: heapless::Vec<u8, MAX_DOMAIN_NAME>,
}

impl InterfaceConfig {
    /// None configured: every address 0.0.0.0, no domain name.
    pub const NONE: InterfaceConfig = InterfaceConfig {
        ip: Ipv4Addr::UNSPECIFIED,
        netmask: Ipv4Addr::UNSPECIFIED,
        gateway: Ipv4Addr::UNSPECIFIED,
        dns: [Ipv4Addr::UNSPECIFIED; 2],
        domain: heapless::Vec::new(),
    };

    /// Parses a Set value (20 bytes and a padded STRING, length already checked) and
    /// checks it: 0x09 for an address that cannot be this interface's.
    pub fn parse(value: &[u8]) -> CipResult<Self> {
        let at = |i: usize| Ipv4Addr::from(get_u32(value, i.saturating_mul(4)));
        let fixed = usize::from(INTERFACE_FIXED);
        let len = usize::from(get_u16(value, fixed));
        let name = value
            .get(fixed.saturating_add(2)..fixed.saturating_add(2).saturating_add(len))
            .ok_or(General::NotEnoughData)?;
        let config = InterfaceConfig {
            ip: at(0),
            netmask: at(1),
            gateway: at(2),
            dns: [at(3), at(4)],
            domain: heapless::Vec::from_slice(name).map_err(|_| General::InvalidAttributeValue)?,
        };
        if !config.is_valid() {
            return Err(General::InvalidAttributeValue.into());
        }
        Ok(config)
    }

    /// True if nothing is configured (address 0.0.0.0).
    pub fn is_none(&self) -> bool {
        self.ip.is_unspecified()
    }

    /// The rules of a Set: a unicast address that is neither the subnet's network nor its
    /// broadcast address, a contiguous mask of 1 to 30 bits, a gateway that is none or a
    /// unicast address on the subnet other than the interface's, name servers none or
    /// unicast, a domain name of letters, digits, '-' and '.'.
    pub fn is_valid(&self) -> bool {
        let mask = u32::from(self.netmask);
        let contiguous = mask != 0 && (!mask) & (!mask).wrapping_add(1) == 0;
        if !contiguous || mask.count_ones() > 30 || !host_on(self.ip, mask) {
            return false;
        }
        let gateway = self.gateway.is_unspecified()
            || (self.gateway != self.ip
                && host_on(self.gateway, mask)
                && u32::from(self.gateway) & mask == u32::from(self.ip) & mask);
        let dns = self.dns.iter().all(|d| d.is_unspecified() || unicast(*d));
        gateway && dns && valid_domain_name(&self.domain)
    }

    /// Writes the attribute 5 value.
    pub(crate) fn write(&self, w: &mut Writer<'_>) -> CipResult {
        for a in [
            self.ip,
            self.netmask,
            self.gateway,
            self.dns[0],
            self.dns[1],
        ] {
            ip(w, a)?;
        }
        padded_string(w, &self.domain)?;
        Ok(())
    }
}

/// A unicast address: not 0.0.0.0/8, loopback, multicast, reserved or broadcast.
fn unicast(a: Ipv4Addr) -> bool {
    let first = a.octets()[0];
    first != 0 && first != 127 && first < 224
}

/// A unicast address whose host part on `mask` is neither all zeros nor all ones.
fn host_on(a: Ipv4Addr, mask: u32) -> bool {
    let host = u32::from(a) & !mask;
    unicast(a) && host != 0 && host != !mask
}

/// A host name (attribute 6): none, or one RFC 1123 label (the host part alone).
pub(crate) fn valid_host_name(name: &[u8]) -> bool {
    name.is_empty() || valid_label(name)
}

/// A domain name (attribute 5): none, or RFC 1123 labels joined by single dots.
pub(crate) fn valid_domain_name(name: &[u8]) -> bool {
    name.is_empty() || name.split(|c| *c == b'.').all(valid_label)
}

/// An RFC 1123 label: 1 to 63 letters, digits and hyphens, neither first nor last a hyphen.
fn valid_label(label: &[u8]) -> bool {
    (1..=63).contains(&label.len())
        && label
            .iter()
            .all(|c| c.is_ascii_alphanumeric() || *c == b'-')
        && label.first() != Some(&b'-')
        && label.last() != Some(&b'-')
}

impl TcpIpState {
    /// The settings stored in `store` over the factory defaults; `None` if there are none
    /// (or they are unreadable, longer than its largest record too: logged, and the defaults hold).
    pub fn stored(store: &mut dyn NvStore) -> Result<Option<TcpIpState>, NvError> {
        crate::nv::read_decoded::<RECORD_MAX, _>(store, key::TCP_IP, "TCP/IP", |b| {
            let mut state = TcpIpState::new();
            state.decode(b).map(|()| state)
        })
    }

    /// Stores attributes 3, 5, 6, 8, 9 and 13 in `store`.
    pub fn save(&self, store: &mut dyn NvStore) -> Result<(), NvError> {
        let mut buf = [0u8; RECORD_MAX];
        let mut w = Writer::new(&mut buf);
        self.encode(&mut w).map_err(|_| NvError::NoSpace)?;
        let len = w.len();
        store.write(key::TCP_IP, buf.get(..len).unwrap_or(&[]))
    }

    /// The interface configuration to start with: the stored one when configuration
    /// control (attribute 3) says static and one is configured.
    pub fn static_interface(&self) -> Option<&InterfaceConfig> {
        (self.config_control & 0x0F == 0 && !self.interface.is_none()).then_some(&self.interface)
    }

    fn encode(&self, w: &mut Writer<'_>) -> crate::wire::Result<()> {
        let i = &self.interface;
        w.u8(RECORD_VERSION)?;
        w.u32(self.config_control)?;
        for a in [i.ip, i.netmask, i.gateway, i.dns[0], i.dns[1]] {
            w.u32(u32::from(a))?;
        }
        w.u8(i.domain.len() as u8)?;
        w.bytes(&i.domain)?;
        w.u8(self.host_name.len() as u8)?;
        w.bytes(&self.host_name)?;
        w.u16(self.inactivity_timeout_s)?;
        w.u8(self.ttl)?;
        w.u8(self.mcast.alloc_control)?;
        w.u16(self.mcast.num_mcast)?;
        w.u32(u32::from(self.mcast.start))
    }

    /// Reads a stored record into `self`; `None` (and `self` partly changed) if malformed.
    fn decode(&mut self, bytes: &[u8]) -> Option<()> {
        let mut r = Reader::new(bytes);
        let version = r.u8().ok()?;
        if !matches!(version, 1 | RECORD_VERSION) {
            return None;
        }
        self.config_control = r.u32().ok()?;
        let mut addr = || r.u32().ok().map(Ipv4Addr::from);
        let (ip, netmask, gateway, dns0, dns1) = (addr()?, addr()?, addr()?, addr()?, addr()?);
        let len = usize::from(r.u8().ok()?);
        let domain = heapless::Vec::from_slice(r.take(len).ok()?).ok()?;
        self.interface = InterfaceConfig {
            ip,
            netmask,
            gateway,
            dns: [dns0, dns1],
            domain,
        };
        let len = usize::from(r.u8().ok()?);
        self.host_name = heapless::Vec::from_slice(r.take(len).ok()?).ok()?;
        self.inactivity_timeout_s = r.u16().ok()?;
        if version == RECORD_VERSION {
            self.ttl = r.u8().ok()?;
            self.mcast = MulticastConfig {
                alloc_control: r.u8().ok()?,
                num_mcast: r.u16().ok()?,
                start: Ipv4Addr::from(r.u32().ok()?),
            };
        }
        let sane = (self.interface.is_none() || self.interface.is_valid())
            && valid_host_name(&self.host_name)
            && self.inactivity_timeout_s <= super::tcpip::MAX_INACTIVITY_TIMEOUT_S
            && self.ttl != 0
            && valid_mcast(&self.mcast);
        sane.then_some(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nv::{AbStore, RamFlash, IMAGE_SIZE, MAX_WRITE_SIZE};

    fn config(ip: [u8; 4], mask: [u8; 4], gw: [u8; 4]) -> InterfaceConfig {
        InterfaceConfig {
            ip: ip.into(),
            netmask: mask.into(),
            gateway: gw.into(),
            ..InterfaceConfig::NONE
        }
    }

    #[test]
    fn interface_rules() {
        let m24 = [255, 255, 255, 0];
        assert!(config([198, 18, 0, 7], m24, [198, 18, 0, 1]).is_valid());
        assert!(config([198, 18, 0, 7], m24, [0; 4]).is_valid());
        for bad in [
            config([0; 4], m24, [0; 4]),
            config([127, 0, 0, 1], m24, [0; 4]),
            config([224, 0, 0, 1], m24, [0; 4]),
            config([255, 255, 255, 255], m24, [0; 4]),
            config([198, 18, 0, 0], m24, [0; 4]),
            config([198, 18, 0, 255], m24, [0; 4]),
            config([198, 18, 0, 7], [255, 0, 255, 0], [0; 4]),
            config([198, 18, 0, 7], [0; 4], [0; 4]),
            config([198, 18, 0, 7], [255; 4], [0; 4]),
            config([198, 18, 0, 7], m24, [198, 18, 1, 1]),
            config([198, 18, 0, 7], m24, [198, 18, 0, 7]),
            config([198, 18, 0, 7], m24, [198, 18, 0, 255]),
        ] {
            assert!(!bad.is_valid(), "{bad:?}");
        }
        let mut dns = config([198, 18, 0, 7], m24, [0; 4]);
        dns.dns[1] = Ipv4Addr::new(239, 1, 1, 1);
        assert!(!dns.is_valid());
    }

    #[test]
    fn settings_round_trip_through_the_store() {
        let mut store = AbStore::mount(RamFlash::<{ MAX_WRITE_SIZE + IMAGE_SIZE }>::new());
        assert_eq!(TcpIpState::stored(&mut store), Ok(None));
        let mut st = TcpIpState::new();
        st.interface = config([198, 18, 0, 9], [255, 255, 255, 0], [198, 18, 0, 1]);
        st.interface.domain = heapless::Vec::from_slice(b"plant.example").unwrap();
        st.host_name = heapless::Vec::from_slice(b"press-4").unwrap();
        st.inactivity_timeout_s = 30;
        st.ttl = 5;
        st.mcast = MulticastConfig {
            alloc_control: 1,
            num_mcast: 4,
            start: Ipv4Addr::new(239, 192, 3, 0),
        };
        st.save(&mut store).unwrap();
        let mut store = AbStore::mount(store.into_flash());
        let back = TcpIpState::stored(&mut store).unwrap().unwrap();
        assert_eq!(back.static_interface(), Some(&st.interface));
        assert_eq!(
            (back.host_name, back.inactivity_timeout_s),
            (st.host_name, 30)
        );
        assert_eq!((back.ttl, back.mcast), (5, st.mcast));
        store.write(key::TCP_IP, &[RECORD_VERSION, 0]).unwrap();
        assert_eq!(TcpIpState::stored(&mut store), Ok(None));
        // Longer than any record of this layout: not believed either, and not an error.
        store.write(key::TCP_IP, &[0; RECORD_MAX + 1]).unwrap();
        assert_eq!(TcpIpState::stored(&mut store), Ok(None));
    }

    #[test]
    fn every_power_cut_boots_the_old_or_the_new_tcpip_settings() {
        use crate::nv::CutFlash;
        let settings = |last: u8, timeout: u16| {
            let mut st = TcpIpState::new();
            st.interface = InterfaceConfig {
                ip: Ipv4Addr::new(198, 18, 0, last),
                netmask: Ipv4Addr::new(255, 255, 255, 0),
                ..InterfaceConfig::NONE
            };
            st.inactivity_timeout_s = timeout;
            st
        };
        let (old, new) = (settings(7, 30), settings(9, 60));
        let mut store = AbStore::mount(CutFlash::new());
        old.save(&mut store).unwrap();
        let before = store.into_flash();
        let mut cut = 0;
        loop {
            let mut flash = before.clone();
            flash.cut_after(cut);
            let mut store = AbStore::mount(flash);
            let done = new.save(&mut store).is_ok();
            let mut flash = store.into_flash();
            flash.restore();
            let booted = TcpIpState::stored(&mut AbStore::mount(flash)).unwrap();
            let expected = if done { &new } else { &old };
            // Old or new as a whole; never defaults, never a mix.
            assert!(
                booted.as_ref() == Some(&old) || booted.as_ref() == Some(&new),
                "cut after {cut}"
            );
            if done {
                assert_eq!(booted.as_ref(), Some(expected));
                break;
            }
            cut += 1;
        }
        assert!(cut > 10);
    }
}
