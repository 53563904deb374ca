//! TCP/IP Interface object (class 0xF5): addresses, host name, multicast configuration,
//! TTL, Address Conflict Detection (attributes 10 and 11, status bits 6 and 7, capability
//! bit 7: [`crate::acd`]) and the encapsulation inactivity timeout.

use core::net::Ipv4Addr;

use super::serve::{serve, Object};
use super::tcpip_nv::{valid_host_name, InterfaceConfig, INTERFACE_FIXED};
use super::Ctx;
use crate::acd::{LastConflict, LAST_CONFLICT_LEN};
use crate::cip::encoding::{ip, padded_string};
use crate::cip::object::{Access, AttributeDef, ClassDef, DataType};
use crate::cip::status::{CipResult, General};
use crate::cip::{class_id, Request};
use crate::config::{MAX_DOMAIN_NAME, MAX_HOST_NAME};
use crate::device::{Device, Multicast, MulticastConfig};
use crate::net::NetworkConfig;
use crate::wire::bytes::{get_u16, get_u32};
use crate::wire::Writer;

/// Configuration capability: DHCP client (bit 2).
const CAPABILITY_DHCP: u32 = 1 << 2;
/// Configuration capability: attributes 3 and 5 are settable (bit 4).
const CAPABILITY_SETTABLE: u32 = 1 << 4;
/// Configuration capability: interface configuration changes need a reset (bit 6).
const CAPABILITY_CHANGE_NEEDS_RESET: u32 = 1 << 6;
/// Configuration capability: Address Conflict Detection (bit 7).
const CAPABILITY_ACD: u32 = 1 << 7;
/// Status: the interface configuration is valid (bits 0-3 = 1: from DHCP or storage).
const STATUS_CONFIGURED: u32 = 1;
/// Status: a set interface configuration waits for the next reset (bit 5).
const STATUS_CONFIG_PENDING: u32 = 1 << 5;
/// Status bit 4: attribute 8 or 9 was set since start (Mcast Pending).
const STATUS_MCAST_PENDING: u32 = 1 << 4;
/// Status: an address conflict was detected (bit 6, AcdStatus).
const STATUS_ACD_CONFLICT: u32 = 1 << 6;
/// Status: the address is not used because of a conflict (bit 7, AcdFault).
const STATUS_ACD_FAULT: u32 = 1 << 7;
/// Longest encapsulation inactivity timeout in seconds (attribute 13).
pub const MAX_INACTIVITY_TIMEOUT_S: u16 = 3600;
/// Configuration control value: static address.
const CONTROL_STATIC: u32 = 0;
/// Configuration control value: DHCP.
pub(crate) const CONTROL_DHCP: u32 = 2;
/// Default encapsulation inactivity timeout in seconds.
pub const DEFAULT_INACTIVITY_TIMEOUT_S: u16 = 120;
/// First address of the CIP multicast range the default algorithm allocates from.
const CIP_MCAST_BASE: u32 = 0xEFC0_0100; // 239.192.1.0

/// Settable TCP/IP object state.
///
/// Attributes 3, 5, 6, 8, 9 and 13 are saved to the adapter's [`crate::nv::NvStore`] (when it has
/// one) before a Set is answered. Attributes 3 and 5 apply at the next reset (capability bit
/// 6): the runtime reads them at start with [`TcpIpState::stored`] and
/// [`TcpIpState::static_interface`]; until then status bit 5 says a change is pending.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TcpIpState {
    /// Attribute 3, as last set (applies at the next reset).
    pub config_control: u32,
    /// Attribute 5 as set or stored (applies at the next reset; all zero: none configured).
    pub interface: InterfaceConfig,
    /// Attribute 3 or 5 was set since start: the change waits for a reset (status bit 5).
    pub interface_pending: bool,
    /// Attribute 6.
    pub host_name: heapless::Vec<u8, MAX_HOST_NAME>,
    /// Attribute 8: multicast TTL, as last set (applies at the next start).
    pub ttl: u8,
    /// Attribute 9, as last set (applies at the next start).
    pub mcast: MulticastConfig,
    /// Attribute 8 as the device started with it: the TTL of T->O multicast until the next
    /// start.
    pub ttl_in_use: u8,
    /// Attribute 9 as the device started with it: the T->O multicast group until the next
    /// start.
    pub mcast_in_use: MulticastConfig,
    /// Attribute 8 or 9 was set since start: the change waits for the next start (status
    /// bit 4, Mcast Pending, Vol 2 table 5-4.3).
    pub mcast_pending: bool,
    /// Attribute 13: encapsulation inactivity timeout in seconds (0 disables it).
    pub inactivity_timeout_s: u16,
    /// The runtime can take the address from DHCP (capability bit 2; attribute 3 may say
    /// DHCP): [`crate::Adapter::set_dhcp_client`]. Not stored.
    pub dhcp_client: bool,
}

