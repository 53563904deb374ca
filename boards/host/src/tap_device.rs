//! [`TapDevice`]: a TAP interface as an embassy-net driver, with one receive and one transmit
//! buffer allocated at start, so a received frame costs no allocation or zeroing (the
//! embassy-net-tuntap driver allocates and zeroes an MTU-sized buffer on every read attempt).

use std::fs::{File, OpenOptions};
use std::io::{self, Read, Write};
use std::os::fd::AsRawFd;
use std::os::unix::fs::OpenOptionsExt;
use std::task::Context;

use async_io::Async;
use embassy_net_driver::{Capabilities, Driver, HardwareAddress, LinkState};

/// Largest Ethernet frame on the TAP: a 1500-byte payload and the 14-byte header.
const FRAME: usize = 1514;
/// Bytes of `struct ifreq`.
const IFREQ_LEN: usize = 40;

/// An open TAP interface.
pub struct TapDevice {
    fd: Async<File>,
    rx: Box<[u8; FRAME]>,
    tx: Box<[u8; FRAME]>,
    mac: [u8; 6],
}

impl TapDevice {
    /// Attaches to (or, if none has the name, creates) the TAP interface `name`.
    pub fn open(name: &str) -> io::Result<Self> {
        let file = OpenOptions::new()
            .read(true)
            .write(true)
            .custom_flags(libc::O_NONBLOCK)
            .open("/dev/net/tun")?;
        let mut ifreq = [0u8; IFREQ_LEN];
        let bytes = name.as_bytes();
        if bytes.len() >= libc::IF_NAMESIZE {
            return Err(io::Error::from(io::ErrorKind::InvalidInput));
        }
        if let Some(dst) = ifreq.get_mut(..bytes.len()) {
            dst.copy_from_slice(bytes);
        }
        let flags = (libc::IFF_TAP | libc::IFF_NO_PI) as libc::c_short;
        if let Some(dst) = ifreq.get_mut(libc::IF_NAMESIZE..libc::IF_NAMESIZE + 2) {
            dst.copy_from_slice(&flags.to_ne_bytes());
        }
        // SAFETY: TUNSETIFF reads and writes a `struct ifreq`, which `ifreq` is sized and laid
        // out as (name, then the flags); it outlives the call.
        if unsafe { libc::ioctl(file.as_raw_fd(), libc::TUNSETIFF, ifreq.as_mut_ptr()) } < 0 {
            return Err(io::Error::last_os_error());
        }
        Ok(TapDevice {
            fd: Async::new(file)?,
            rx: Box::new([0; FRAME]),
            tx: Box::new([0; FRAME]),
            mac: [0; 6],
        })
    }

    /// Sets the Ethernet address the network stack uses.
    pub fn set_hardware_address(&mut self, mac: [u8; 6]) {
        self.mac = mac;
    }
}

/// A received frame, in the device's receive buffer.
pub struct RxToken<'a> {
    frame: &'a mut [u8],
}

/// Room for one frame to send, in the device's transmit buffer.
pub struct TxToken<'a> {
    fd: &'a Async<File>,
    buf: &'a mut [u8; FRAME],
}

impl embassy_net_driver::RxToken for RxToken<'_> {
    fn consume<R, F: FnOnce(&mut [u8]) -> R>(self, f: F) -> R {
        f(self.frame)
    }
}

impl embassy_net_driver::TxToken for TxToken<'_> {
    fn consume<R, F: FnOnce(&mut [u8]) -> R>(self, len: usize, f: F) -> R {
        let frame = self.buf.get_mut(..len).unwrap_or_default();
        let r = f(frame);
        // A full TAP queue drops the frame, as a busy wire would.
        if let Err(e) = self.fd.get_ref().write(frame) {
            log::debug!("tap write: {e}");
        }
        r
    }
}

impl Driver for TapDevice {
    type RxToken<'a> = RxToken<'a>;
    type TxToken<'a> = TxToken<'a>;

    fn receive(&mut self, cx: &mut Context<'_>) -> Option<(RxToken<'_>, TxToken<'_>)> {
        // Bounded: a read that finds nothing asks the reactor, which either registers the
        // waker (no frame: done) or says a frame arrived meanwhile (one more read).
        for _ in 0..2 {
            match self.fd.get_ref().read(self.rx.as_mut_slice()) {
                Ok(n) => {
                    let Self { fd, rx, tx, .. } = self;
                    let frame = rx.get_mut(..n).unwrap_or_default();
                    return Some((RxToken { frame }, TxToken { fd, buf: tx }));
                }
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => {
                    if self.fd.poll_readable(cx).is_pending() {
                        return None;
                    }
                }
                Err(e) => {
                    log::warn!("tap read: {e}");
                    return None;
                }
            }
        }
        // A frame announced but not there: ask again, which registers the waker.
        let _ = self.fd.poll_readable(cx);
        None
    }

    fn transmit(&mut self, _cx: &mut Context<'_>) -> Option<TxToken<'_>> {
        Some(TxToken {
            fd: &self.fd,
            buf: &mut self.tx,
        })
    }

    fn link_state(&mut self, _cx: &mut Context<'_>) -> LinkState {
        LinkState::Up
    }

    fn capabilities(&self) -> Capabilities {
        let mut caps = Capabilities::default();
        caps.max_transmission_unit = FRAME;
        caps
    }

    fn hardware_address(&self) -> HardwareAddress {
        HardwareAddress::Ethernet(self.mac)
    }
}
