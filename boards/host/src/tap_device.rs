//! [`TapDevice`]: a TAP interface as an embassy-net driver, with one receive and one transmit
//! buffer allocated at start, so a received frame costs no allocation or zeroing (the
//! embassy-net-tuntap driver allocates and zeroes an MTU-sized buffer on every read attempt);
//! it reads after the loop's `ppoll` found the TAP readable ([`Readable`]) and then on, as a
//! MAC's receive ring is drained, up to [`READS_PER_REPORT`] frames or until the TAP is empty
//! (a flood costs one `ppoll` for that many frames, not one each, while the loop's other
//! descriptors are still watched between them); and it is built to survive the link going down: the kernel refuses
//! writes (EIO) while the TAP is administratively down (`ip link set TAP down`, a pulled
//! cable), and such a frame is dropped as on a link without carrier, while the link state
//! follows the interface's flags (up and running), read again whenever netlink reports a
//! change ([`Watch`]): nothing is polled on a timer.

use std::fs::{File, OpenOptions};
use std::future::Future;
use std::io::{self, Read, Write};
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};
use std::os::unix::fs::OpenOptionsExt;
use std::pin::Pin;
use std::task::Context;

use embassy_net_driver::{Capabilities, Driver, HardwareAddress, LinkState};
use embassy_time::{Duration, Timer};
use enip_host_runtime::Readable;

use crate::netlink::Watch;

/// Largest Ethernet frame on the TAP: a 1500-byte payload and the 14-byte header.
const FRAME: usize = 1514;
/// Bytes of `struct ifreq`.
const IFREQ_LEN: usize = 40;
/// How long after a failed read the TAP is watched again (a persistent error is retried,
/// not spun on).
const READ_RETRY: Duration = Duration::from_millis(100);
/// Frames read after one readiness report before the loop's wait is asked again.
const READS_PER_REPORT: u8 = 16;

/// An open TAP interface.
pub struct TapDevice {
    /// The TAP's readiness, reported by the loop's wait (dropped before the TAP closes).
    readable: Readable,
    /// The TAP, non-blocking.
    file: File,
    rx: Box<[u8; FRAME]>,
    tx: Box<[u8; FRAME]>,
    mac: [u8; 6],
    /// The interface name, NUL-padded as `struct ifreq` wants it.
    name: [u8; libc::IF_NAMESIZE],
    /// An AF_INET datagram socket, only for the interface-flags ioctl.
    control: OwnedFd,
    link: LinkState,
    /// The readiness of `watch` (dropped before it closes).
    link_changes: Readable,
    /// Says when links may have changed: the flags are read again then.
    watch: Watch,
    /// After a failed read: when to watch the TAP again.
    retry: Option<Timer>,
    /// Reads that may still be tried without a new readiness report (0: wait for one).
    reads_left: u8,
    /// Frames the kernel refused since the link was last seen down (logged once an outage).
    dropped: u64,
}

impl TapDevice {
    /// Attaches to (or, if none has the name, creates) the TAP interface `name`.
    pub fn open(name: &str) -> io::Result<Self> {
        let file = OpenOptions::new()
            .read(true)
            .write(true)
            .custom_flags(libc::O_NONBLOCK)
            .open("/dev/net/tun")?;
        let bytes = name.as_bytes();
        if bytes.len() >= libc::IF_NAMESIZE {
            return Err(io::Error::from(io::ErrorKind::InvalidInput));
        }
        let mut padded = [0u8; libc::IF_NAMESIZE];
        if let Some(dst) = padded.get_mut(..bytes.len()) {
            dst.copy_from_slice(bytes);
        }
        let mut ifreq = request(&padded);
        let flags = (libc::IFF_TAP | libc::IFF_NO_PI) as libc::c_short;
        if let Some(dst) = ifreq.get_mut(libc::IF_NAMESIZE..libc::IF_NAMESIZE + 2) {
            dst.copy_from_slice(&flags.to_ne_bytes());
        }
        // SAFETY: TUNSETIFF reads and writes a `struct ifreq`, which `ifreq` is sized and laid
        // out as (name, then the flags); it outlives the call.
        if unsafe { libc::ioctl(file.as_raw_fd(), libc::TUNSETIFF, ifreq.as_mut_ptr()) } < 0 {
            return Err(io::Error::last_os_error());
        }
        // SAFETY: socket(2) with constant arguments; the result is checked before use.
        let fd = unsafe { libc::socket(libc::AF_INET, libc::SOCK_DGRAM, libc::IPPROTO_IP) };
        if fd < 0 {
            return Err(io::Error::last_os_error());
        }
        // SAFETY: `fd` is a socket this function just opened and nothing else owns.
        let control = unsafe { OwnedFd::from_raw_fd(fd) };
        // Subscribed before the flags are first read, so no change after that goes unseen.
        let watch = Watch::open()?;
        let mut tap = TapDevice {
            readable: Readable::new(file.as_raw_fd()),
            file,
            rx: Box::new([0; FRAME]),
            tx: Box::new([0; FRAME]),
            mac: [0; 6],
            name: padded,
            control,
            link: LinkState::Down,
            link_changes: Readable::new(watch.fd()),
            watch,
            retry: None,
            reads_left: 0,
            dropped: 0,
        };
        tap.link = tap.read_link()?;
        Ok(tap)
    }

    /// Sets the Ethernet address the network stack uses.
    pub fn set_hardware_address(&mut self, mac: [u8; 6]) {
        self.mac = mac;
    }

