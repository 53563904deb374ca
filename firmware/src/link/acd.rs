//! Address Conflict Detection in the link task: the stack's [`Acd`] state machine run on
//! the frames the link task sees. It follows the interface address (a new static or DHCP
//! address is probed before use, and again when the link comes up), reads every received ARP message, sends the probes,
//! announcements and defences, and until the address has been probed and announced (or
//! after it was lost) holds back what the interface would send from it: the network stack's
//! frames are dropped, except IPv4 from 0.0.0.0 (a DHCP client's), and T->O data is not
//! produced. What it finds goes to the adapter ([`AcdPort`]): the TCP/IP object's status
//! bits and attribute 11, saved in the non-volatile store.

use core::net::Ipv4Addr;

use enip_stack::acd::{Acd, Arp, ArpFrame, LastConflict, Phase, Verdict};
use enip_stack::{Device, Instant};

use crate::shared::{with_adapter_quiet, SharedAdapter};

/// What the link task tells the adapter about Address Conflict Detection; implemented by
/// [`crate::SharedAdapter`].
pub trait AcdPort {
    /// Whether to detect conflicts in this run (TCP/IP attribute 10 at start); also reports
    /// the capability (attribute 2 bit 7).
    fn acd_start(&self) -> bool;
    /// Status bits 6 (conflict detected) and 7 (address not used).
    fn acd_status(&self, conflict: bool, fault: bool);
    /// Records a conflict in attribute 11.
    fn acd_conflict(&self, last: LastConflict);
}

impl<D: Device, const S: usize, const C: usize, const F: usize, const L: usize> AcdPort
    for SharedAdapter<D, S, C, F, L>
{
    fn acd_start(&self) -> bool {
        with_adapter_quiet(self, |a| {
            a.set_acd_capable();
            a.acd_selected()
        })
    }

    fn acd_status(&self, conflict: bool, fault: bool) {
        with_adapter_quiet(self, |a| a.set_acd_status(conflict, fault));
    }

    fn acd_conflict(&self, last: LastConflict) {
        with_adapter_quiet(self, |a| a.record_acd_conflict(last));
    }
}

/// The link task's conflict detection.
pub(crate) struct Guard {
    acd: Acd,
    /// Detection runs in this run (`None` until the first [`Guard::follow`] asked).
    active: Option<bool>,
    /// A defence to send as soon as the driver has room.
    defence: bool,
    /// The link was up at the last [`Guard::link`].
    link_up: bool,
}

impl Guard {
    /// Detection for the interface with hardware address `mac`; `seed` spreads the timing.
    pub fn new(mac: [u8; 6], seed: u64) -> Self {
        Guard {
            acd: Acd::new(mac, seed),
            active: None,
            defence: false,
            link_up: false,
        }
    }

    /// Follows the link state at `now`: when the link comes up the address in use or under
    /// test is probed again (RFC 5227 section 2.1: another host may have taken it meanwhile).
    pub fn link(&mut self, up: bool, now: Instant) {
        let came_up = up && !self.link_up;
        self.link_up = up;
        let probing_or_used = !matches!(self.acd.phase(), Phase::Idle | Phase::Fault);
        if came_up && self.active == Some(true) && probing_or_used {
            if self.acd.usable() {
                info!("ACD: link up: probing {} again", self.acd.ip());
            }
            self.acd.start(self.acd.ip(), now);
        }
    }

    /// True if [`Self::follow`] of `ip` and [`Self::link`] of `up` would change nothing:
    /// whether Address Conflict Detection runs is known, and it runs on neither a new address
    /// nor a link that changed.
    pub fn follows(&self, ip: Ipv4Addr, up: bool) -> bool {
        self.link_up == up
            && match self.active {
                Some(active) => !active || ip == self.acd.ip(),
                None => false,
            }
    }

    /// Follows the interface address `ip` at `now`: a new one is probed.
    pub fn follow(&mut self, ip: Ipv4Addr, port: &dyn AcdPort, now: Instant) {
        let active = *self.active.get_or_insert_with(|| port.acd_start());
        if !active || ip == self.acd.ip() {
            return;
        }
        if ip.is_unspecified() {
            self.acd.stop();
        } else {
            info!("ACD: probing {} before using it", ip);
            self.acd.start(ip, now);
            port.acd_status(false, false);
        }
    }

    /// Judges a received frame at `now` if it is an ARP message.
    pub fn receive(&mut self, frame: &[u8], port: &dyn AcdPort, now: Instant) {
        if self.active != Some(true) {
            return;
        }
        let Some(arp) = Arp::from_frame(frame) else {
            return;
        };
        match self.acd.process(&arp, now) {
            Verdict::None => {}
            Verdict::Defend(last) => {
                warn!("ACD: another host claims {}: defending it", self.acd.ip());
                self.defence = true;
                port.acd_conflict(last);
            }
            Verdict::Lost(last) => {
                warn!(
                    "ACD: {} is in use by another host: not using it (address conflict)",
                    self.acd.ip()
                );
                port.acd_conflict(last);
                port.acd_status(true, true);
            }
        }
    }