impl TcpIpState {
    /// Factory defaults.
    pub fn new() -> Self {
        TcpIpState {
            config_control: CONTROL_STATIC,
            interface: InterfaceConfig::NONE,
            interface_pending: false,
            host_name: heapless::Vec::new(),
            ttl: 1,
            mcast: NO_MCAST_RANGE,
            ttl_in_use: 1,
            mcast_in_use: NO_MCAST_RANGE,
            mcast_pending: false,
            inactivity_timeout_s: DEFAULT_INACTIVITY_TIMEOUT_S,
            dhcp_client: false,
        }
    }

    /// Attributes 8 and 9 as stored: set and in use alike (what the device starts with).
    pub fn start_with_multicast(&mut self, ttl: u8, mcast: MulticastConfig) {
        (self.ttl, self.mcast) = (ttl, mcast);
        (self.ttl_in_use, self.mcast_in_use) = (ttl, mcast);
    }

    /// The first multicast address and the TTL in use: the device's when it keeps them
    /// ([`Device::multicast`]), else those this object started with.
    pub fn multicast_in_use(&self, device: &impl Device, net: &NetworkConfig) -> (Ipv4Addr, u8) {
        match device.multicast() {
            Some(m) => (m.config.start, m.ttl),
            None => (multicast_start(&self.mcast_in_use, net), self.ttl_in_use),
        }
    }
}

/// Attribute 9 with no range of its own (allocation control 0: the CIP default algorithm).
const NO_MCAST_RANGE: MulticastConfig = MulticastConfig {
    alloc_control: 0,
    num_mcast: 0,
    start: Ipv4Addr::UNSPECIFIED,
};

/// The first multicast address of `mcast`: its own, or the CIP default algorithm's for `net`.
fn multicast_start(mcast: &MulticastConfig, net: &NetworkConfig) -> Ipv4Addr {
    if mcast.alloc_control == 1 {
        return mcast.start;
    }
    let host = u32::from(net.ip) & !u32::from(net.netmask);
    let host_id = host.wrapping_sub(1) & 0x3FF;
    // host_id < 0x400: the sum stays inside 239.192.0.0/14, far below u32::MAX.
    Ipv4Addr::from(CIP_MCAST_BASE.wrapping_add(host_id << 5))
}

/// Number of multicast addresses `mcast` allocates.
fn multicast_count(mcast: &MulticastConfig) -> u16 {
    if mcast.alloc_control == 1 {
        mcast.num_mcast
    } else {
        1
    }
}

impl Default for TcpIpState {
    fn default() -> Self {
        Self::new()
    }
}