    /// Reads one frame into the receive buffer; a failure other than an empty TAP is logged
    /// and the TAP watched again only after [`READ_RETRY`] (the timer polled with `cx`).
    fn read(&mut self, cx: &mut Context<'_>) -> ReadOutcome {
        match (&self.file).read(self.rx.as_mut_slice()) {
            Ok(n) => ReadOutcome::Frame(n),
            Err(e) if e.kind() == io::ErrorKind::WouldBlock => ReadOutcome::Empty,
            Err(e) => {
                log::warn!("tap read: {e}");
                let mut retry = Timer::after(READ_RETRY);
                // Polled once, so that it wakes the runner.
                let _ = Pin::new(&mut retry).poll(cx);
                self.retry = Some(retry);
                self.reads_left = 0;
                ReadOutcome::Failed
            }
        }
    }

    /// The tokens of the `n`-byte frame just read.
    fn tokens(&mut self, n: usize) -> (RxToken<'_>, TxToken<'_>) {
        let Self {
            file,
            rx,
            tx,
            dropped,
            ..
        } = self;
        let frame = rx.get_mut(..n).unwrap_or_default();
        let tx = TxToken {
            file,
            buf: tx,
            dropped,
        };
        (RxToken { frame }, tx)
    }

    /// The link state from the interface's flags: up only when both up and running.
    fn read_link(&self) -> io::Result<LinkState> {
        let mut ifreq = request(&self.name);
        // SAFETY: SIOCGIFFLAGS reads the name from and writes the flags into a `struct
        // ifreq`, which `ifreq` is sized and laid out as; it outlives the call.
        let r = unsafe {
            libc::ioctl(
                self.control.as_raw_fd(),
                libc::SIOCGIFFLAGS,
                ifreq.as_mut_ptr(),
            )
        };
        if r < 0 {
            return Err(io::Error::last_os_error());
        }
        let mut raw = [0u8; 2];
        if let Some(src) = ifreq.get(libc::IF_NAMESIZE..libc::IF_NAMESIZE + 2) {
            raw.copy_from_slice(src);
        }
        let flags = i32::from(libc::c_short::from_ne_bytes(raw));
        let up = libc::IFF_UP | libc::IFF_RUNNING;
        Ok(if flags & up == up {
            LinkState::Up
        } else {
            LinkState::Down
        })
    }
}

/// A `struct ifreq` naming interface `name` (NUL-padded), everything else zero.
fn request(name: &[u8; libc::IF_NAMESIZE]) -> [u8; IFREQ_LEN] {
    let mut ifreq = [0u8; IFREQ_LEN];
    if let Some(dst) = ifreq.get_mut(..libc::IF_NAMESIZE) {
        dst.copy_from_slice(name);
    }
    ifreq
}

/// What one read of the TAP gave.
enum ReadOutcome {
    /// A frame of this many bytes.
    Frame(usize),
    /// Nothing to read.
    Empty,
    /// An error, logged; the TAP is read again after [`READ_RETRY`].
    Failed,
}

/// A received frame, in the device's receive buffer.
pub struct RxToken<'a> {
    frame: &'a mut [u8],
}

/// Room for one frame to send, in the device's transmit buffer.
pub struct TxToken<'a> {
    file: &'a File,
    buf: &'a mut [u8; FRAME],
    dropped: &'a mut u64,
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
        // A full TAP queue or a link that is down (EIO) drops the frame, as a busy wire or a
        // link without carrier would.
        if let Err(e) = (&*self.file).write(frame) {
            if *self.dropped == 0 {
                log::info!("tap: dropping frames: {e}");
            }
            *self.dropped = self.dropped.saturating_add(1);
        }
        r
    }
}

impl Driver for TapDevice {
    type RxToken<'a> = RxToken<'a>;
    type TxToken<'a> = TxToken<'a>;

    fn receive(&mut self, cx: &mut Context<'_>) -> Option<(RxToken<'_>, TxToken<'_>)> {
        if let Some(retry) = &mut self.retry {
            if Pin::new(retry).poll(cx).is_pending() {
                return None;
            }
            self.retry = None;
        }
        if self.reads_left > 0 {
            self.reads_left -= 1;
            match self.read(cx) {
                ReadOutcome::Frame(n) => return Some(self.tokens(n)),
                ReadOutcome::Failed => return None,
                // Drained: wait for the next report.
                ReadOutcome::Empty => self.reads_left = 0,
            }
        }
        // Bounded: a report with nothing to read (another reader took it, or the reads since
        // it drained the TAP) is taken, so the second poll keeps the waker for the next one.
        for _ in 0..2 {
            if self.readable.poll_readable(cx).is_pending() {
                return None;
            }
            match self.read(cx) {
                ReadOutcome::Frame(n) => {
                    self.reads_left = READS_PER_REPORT - 1;
                    return Some(self.tokens(n));
                }
                ReadOutcome::Failed => return None,
                ReadOutcome::Empty => {}
            }
        }
        None
    }

    fn transmit(&mut self, _cx: &mut Context<'_>) -> Option<TxToken<'_>> {
        Some(TxToken {
            file: &self.file,
            buf: &mut self.tx,
            dropped: &mut self.dropped,
        })
    }

    fn link_state(&mut self, cx: &mut Context<'_>) -> LinkState {
        // At most one turn: the first poll takes the report, the second keeps the waker.
        while self.link_changes.poll_readable(cx).is_ready() {
            self.watch.drain(self.rx.as_mut_slice());
            match self.read_link() {
                Ok(link) if link != self.link => {
                    log::info!("tap: link up {}", link == LinkState::Up);
                    if link == LinkState::Up && self.dropped > 0 {
                        log::info!(
                            "tap: {} frames dropped while the link was down",
                            self.dropped
                        );
                        self.dropped = 0;
                    }
                    self.link = link;
                }
                Ok(_) => {}
                Err(e) => log::warn!("tap: cannot read its flags: {e}"),
            }
        }
        self.link
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
