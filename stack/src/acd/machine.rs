//! [`Acd`]: the Address Conflict Detection state machine of one IPv4 address (RFC 5227 as
//! CIP Volume 2 adopts it for EtherNet/IP), sans-IO: the runtime passes in every received
//! ARP PDU and the time, sends the frames it asks for, and holds back the interface's own
//! traffic until [`Acd::usable`].
//!
//! Probe (section 2.1): after a random wait of 0 to PROBE_WAIT, PROBE_NUM probes
//! (sender address 0.0.0.0) PROBE_MIN to PROBE_MAX apart; any ARP message whose sender
//! address is the one probed, or another host's probe for it, is a conflict and the
//! address is not used. Announce (section 2.3): ANNOUNCE_WAIT after the last probe,
//! ANNOUNCE_NUM announcements ANNOUNCE_INTERVAL apart; the address is used once the last
//! one is out. Ongoing detection (section 2.4, policy (b)): a conflicting ARP message is
//! answered with an announcement, unless another came within DEFEND_INTERVAL: then the
//! address is given up.

use core::net::Ipv4Addr;

use super::arp::{Arp, ArpFrame};
use super::record::{Activity, LastConflict};
use crate::rng::Rng;
use crate::time::{Duration, Instant};

/// Longest random wait before the first probe (RFC 5227 PROBE_WAIT).
pub const PROBE_WAIT: Duration = Duration::from_secs(1);
/// Probes sent (PROBE_NUM).
pub const PROBE_NUM: u8 = 3;
/// Shortest time between two probes (PROBE_MIN).
pub const PROBE_MIN: Duration = Duration::from_secs(1);
/// Longest time between two probes (PROBE_MAX).
pub const PROBE_MAX: Duration = Duration::from_secs(2);
/// Wait after the last probe before the first announcement (ANNOUNCE_WAIT).
pub const ANNOUNCE_WAIT: Duration = Duration::from_secs(2);
/// Announcements sent (ANNOUNCE_NUM).
pub const ANNOUNCE_NUM: u8 = 2;
/// Time between two announcements (ANNOUNCE_INTERVAL).
pub const ANNOUNCE_INTERVAL: Duration = Duration::from_secs(2);
/// Two conflicts closer than this and the address is given up (DEFEND_INTERVAL).
pub const DEFEND_INTERVAL: Duration = Duration::from_secs(10);

/// Where the address stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Phase {
    /// No address under detection.
    Idle,
    /// Probing; `sent` probes are out.
    Probing {
        /// Probes sent so far.
        sent: u8,
    },
    /// Announcing; `sent` announcements are out.
    Announcing {
        /// Announcements sent so far.
        sent: u8,
    },
    /// In use, watched and defended.
    Ongoing,
    /// Another host has it: not used (probing found it, or a second conflict came within
    /// [`DEFEND_INTERVAL`]).
    Fault,
}

/// What a received ARP PDU means for the address.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// Nothing.
    None,
    /// A conflict the address survives: send an [`ArpFrame::Announcement`] now.
    Defend(LastConflict),
    /// A conflict that cost the address (or kept it from being used): [`Phase::Fault`].
    Lost(LastConflict),
}

/// Address Conflict Detection for one interface.
#[derive(Debug, Clone)]
pub struct Acd {
    mac: [u8; 6],
    ip: Ipv4Addr,
    phase: Phase,
    /// When the next probe or announcement is due.
    next: Option<Instant>,
    /// When the address was last defended.
    defended: Option<Instant>,
    rng: Rng,
}

impl Acd {
    /// Detection for the interface with hardware address `mac`, idle; `seed` randomises the
    /// probe timing (two devices powered up together must not probe in step).
    pub fn new(mac: [u8; 6], seed: u64) -> Self {
        Acd {
            mac,
            ip: Ipv4Addr::UNSPECIFIED,
            phase: Phase::Idle,
            next: None,
            defended: None,
            rng: Rng::new(seed),
        }
    }

    /// Starts probing `ip` at `now` (the first probe after a random wait up to
    /// [`PROBE_WAIT`]).
    pub fn start(&mut self, ip: Ipv4Addr, now: Instant) {
        self.ip = ip;
        self.phase = Phase::Probing { sent: 0 };
        self.defended = None;
        self.next = Some(now.add(self.random(Duration(0), PROBE_WAIT)));
    }

    /// Stops detection (the address went away or detection was turned off).
    pub fn stop(&mut self) {
        self.phase = Phase::Idle;
        self.next = None;
    }

    /// The address under detection.
    pub fn ip(&self) -> Ipv4Addr {
        self.ip
    }