/// The TCP/IP Interface class: one instance, attributes 1-13; 3, 5, 6, 8, 9, 10, 11 and 13
/// settable.
pub const CLASS: ClassDef = ClassDef {
    id: class_id::TCP_IP_INTERFACE,
    name: "TCP/IP Interface",
    revision: 4,
    max_instance: 1,
    attributes: &[
        AttributeDef::get(1, DataType::Dword, "Status"),
        AttributeDef::get(2, DataType::Dword, "Configuration Capability"),
        AttributeDef::get_set(3, DataType::Dword, "Configuration Control"),
        AttributeDef::get(4, DataType::Bytes(6), "Physical Link Object"),
        AttributeDef::get_set(
            5,
            DataType::BytesThenPaddedString {
                bytes: INTERFACE_FIXED,
                max: MAX_DOMAIN_NAME as u16,
            },
            "Interface Configuration",
        ),
        AttributeDef::get_set(
            6,
            DataType::PaddedString {
                max: MAX_HOST_NAME as u16,
            },
            "Host Name",
        ),
        AttributeDef::get(7, DataType::Bytes(6), "Safety Network Number"),
        AttributeDef::get_set(8, DataType::Usint, "TTL Value"),
        AttributeDef::get_set(9, DataType::Bytes(8), "Mcast Config"),
        AttributeDef::get_set(10, DataType::Bool, "Select ACD"),
        AttributeDef::get_set(
            11,
            DataType::Bytes(LAST_CONFLICT_LEN as u16),
            "Last Conflict Detected",
        ),
        AttributeDef::get(12, DataType::Bool, "EtherNet/IP Quick Connect"),
        AttributeDef::get_set(13, DataType::Uint, "Encapsulation Inactivity Timeout"),
    ],
    get_all: &[1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13],
    optional_attributes: &[8, 9, 10, 11, 13],
};

struct TcpIp<'c, 'a, D: Device, const C: usize>(&'c mut Ctx<'a, D, C>);

impl<D: Device, const C: usize> Object for TcpIp<'_, '_, D, C> {
    fn class(&self) -> &ClassDef {
        &CLASS
    }
    /// Safety Network Number (7) and QuickConnect (12): no CIP Safety, no QuickConnect; their
    /// zeros only fill Get_Attributes_All, alone they are 0x14.
    fn access(&self, _instance: u32, attr: &AttributeDef) -> Option<Access> {
        (!matches!(attr.id, 7 | 12)).then_some(attr.access)
    }
    fn get(&mut self, _instance: u32, attr: &AttributeDef, w: &mut Writer<'_>) -> CipResult {
        let net = self.0.net;
        let st = &self.0.state.tcpip;
        let acd = &self.0.state.acd;
        let bit = |on: bool, bit: u32| if on { bit } else { 0 };
        match attr.id {
            1 => w.u32(
                STATUS_CONFIGURED
                    | bit(st.mcast_pending, STATUS_MCAST_PENDING)
                    | bit(st.interface_pending, STATUS_CONFIG_PENDING)
                    | bit(acd.conflict, STATUS_ACD_CONFLICT)
                    | bit(acd.fault, STATUS_ACD_FAULT),
            )?,
            2 => w.u32(
                bit(st.dhcp_client, CAPABILITY_DHCP)
                    | CAPABILITY_SETTABLE
                    | CAPABILITY_CHANGE_NEEDS_RESET
                    | bit(acd.capable, CAPABILITY_ACD),
            )?,
            3 => w.u32(st.config_control)?,
            4 => w.bytes(&[2, 0, 0x20, 0xF6, 0x24, 0x01])?,
            // The values set and waiting for a reset, else those in use.
            5 if st.interface_pending && !st.interface.is_none() => st.interface.write(w)?,
            5 => {
                ip(w, net.ip)?;
                ip(w, net.netmask)?;
                ip(w, net.gateway)?;
                ip(w, net.dns[0])?;
                ip(w, net.dns[1])?;
                padded_string(w, &st.interface.domain)?;
            }
            6 => padded_string(w, &st.host_name)?,
            7 => w.zeros(6)?,
            8 => w.u8(self.0.device.multicast().map_or(st.ttl, |m| m.ttl))?,
            9 => {
                let m = self.0.device.multicast().map_or(
                    MulticastConfig {
                        alloc_control: st.mcast.alloc_control,
                        num_mcast: multicast_count(&st.mcast),
                        start: multicast_start(&st.mcast, net),
                    },
                    |m| m.config,
                );
                w.u8(m.alloc_control)?;
                w.u8(0)?;
                w.u16(m.num_mcast)?;
                ip(w, m.start)?;
            }
            10 => w.u8(u8::from(acd.settings.select))?,
            11 => w.bytes(&acd.settings.last.to_bytes())?,
            12 => w.u8(0)?,
            _ => w.u16(st.inactivity_timeout_s)?,
        }
        Ok(())
    }

