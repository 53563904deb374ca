//! The kernel interface holding the bound address: its configuration as the adapter reports
//! it (address, mask, gateway, MAC, link state), read with `getifaddrs(3)` and
//! `/proc/net/route` when a netlink [`crate::netlink::Watch`] says it may have changed, so
//! nothing is polled while it stays the same.

use std::ffi::CStr;
use std::io;
use std::net::Ipv4Addr;

use enip_stack::NetworkConfig;

/// The interface holding the bound address, as last read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Interface {
    /// Interface name.
    pub name: String,
    /// Interface index.
    pub index: u32,
    /// The configuration the adapter reports; the address unspecified while the interface
    /// no longer holds it.
    pub config: NetworkConfig,
}

impl Interface {
    /// The interface holding `ip` now, or why there is none.
    pub fn holding(ip: Ipv4Addr) -> Result<Self, String> {
        let addrs = IfAddrs::read().map_err(|e| format!("cannot list interfaces: {e}"))?;
        let (name, netmask, flags) = addrs
            .iter()
            .find_map(|a| match a.v4() {
                Some((addr, mask)) if addr == ip => Some((a.name(), mask, a.flags())),
                _ => None,
            })
            .ok_or_else(|| {
                format!(
                    "no interface has the address {ip}; --bind takes one of this host's own \
                     addresses (see `ip -4 addr`)"
                )
            })?;
        let mac = addrs
            .iter()
            .filter(|a| a.name() == name)
            .find_map(|a| a.mac())
            .unwrap_or([0; 6]);
        let mut config = NetworkConfig::new_static(ip, netmask, mac);
        config.gateway = default_gateway(&name).unwrap_or(Ipv4Addr::UNSPECIFIED);
        config.link_up = flags & libc::IFF_RUNNING as u32 != 0;
        let index = index_of(&name)?;
        Ok(Interface {
            name,
            index,
            config,
        })
    }

    /// This interface read again: the same one while it holds `ip`; else its address is
    /// unspecified and its link down.
    pub fn refreshed(&self, ip: Ipv4Addr) -> Interface {
        match Interface::holding(ip) {
            Ok(now) if now.index == self.index => now,
            _ => {
                let mut gone = self.clone();
                gone.config.ip = Ipv4Addr::UNSPECIFIED;
                gone.config.link_up = false;
                gone
            }
        }
    }
}

/// The index of interface `name`.
fn index_of(name: &str) -> Result<u32, String> {
    let c_name = std::ffi::CString::new(name).map_err(|_| format!("bad interface {name:?}"))?;
    // SAFETY: `c_name` is a valid NUL-terminated string that outlives the call.
    match unsafe { libc::if_nametoindex(c_name.as_ptr()) } {
        0 => Err(format!(
            "interface {name:?}: {}",
            io::Error::last_os_error()
        )),
        i => Ok(i),
    }
}

/// The default route's gateway on interface `name`, from `/proc/net/route`.
fn default_gateway(name: &str) -> Option<Ipv4Addr> {
    let table = std::fs::read_to_string("/proc/net/route").ok()?;
    table.lines().skip(1).find_map(|line| {
        let mut cols = line.split_whitespace();
        let (iface, dest, gateway) = (cols.next()?, cols.next()?, cols.next()?);
        if iface != name || dest != "00000000" {
            return None;
        }
        // The kernel prints the address's bytes as a native-endian hexadecimal number.
        let raw = u32::from_str_radix(gateway, 16).ok()?;
        Some(Ipv4Addr::from(raw.to_ne_bytes()))
    })
}

/// The list `getifaddrs(3)` returns, freed when dropped.
struct IfAddrs {
    head: *mut libc::ifaddrs,
}

/// One entry of an [`IfAddrs`] list.
struct IfAddr<'a>(&'a libc::ifaddrs);

impl IfAddrs {
    fn read() -> io::Result<Self> {
        let mut head = std::ptr::null_mut();
        // SAFETY: `head` is a valid out-pointer; on success the list is freed in `drop`.
        if unsafe { libc::getifaddrs(&mut head) } != 0 {
            return Err(io::Error::last_os_error());
        }
        Ok(IfAddrs { head })
    }

    fn iter(&self) -> impl Iterator<Item = IfAddr<'_>> {
        // SAFETY: each `ifa_next` is null or points to the next entry of the list, which
        // lives until `self` is dropped.
        std::iter::successors(unsafe { self.head.as_ref() }, |a| unsafe {
            a.ifa_next.as_ref()
        })
        .map(IfAddr)
    }
}

impl Drop for IfAddrs {
    fn drop(&mut self) {
        // SAFETY: `head` came from a successful getifaddrs and is freed once.
        unsafe { libc::freeifaddrs(self.head) }
    }
}

impl IfAddr<'_> {
    fn name(&self) -> String {
        if self.0.ifa_name.is_null() {
            return String::new();
        }
        // SAFETY: a non-null `ifa_name` is a NUL-terminated string owned by the list.
        unsafe { CStr::from_ptr(self.0.ifa_name) }
            .to_string_lossy()
            .into_owned()
    }

    fn flags(&self) -> u32 {
        self.0.ifa_flags
    }

    /// The IPv4 address and netmask, if this entry is one.
    fn v4(&self) -> Option<(Ipv4Addr, Ipv4Addr)> {
        let v4 = |p: *const libc::sockaddr| {
            // SAFETY: a non-null address of family AF_INET is a sockaddr_in owned by the list.
            let sa = unsafe { p.as_ref() }?;
            (i32::from(sa.sa_family) == libc::AF_INET).then(|| {
                let sin = unsafe { &*(p as *const libc::sockaddr_in) };
                Ipv4Addr::from(u32::from_be(sin.sin_addr.s_addr))
            })
        };
        Some((v4(self.0.ifa_addr)?, v4(self.0.ifa_netmask)?))
    }

    /// The Ethernet address, if this entry is the interface's link-layer one.
    fn mac(&self) -> Option<[u8; 6]> {
        let p = self.0.ifa_addr;
        // SAFETY: a non-null address of family AF_PACKET is a sockaddr_ll owned by the list.
        let sa = unsafe { p.as_ref() }?;
        if i32::from(sa.sa_family) != libc::AF_PACKET {
            return None;
        }
        let ll = unsafe { &*(p as *const libc::sockaddr_ll) };
        let mut mac = [0; 6];
        let addr = ll.sll_addr.get(..6)?;
        (ll.sll_halen == 6).then(|| {
            mac.copy_from_slice(addr);
            mac
        })
    }
}