    /// Where the address stands.
    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// True once probing and announcing are over without conflict and until the address is
    /// lost: the interface may send from it.
    pub fn usable(&self) -> bool {
        self.phase == Phase::Ongoing
    }

    /// When [`Acd::dispatch`] has the next frame to send.
    pub fn poll_at(&self) -> Option<Instant> {
        self.next
    }

    /// The probe or announcement due at `now`, if any; the caller sends it.
    pub fn dispatch(&mut self, now: Instant) -> Option<ArpFrame> {
        if self.next.is_none_or(|at| now < at) {
            return None;
        }
        match self.phase {
            Phase::Probing { sent } if sent < PROBE_NUM => {
                let sent = sent.saturating_add(1);
                self.phase = Phase::Probing { sent };
                let wait = if sent == PROBE_NUM {
                    ANNOUNCE_WAIT
                } else {
                    self.random(PROBE_MIN, PROBE_MAX)
                };
                self.next = Some(now.add(wait));
                Some(ArpFrame::Probe)
            }
            Phase::Probing { .. } => Some(self.announce(0, now)),
            Phase::Announcing { sent } => Some(self.announce(sent, now)),
            Phase::Idle | Phase::Ongoing | Phase::Fault => {
                self.next = None;
                None
            }
        }
    }

    /// Announcement number `sent + 1`.
    fn announce(&mut self, sent: u8, now: Instant) -> ArpFrame {
        let sent = sent.saturating_add(1);
        if sent >= ANNOUNCE_NUM {
            self.phase = Phase::Ongoing;
            self.next = None;
        } else {
            self.phase = Phase::Announcing { sent };
            self.next = Some(now.add(ANNOUNCE_INTERVAL));
        }
        ArpFrame::Announcement
    }

    /// Judges one received ARP PDU at `now`.
    pub fn process(&mut self, arp: &Arp, now: Instant) -> Verdict {
        if arp.sender_mac == self.mac {
            return Verdict::None;
        }
        let claims = arp.sender_ip == self.ip;
        match self.phase {
            Phase::Probing { .. } => {
                // Another host's probe for the same address counts too (section 2.1.1).
                let probes = arp.sender_ip.is_unspecified() && arp.target_ip == self.ip;
                if claims || probes {
                    return self.lose(arp, Activity::Probe);
                }
            }
            Phase::Announcing { .. } | Phase::Ongoing if claims => {
                let recent = self
                    .defended
                    .is_some_and(|at| now.since(at).as_micros() < DEFEND_INTERVAL.as_micros());
                if recent {
                    return self.lose(arp, Activity::Ongoing);
                }
                self.defended = Some(now);
                return Verdict::Defend(LastConflict::of(Activity::Ongoing, arp));
            }
            _ => {}
        }
        Verdict::None
    }

    /// Gives the address up after `arp`.
    fn lose(&mut self, arp: &Arp, activity: Activity) -> Verdict {
        self.phase = Phase::Fault;
        self.next = None;
        Verdict::Lost(LastConflict::of(activity, arp))
    }