    /// Every settable attribute is non-volatile (Vol 2 table 5-4.3): the Set is saved before
    /// it is answered, or undone and refused with 0x19.
    fn set(&mut self, _instance: u32, attr: &AttributeDef, value: &[u8]) -> CipResult {
        if matches!(attr.id, 10 | 11) {
            return self.set_acd(attr, value);
        }
        let before = self.0.state.tcpip.clone();
        if matches!(attr.id, 8 | 9) {
            self.set_multicast(attr, value)?;
        } else {
            self.set_interface(attr, value)?;
        }
        let ctx = &mut *self.0;
        if let Some(store) = ctx.store.as_deref_mut() {
            if ctx.state.tcpip.save(store).is_err() {
                warn!("TCP/IP attribute {}: storing failed", attr.id);
                ctx.state.tcpip = before;
                return Err(General::StoreOperationFailure.into());
            }
        }
        Ok(())
    }
}

impl<D: Device, const C: usize> TcpIp<'_, '_, D, C> {
    /// Sets attribute 3, 5, 6 or 13 in RAM.
    fn set_interface(&mut self, attr: &AttributeDef, value: &[u8]) -> CipResult {
        let st = &mut self.0.state.tcpip;
        match attr.id {
            3 => {
                // Static, or DHCP where the runtime has a DHCP client (capability bit 2); no
                // DNS Enable (bit 4): the device has no DNS client (capability bit 1 clear).
                let v = get_u32(value, 0);
                let method = v == CONTROL_STATIC || (v == CONTROL_DHCP && st.dhcp_client);
                if !method {
                    return Err(General::InvalidAttributeValue.into());
                }
                st.interface_pending |= v != st.config_control;
                st.config_control = v;
                Ok(())
            }
            5 => {
                // Only a static configuration takes an address (Vol 2, 5-4.3.2.5).
                if st.config_control & 0x0F != CONTROL_STATIC {
                    return Err(General::ObjectStateConflict.into());
                }
                let config = InterfaceConfig::parse(value)?;
                st.interface_pending |= config != st.interface;
                st.interface = config;
                Ok(())
            }
            6 => {
                let len = usize::from(get_u16(value, 0));
                let name = value.get(2..2 + len).unwrap_or(&[]);
                if !valid_host_name(name) {
                    return Err(General::InvalidAttributeValue.into());
                }
                st.host_name =
                    heapless::Vec::from_slice(name).map_err(|_| General::InvalidAttributeValue)?;
                // The LLDP System Name follows.
                self.0.state.lldp.local_changed();
                Ok(())
            }
            _ => {
                let v = get_u16(value, 0);
                if v > MAX_INACTIVITY_TIMEOUT_S {
                    return Err(General::InvalidAttributeValue.into());
                }
                st.inactivity_timeout_s = v;
                Ok(())
            }
        }
    }

    /// Sets attribute 10 (applies at the next start) or clears attribute 11 (only an all-zero
    /// value is taken: the attribute records what the device saw), and saves both.
    fn set_acd(&mut self, attr: &AttributeDef, value: &[u8]) -> CipResult {
        let ctx = &mut *self.0;
        let mut settings = ctx.state.acd.settings;
        match (attr.id, value) {
            (10, [v @ (0 | 1)]) => settings.select = *v == 1,
            (11, v) if v.iter().all(|b| *b == 0) => settings.last = LastConflict::NONE,
            _ => return Err(General::InvalidAttributeValue.into()),
        }
        if let Some(store) = ctx.store.as_deref_mut() {
            if settings.save(store).is_err() {
                warn!("TCP/IP attribute {}: storing failed", attr.id);
                return Err(General::StoreOperationFailure.into());
            }
            ctx.state.acd.saved = settings.last;
        }
        ctx.state.acd.settings = settings;
        Ok(())
    }

