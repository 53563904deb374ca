//! The chaos soak's schedule: an endless sequence of steps (a pause, a fault kind, a
//! parameter) drawn from a seed by SplitMix64, so that the same seed gives the same schedule
//! whatever the board does.

use std::fmt;
use std::time::Duration;

/// A kind of fault, with its weight in the schedule (per 100 steps).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Reconnect churn: sessions opened, a connection opened and closed, closed.
    Churn,
    /// One request of the hostile battery.
    Hostile,
    /// A link flap of 0.1-2 s.
    LinkFlap,
    /// An Identity Reset (type 0, or 1 one time in four).
    Reset,
    /// A value set in the non-volatile store (TCP/IP host name, a QoS DSCP).
    NvWrite,
    /// A burst of back-to-back explicit requests.
    ExplicitBurst,
    /// Extra Class 1 connections at 1 ms for a while.
    Class1Burst,
}

/// Every kind with its weight.
const WEIGHTS: [(Kind, u64); 7] = [
    (Kind::Churn, 18),
    (Kind::Hostile, 24),
    (Kind::LinkFlap, 8),
    (Kind::Reset, 8),
    (Kind::NvWrite, 14),
    (Kind::ExplicitBurst, 14),
    (Kind::Class1Burst, 14),
];

impl Kind {
    /// Its name in the report.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Churn => "reconnect_churn",
            Kind::Hostile => "hostile_request",
            Kind::LinkFlap => "link_flap",
            Kind::Reset => "identity_reset",
            Kind::NvWrite => "nv_write",
            Kind::ExplicitBurst => "explicit_burst",
            Kind::Class1Burst => "class1_burst",
        }
    }
}

/// One step of the schedule.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Step {
    /// Pause before it.
    pub pause: Duration,
    /// What is injected.
    pub kind: Kind,
    /// Its parameter (what each fault takes from it is in `chaos.rs`).
    pub param: u64,
}

impl fmt::Display for Step {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "+{}ms {}({})",
            self.pause.as_millis(),
            self.kind.name(),
            self.param % 10_000
        )
    }
}

/// The schedule of a seed.
pub struct Plan(u64);

impl Plan {
    /// The schedule of `seed`.
    pub fn new(seed: u64) -> Plan {
        Plan(seed)
    }

    /// SplitMix64.
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}

impl Iterator for Plan {
    type Item = Step;

    fn next(&mut self) -> Option<Step> {
        let pause = Duration::from_millis(300 + self.next_u64() % 2200);
        let total: u64 = WEIGHTS.iter().map(|(_, w)| w).sum();
        let mut pick = self.next_u64() % total;
        let mut kind = Kind::Churn;
        for (k, w) in WEIGHTS {
            if pick < w {
                kind = k;
                break;
            }
            pick -= w;
        }
        let param = self.next_u64();
        Some(Step { pause, kind, param })
    }
}

#[test]
fn chaos_plan_same_seed_same_schedule() {
    let a: Vec<Step> = Plan::new(7).take(500).collect();
    let b: Vec<Step> = Plan::new(7).take(500).collect();
    let c: Vec<Step> = Plan::new(8).take(500).collect();
    assert_eq!(a, b);
    assert_ne!(a, c);
    for (kind, _) in WEIGHTS {
        assert!(a.iter().any(|s| s.kind == kind), "{kind:?} never drawn");
    }
    assert!(a
        .iter()
        .all(|s| (300..2500).contains(&(s.pause.as_millis() as u64))));
}