    /// A random duration in `min..=max`.
    fn random(&mut self, min: Duration, max: Duration) -> Duration {
        let span = max.as_micros().saturating_sub(min.as_micros());
        Duration(
            min.as_micros()
                .saturating_add(self.rng.below_or_equal(span)),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::acd::arp::{ARP_FRAME_LEN, OP_REPLY};
    use std::vec::Vec;

    extern crate std;

    const MAC: [u8; 6] = [2, 0, 0, 0, 0, 1];
    const OTHER: [u8; 6] = [2, 0, 0, 0, 0, 0x99];
    const IP: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 2);

    fn at(ms: u64) -> Instant {
        Instant::from_micros(ms * 1000)
    }

    /// Runs `acd` in 1 ms steps from `from` to `to`, returning (ms, frame) of every send.
    fn run(acd: &mut Acd, from: u64, to: u64) -> Vec<(u64, ArpFrame)> {
        (from..to)
            .filter_map(|ms| acd.dispatch(at(ms)).map(|f| (ms, f)))
            .collect()
    }

    /// An ARP PDU from `mac` with sender `sender` and target `target`.
    fn arp(op: u16, mac: [u8; 6], sender: Ipv4Addr, target: Ipv4Addr) -> Arp {
        let mut frame = [0u8; ARP_FRAME_LEN];
        ArpFrame::Announcement.write(mac, target, &mut frame);
        let mut a = Arp::from_frame(&frame).unwrap();
        a.op = op;
        a.sender_ip = sender;
        a
    }

    #[test]
    fn probes_then_announces_within_the_rfc_timing() {
        for seed in 1..50u64 {
            let mut acd = Acd::new(MAC, seed);
            acd.start(IP, at(0));
            let sent = run(&mut acd, 0, 20_000);
            let kinds: Vec<_> = sent.iter().map(|s| s.1).collect();
            use ArpFrame::{Announcement as A, Probe as P};
            assert_eq!(kinds, [P, P, P, A, A], "seed {seed}");
            let t: Vec<u64> = sent.iter().map(|s| s.0).collect();
            assert!(t[0] <= 1000, "first probe within PROBE_WAIT: {t:?}");
            for gap in [t[1] - t[0], t[2] - t[1]] {
                assert!((1000..=2000).contains(&gap), "PROBE_MIN..MAX: {t:?}");
            }
            assert_eq!(t[3] - t[2], 2000, "ANNOUNCE_WAIT");
            assert_eq!(t[4] - t[3], 2000, "ANNOUNCE_INTERVAL");
            // Usable only once the last announcement is out.
            let mut again = Acd::new(MAC, seed);
            again.start(IP, at(0));
            run(&mut again, 0, t[4]);
            assert!(!again.usable());
            run(&mut again, t[4], t[4] + 1);
            assert!(again.usable() && again.poll_at().is_none());
        }
        // The seed spreads the first probe.
        let first = |seed| {
            let mut acd = Acd::new(MAC, seed);
            acd.start(IP, at(0));
            acd.poll_at().unwrap()
        };
        assert_ne!(first(1), first(2));
    }

    #[test]
    fn a_reply_or_a_probe_for_the_address_while_probing_refuses_it() {
        let reply = arp(OP_REPLY, OTHER, IP, Ipv4Addr::UNSPECIFIED);
        let probe = arp(1, OTHER, Ipv4Addr::UNSPECIFIED, IP);
        for conflict in [reply, probe] {
            let mut acd = Acd::new(MAC, 7);
            acd.start(IP, at(0));
            run(&mut acd, 0, 1500);
            let Verdict::Lost(last) = acd.process(&conflict, at(1500)) else {
                panic!("no conflict");
            };
            assert_eq!(last.activity, Activity::Probe);
            assert_eq!((last.remote_mac, last.pdu), (OTHER, conflict.raw));
            assert_eq!(acd.phase(), Phase::Fault);
            assert!(run(&mut acd, 1500, 20_000).is_empty() && !acd.usable());
        }
    }

    #[test]
    fn unrelated_arp_and_own_frames_are_no_conflict() {
        let mut acd = Acd::new(MAC, 7);
        acd.start(IP, at(0));
        let other_ip = Ipv4Addr::new(198, 18, 0, 1);
        // Someone asking for our address (the kernel resolving it) is not a claim.
        assert_eq!(
            acd.process(&arp(1, OTHER, other_ip, IP), at(1)),
            Verdict::None
        );
        // Our own probe, reflected.
        let own = arp(1, MAC, Ipv4Addr::UNSPECIFIED, IP);
        assert_eq!(acd.process(&own, at(2)), Verdict::None);
        run(&mut acd, 0, 20_000);
        assert!(acd.usable());
        assert_eq!(
            acd.process(&arp(1, OTHER, other_ip, IP), at(20_001)),
            Verdict::None
        );
        // Another host's probe for our address in use: the ARP layer answers it, no conflict.
        let probe = arp(1, OTHER, Ipv4Addr::UNSPECIFIED, IP);
        assert_eq!(acd.process(&probe, at(20_002)), Verdict::None);
    }

    #[test]
    fn defends_once_then_gives_up_within_the_defend_interval() {
        let mut acd = Acd::new(MAC, 3);
        acd.start(IP, at(0));
        run(&mut acd, 0, 20_000);
        let gratuitous = arp(1, OTHER, IP, IP);
        let Verdict::Defend(last) = acd.process(&gratuitous, at(20_000)) else {
            panic!("not defended");
        };
        assert_eq!((last.activity, last.remote_mac), (Activity::Ongoing, OTHER));
        assert!(acd.usable());
        // A second one 10 s later is defended again; one within 10 s of that costs it.
        assert!(matches!(
            acd.process(&gratuitous, at(30_000)),
            Verdict::Defend(_)
        ));
        assert!(matches!(
            acd.process(&gratuitous, at(39_999)),
            Verdict::Lost(_)
        ));
        assert_eq!(acd.phase(), Phase::Fault);
        assert!(!acd.usable());
        // Stopped and started again, it probes afresh.
        acd.stop();
        acd.start(IP, at(50_000));
        assert!(matches!(acd.phase(), Phase::Probing { sent: 0 }));
        assert_eq!(run(&mut acd, 50_000, 70_000).len(), 5);
    }
}