    /// Sets attribute 8 or 9: in RAM until the next start (status bit 4 says a change
    /// waits), or by the device when it keeps them (and applies them when it chooses).
    fn set_multicast(&mut self, attr: &AttributeDef, value: &[u8]) -> CipResult {
        let set = self.set_multicast_value(attr, value);
        self.0.state.tcpip.mcast_pending |= set.is_ok() && self.0.device.multicast().is_none();
        set
    }

    /// [`Self::set_multicast`]'s value.
    fn set_multicast_value(&mut self, attr: &AttributeDef, value: &[u8]) -> CipResult {
        let st = &mut self.0.state.tcpip;
        match attr.id {
            8 => match value.first().copied().unwrap_or(0) {
                0 => Err(General::InvalidAttributeValue.into()),
                ttl => {
                    match self.0.device.multicast() {
                        Some(m) => self.0.device.set_multicast(Multicast { ttl, ..m })?,
                        None => st.ttl = ttl,
                    }
                    Ok(())
                }
            },
            9 => {
                let v = value;
                let mcast = MulticastConfig {
                    alloc_control: v.first().copied().unwrap_or(0xFF),
                    num_mcast: get_u16(v, 2),
                    start: Ipv4Addr::from(get_u32(v, 4)),
                };
                let reserved = v.get(1).copied().unwrap_or(0xFF);
                if reserved != 0 || !valid_mcast(&mcast) {
                    return Err(General::InvalidAttributeValue.into());
                }
                match self.0.device.multicast() {
                    Some(m) => self.0.device.set_multicast(Multicast {
                        ttl: m.ttl,
                        config: mcast,
                    })?,
                    None => st.mcast = mcast,
                }
                Ok(())
            }
            _ => Err(General::AttributeNotSettable.into()),
        }
    }
}

/// Alloc control 0 takes no range; 1 takes a non-empty range inside 239.192.0.0/14.
pub(crate) fn valid_mcast(m: &MulticastConfig) -> bool {
    let start = u32::from(m.start);
    match m.alloc_control {
        0 => m.num_mcast == 0 && start == 0,
        1 => {
            let end = start
                .saturating_add(u32::from(m.num_mcast))
                .saturating_sub(1);
            m.num_mcast > 0
                && start & 0xFFFC_0000 == 0xEFC0_0000
                && end & 0xFFFC_0000 == 0xEFC0_0000
        }
        _ => false,
    }
}

/// Handles a request to the TCP/IP Interface class or its instance 1.
pub(crate) fn handle<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    #[cfg(feature = "cip-security")]
    if let Some(r) = super::security::port_admin(ctx, req, w) {
        return r;
    }
    serve(&mut TcpIp(ctx), req, w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_multicast_algorithm() {
        let net = NetworkConfig::new_static(
            Ipv4Addr::new(198, 18, 0, 2),
            Ipv4Addr::new(255, 255, 255, 0),
            [2, 0, 0, 0, 0, 1],
        );
        // host id 2 - 1 = 1 -> 239.192.1.0 + 32
        assert_eq!(
            multicast_start(&TcpIpState::new().mcast_in_use, &net),
            Ipv4Addr::new(239, 192, 1, 32)
        );
    }

    #[test]
    fn multicast_ranges() {
        let m = |a, n, s: [u8; 4]| MulticastConfig {
            alloc_control: a,
            num_mcast: n,
            start: Ipv4Addr::from(s),
        };
        assert!(valid_mcast(&m(0, 0, [0; 4])));
        assert!(!valid_mcast(&m(0, 1, [0; 4])));
        assert!(valid_mcast(&m(1, 1, [239, 192, 15, 32])));
        assert!(!valid_mcast(&m(1, 0, [239, 192, 15, 32])));
        assert!(!valid_mcast(&m(1, 1, [224, 0, 0, 1])));
        assert!(!valid_mcast(&m(2, 1, [239, 192, 15, 32])));
    }
}
