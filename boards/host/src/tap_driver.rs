//! [`Tap`]: the embassy-net driver of a TAP interface, built to survive the link going down.
//!
//! `embassy-net-tuntap`'s own driver panics when a write fails, which is what the kernel
//! answers (EIO) while the TAP is administratively down (`ip link set TAP down`): a pulled
//! cable would kill the adapter. Here a frame that cannot be written is dropped, as on a
//! link without carrier, and the link state follows the interface's flags (up and running),
//! read every [`LINK_POLL`], so the adapter sees the link go down and come back.

use std::ffi::CString;
use std::future::Future;
use std::io::{self, Read, Write};
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};
use std::pin::Pin;
use std::task::{Context, Poll};

use async_io::Async;
use embassy_net_driver::{Capabilities, Driver, HardwareAddress, LinkState};
use embassy_net_tuntap::TunTap;
use embassy_time::{Duration, Timer};

/// How often the interface's flags are read for the link state.
const LINK_POLL: Duration = Duration::from_millis(100);
/// Ethernet header bytes, which smoltcp counts in the MTU and the interface's MTU does not.
const ETHERNET_HEADER: usize = 14;

/// A TAP interface as an embassy-net driver.
pub struct Tap {
    device: Async<TunTap>,
    /// An AF_INET datagram socket, only for the interface ioctls.
    control: OwnedFd,
    /// The interface name, for the ioctls.
    name: CString,
    mac: [u8; 6],
    mtu: usize,
    link: LinkState,
    /// When the flags are read next.
    next_poll: Timer,
    /// Frames dropped since the link was last seen down (logged once per outage).
    dropped: u64,
}

impl Tap {
    /// Attaches to the TAP interface `name` (created if it does not exist).
    pub fn open(name: &str) -> io::Result<Tap> {
        let device = Async::new(TunTap::new(name)?)?;
        // SAFETY: socket(2) with constant arguments; the result is checked before use.
        let fd = unsafe { libc::socket(libc::AF_INET, libc::SOCK_DGRAM, libc::IPPROTO_IP) };
        if fd < 0 {
            return Err(io::Error::last_os_error());
        }
        // SAFETY: `fd` is a socket this function just opened and nothing else owns.
        let control = unsafe { OwnedFd::from_raw_fd(fd) };
        let name = CString::new(name).map_err(|_| io::Error::other("bad interface name"))?;
        let mut tap = Tap {
            device,
            control,
            name,
            mac: [0x02, 0, 0, 0, 0, 0x02],
            mtu: 0,
            link: LinkState::Down,
            next_poll: Timer::after(LINK_POLL),
            dropped: 0,
        };
        let mtu = tap.ioctl(libc::SIOCGIFMTU)?;
        // SAFETY: SIOCGIFMTU fills the `ifru_mtu` member of the union.
        tap.mtu =
            usize::try_from(unsafe { mtu.ifr_ifru.ifru_mtu }).unwrap_or(1500) + ETHERNET_HEADER;
        tap.link = tap.read_link()?;
        Ok(tap)
    }

    /// Sets the MAC address the stack uses on the TAP.
    pub fn set_hardware_address(&mut self, mac: [u8; 6]) {
        self.mac = mac;
    }

    /// Runs the interface ioctl `request` and returns the filled request block.
    fn ioctl(&self, request: libc::Ioctl) -> io::Result<libc::ifreq> {
        // SAFETY: an all-zero `ifreq` is a valid value of this plain C struct.
        let mut ifr: libc::ifreq = unsafe { std::mem::zeroed() };
        let name = self.name.as_bytes();
        if name.len() >= ifr.ifr_name.len() {
            return Err(io::Error::other("interface name too long"));
        }
        for (dst, src) in ifr.ifr_name.iter_mut().zip(name) {
            *dst = *src as libc::c_char;
        }
        // SAFETY: `ifr` is a valid, NUL-terminated request block that outlives the call, and
        // the socket is open; the kernel writes only inside the block.
        let r = unsafe { libc::ioctl(self.control.as_raw_fd(), request, &mut ifr) };
        if r < 0 {
            return Err(io::Error::last_os_error());
        }
        Ok(ifr)
    }