    /// True if the interface may send from its address.
    pub fn usable(&self) -> bool {
        match self.active {
            Some(true) => self.acd.usable() || self.acd.phase() == Phase::Idle,
            _ => true,
        }
    }

    /// The frame to send at `now`, if any (a defence first); `put_back` it if the driver
    /// had no room.
    pub fn due(&mut self, now: Instant) -> Option<ArpFrame> {
        if core::mem::take(&mut self.defence) {
            return Some(ArpFrame::Announcement);
        }
        let frame = self.acd.dispatch(now);
        if frame.is_some() && self.acd.usable() {
            info!("ACD: {} probed and announced: in use", self.acd.ip());
        }
        frame
    }

    /// A frame [`Guard::due`] gave that could not be sent: an announcement goes at the next
    /// chance (a probe is not repeated: the next comes on time).
    pub fn put_back(&mut self, frame: ArpFrame) {
        self.defence |= frame == ArpFrame::Announcement;
    }

    /// The address probes and announcements are about.
    pub fn ip(&self) -> Ipv4Addr {
        self.acd.ip()
    }

    /// When [`Guard::due`] has the next frame.
    pub fn deadline(&self, now: Instant) -> Option<Instant> {
        if self.defence {
            Some(now)
        } else {
            self.acd.poll_at()
        }
    }
}

/// Whether the network stack's `frame` may go out while the address is not usable: IPv4
/// from 0.0.0.0 only (a DHCP client asking for an address).
pub(crate) fn passes_unaddressed(frame: &[u8]) -> bool {
    frame.get(12..14) == Some(&[0x08, 0x00]) && frame.get(26..30) == Some(&[0; 4])
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::cell::{Cell, RefCell};
    use enip_stack::acd::{Activity, ARP_FRAME_LEN};

    #[derive(Default)]
    struct Port {
        status: Cell<(bool, bool)>,
        last: RefCell<Option<LastConflict>>,
    }

    impl AcdPort for Port {
        fn acd_start(&self) -> bool {
            true
        }
        fn acd_status(&self, conflict: bool, fault: bool) {
            self.status.set((conflict, fault));
        }
        fn acd_conflict(&self, last: LastConflict) {
            *self.last.borrow_mut() = Some(last);
        }
    }

    const IP: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 2);

    #[test]
    fn holds_traffic_back_until_announced_and_after_a_loss() {
        let port = Port::default();
        let mut g = Guard::new([2, 0, 0, 0, 0, 1], 5);
        g.follow(IP, &port, Instant::from_micros(0));
        assert!(!g.usable());
        let mut sent = 0;
        for ms in 0..20_000u64 {
            if g.due(Instant::from_micros(ms * 1000)).is_some() {
                sent += 1;
            }
        }
        assert_eq!(sent, 5);
        assert!(g.usable());
        // A gratuitous ARP from another host: defended, recorded.
        let mut frame = [0u8; ARP_FRAME_LEN];
        ArpFrame::Announcement.write([2, 0, 0, 0, 0, 9], IP, &mut frame);
        let now = Instant::from_micros(21_000_000);
        g.receive(&frame, &port, now);
        assert_eq!(g.due(now), Some(ArpFrame::Announcement));
        let last = port.last.borrow().unwrap();
        assert_eq!(
            (last.activity, last.remote_mac),
            (Activity::Ongoing, [2, 0, 0, 0, 0, 9])
        );
        assert!(g.usable());
        // Again within the defend interval: lost.
        g.receive(&frame, &port, Instant::from_micros(22_000_000));
        assert!(!g.usable());
        assert_eq!(port.status.get(), (true, true));
    }

    #[test]
    fn the_address_is_probed_again_when_the_link_comes_up() {
        let port = Port::default();
        let mut g = Guard::new([2, 0, 0, 0, 0, 1], 5);
        g.follow(IP, &port, Instant::from_micros(0));
        g.link(true, Instant::from_micros(0));
        let mut sent = 0;
        for ms in 0..20_000u64 {
            sent += usize::from(g.due(Instant::from_micros(ms * 1000)).is_some());
        }
        assert_eq!(sent, 5);
        assert!(g.usable());
        // Still up: nothing new. Down, then up: held back and probed afresh.
        g.link(true, Instant::from_micros(20_000_000));
        assert!(g.usable());
        g.link(false, Instant::from_micros(21_000_000));
        assert!(g.usable());
        g.link(true, Instant::from_micros(22_000_000));
        assert!(!g.usable());
        let first = g.deadline(Instant::from_micros(22_000_000)).unwrap();
        assert!(first.as_micros() <= 23_000_000);
    }

    #[test]
    fn only_dhcp_traffic_passes_before_the_address_is_usable() {
        let mut frame = [0u8; 42];
        frame[12..14].copy_from_slice(&[0x08, 0x00]);
        assert!(passes_unaddressed(&frame));
        frame[26..30].copy_from_slice(&IP.octets());
        assert!(!passes_unaddressed(&frame));
        frame[12..14].copy_from_slice(&[0x08, 0x06]);
        frame[26..30].copy_from_slice(&[0; 4]);
        assert!(!passes_unaddressed(&frame));
    }
}