    /// The link state from the interface's flags: up only when both up and running.
    fn read_link(&self) -> io::Result<LinkState> {
        let ifr = self.ioctl(libc::SIOCGIFFLAGS)?;
        // SAFETY: SIOCGIFFLAGS fills the `ifru_flags` member of the union.
        let flags = i32::from(unsafe { ifr.ifr_ifru.ifru_flags });
        let up = libc::IFF_UP | libc::IFF_RUNNING;
        Ok(if flags & up == up {
            LinkState::Up
        } else {
            LinkState::Down
        })
    }
}

impl Driver for Tap {
    type RxToken<'a>
        = RxToken
    where
        Self: 'a;
    type TxToken<'a>
        = TxToken<'a>
    where
        Self: 'a;

    fn receive(&mut self, cx: &mut Context) -> Option<(RxToken, TxToken<'_>)> {
        let mut buf = vec![0; self.mtu];
        loop {
            // SAFETY (of `get_mut`, which async-io marks unsafe): reading does not close or
            // replace the file descriptor.
            match unsafe { self.device.get_mut() }.read(&mut buf) {
                Ok(n) => {
                    buf.truncate(n);
                    let rx = RxToken { frame: buf };
                    return Some((rx, TxToken { tap: self }));
                }
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => {
                    if self.device.poll_readable(cx).is_pending() {
                        return None;
                    }
                }
                Err(e) => {
                    // Woken again by the link poll; a persistent error cannot spin here.
                    log::warn!("tap {:?}: read failed: {e}", self.name);
                    return None;
                }
            }
        }
    }

    fn transmit(&mut self, _cx: &mut Context) -> Option<TxToken<'_>> {
        Some(TxToken { tap: self })
    }

    fn link_state(&mut self, cx: &mut Context) -> LinkState {
        while Pin::new(&mut self.next_poll).poll(cx) == Poll::Ready(()) {
            self.next_poll = Timer::after(LINK_POLL);
            match self.read_link() {
                Ok(link) if link != self.link => {
                    log::info!("tap {:?}: link up {}", self.name, link == LinkState::Up);
                    if link == LinkState::Up && self.dropped > 0 {
                        log::info!(
                            "tap {:?}: {} frames dropped while the link was down",
                            self.name,
                            self.dropped
                        );
                        self.dropped = 0;
                    }
                    self.link = link;
                }
                Ok(_) => {}
                Err(e) => log::warn!("tap {:?}: cannot read its flags: {e}", self.name),
            }
        }
        self.link
    }

    fn capabilities(&self) -> Capabilities {
        let mut caps = Capabilities::default();
        caps.max_transmission_unit = self.mtu;
        caps
    }

    fn hardware_address(&self) -> HardwareAddress {
        HardwareAddress::Ethernet(self.mac)
    }
}

/// A received frame.
pub struct RxToken {
    frame: Vec<u8>,
}

impl embassy_net_driver::RxToken for RxToken {
    fn consume<R, F: FnOnce(&mut [u8]) -> R>(mut self, f: F) -> R {
        f(&mut self.frame)
    }
}

/// Room for one frame to send.
pub struct TxToken<'a> {
    tap: &'a mut Tap,
}

impl embassy_net_driver::TxToken for TxToken<'_> {
    fn consume<R, F: FnOnce(&mut [u8]) -> R>(self, len: usize, f: F) -> R {
        let mut frame = vec![0; len];
        let result = f(&mut frame);
        // SAFETY (of `get_mut`): writing does not close or replace the file descriptor.
        match unsafe { self.tap.device.get_mut() }.write(&frame) {
            Ok(_) => {}
            // The kernel refuses frames while the interface is down: dropped, as on a link
            // without carrier.
            Err(e) => {
                if self.tap.dropped == 0 {
                    log::info!("tap {:?}: dropping frames: {e}", self.tap.name);
                }
                self.tap.dropped += 1;
            }
        }
        result
    }
}
