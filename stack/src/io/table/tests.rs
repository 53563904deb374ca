//! The table's timing intents against a model of the rules written out plainly (an RPI grid
//! `next` and a separate trigger deadline, as the connection entries kept them before the
//! table owned them): after any sequence of opens, feeds, triggers, productions, expiries and
//! closes, every slot's watchdog and deadline, the first producer and the next deadline are
//! what the model says.

use core::net::{Ipv4Addr, SocketAddrV4};

use super::*;
use crate::cip::status::CipResult;
use crate::config::FIRST_PACKET_GRACE_US;
use crate::device::{AssemblyInfo, AssemblyRole, ConnectionPoints, IdentityInfo};
use crate::io::connection::Consumer;
use crate::time::Duration;

/// Input assemblies the producers produce (triggered by instance).
const INPUTS: [u16; 2] = [100, 101];

struct Block;

const ASSEMBLIES: [AssemblyInfo; 3] = [
    AssemblyInfo {
        instance: 100,
        role: AssemblyRole::Input,
        size: 4,
        run_idle_header: false,
    },
    AssemblyInfo {
        instance: 101,
        role: AssemblyRole::Input,
        size: 4,
        run_idle_header: false,
    },
    AssemblyInfo {
        instance: 150,
        role: AssemblyRole::Output,
        size: 4,
        run_idle_header: true,
    },
];

const IDENTITY: IdentityInfo = IdentityInfo {
    vendor_id: 1,
    device_type: 0x0C,
    product_code: 1,
    revision: (1, 1),
    serial_number: 1,
    product_name: "table test",
};

impl Device for Block {
    fn identity(&self) -> &IdentityInfo {
        &IDENTITY
    }
    fn assemblies(&self) -> &[AssemblyInfo] {
        &ASSEMBLIES
    }
    fn read_assembly(&mut self, _instance: u16, out: &mut [u8]) -> CipResult<usize> {
        out.fill(0x5A);
        Ok(out.len())
    }
    fn write_assembly(&mut self, _instance: u16, _data: &[u8]) -> CipResult {
        Ok(())
    }
}

/// A small deterministic generator (xorshift64).
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: u64) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0 % n
    }
}

/// One slot as the model sees it.
#[derive(Debug, Clone, Copy)]
struct Model {
    expires: Instant,
    last: Instant,
    timeout: u64,
    /// The producer: RPI, inhibit, whether triggers count, the grid's next point, the
    /// inhibit time's end and whether a trigger waits.
    producer: Option<ModelProducer>,
}

#[derive(Debug, Clone, Copy)]
struct ModelProducer {
    instance: u16,
    rpi: u64,
    inhibit: u64,
    triggers: bool,
    next: u64,
    inhibit_until: u64,
    triggered: bool,
    /// Cyclic, before its first production: then it moves onto the clock's grid.
    to_clock_grid: bool,
}

impl ModelProducer {
    fn due(&self) -> u64 {
        if self.triggered {
            self.inhibit_until.min(self.next)
        } else {
            self.next
        }
    }
}

fn connection<const C: usize>(rng: &mut Rng, table: &ConnectionTable<C>, n: u16) -> Connection {
    let kind = match rng.below(4) {
        0 => Kind::Explicit,
        1 => Kind::ListenOnly,
        2 => Kind::InputOnly,
        _ => Kind::ExclusiveOwner,
    };
    let rpi = [1_000, 2_000, 3_000, 10_000][rng.below(4) as usize];
    let timeout = Duration::from_micros(rpi * (4 << rng.below(3)));
    let trigger = [
        Trigger::Cyclic,
        Trigger::ChangeOfState,
        Trigger::Application,
    ][rng.below(3) as usize];
    let instance = INPUTS[rng.below(2) as usize];
    let producer = Producer {
        instance,
        size: 4,
        destination: SocketAddrV4::new(Ipv4Addr::new(239, 192, 1, 0), 2222),
        inhibit: Duration::from_micros([0, 500, 2_500][rng.below(3) as usize]),
        trigger,
        encap_sequence: 0,
        sequence: 0,
        dscp: 47,
        priority: 0,
        variable: false,
    };
    let consumer = Consumer {
        instance: 150,
        size: 4,
        run_idle: true,
        last_sequence: None,
        last_encap_sequence: None,
        run: false,
    };
    // A listen-only follows an open producer's T->O ID when there is one.
    let followed = table
        .iter()
        .find(|(_, c)| c.producer().is_some())
        .map(|(_, c)| c.t_o_id);
    let transport = match kind {
        Kind::Explicit => Transport::Class3 {
            last_sequence: None,
        },
        Kind::ListenOnly => Transport::Class1 {
            consumer,
            producer: None,
        },
        _ => Transport::Class1 {
            consumer,
            producer: Some(producer),
        },
    };
    Connection {
        kind,
        triad: Triad {
            connection_serial: n,
            vendor_id: 1,
            originator_serial: 7,
        },
        originator: Ipv4Addr::new(198, 18, 0, 2),
        points: ConnectionPoints::default(),
        socket: 0,
        o_t_id: 0,
        t_o_id: match kind {
            Kind::ListenOnly => followed.unwrap_or(0x7000_0000 | u32::from(n)),
            _ => 0x1000_0000 | u32::from(n),
        },
        o_t_rpi: rpi as u32,
        t_o_rpi: rpi as u32,
        timeout,
        transport,
    }
}

/// Checks every slot and summary of `table` against `model`.
fn check<const C: usize>(table: &ConnectionTable<C>, model: &[Option<Model>; C], now: Instant) {
    table.timing.assert_consistent();
    let mut earliest = u64::MAX;
    let mut first: Option<(u64, usize)> = None;
    for (slot, m) in model.iter().enumerate() {
        assert_eq!(
            table.get(slot).is_some(),
            m.is_some(),
            "slot {slot} occupied"
        );
        let Some(m) = m else {
            assert_eq!(table.timing.expires(slot), Instant::NEVER, "empty {slot}");
            assert_eq!(table.timing.next_production(slot), Instant::NEVER);
            continue;
        };
        assert_eq!(table.expires(slot), Some(m.expires), "slot {slot} expiry");
        assert_eq!(
            table.last_activity(slot),
            Some(m.last),
            "slot {slot} activity"
        );
        let due = m.producer.map(|p| p.due());
        assert_eq!(
            table.next_production(slot),
            due.map(Instant),
            "slot {slot} due"
        );
        earliest = earliest.min(m.expires.0);
        if let Some(due) = due {
            earliest = earliest.min(due);
            if first.is_none_or(|(at, _)| due < at) {
                first = Some((due, slot));
            }
        }
    }
    let expected = (earliest != u64::MAX).then_some(Instant(earliest));
    assert_eq!(table.next_deadline(), expected, "next deadline at {now:?}");
    let due = first.filter(|&(at, _)| at <= now.0).map(|(_, slot)| slot);
    assert_eq!(table.due(now), due, "producer due at {now:?}");
}

#[test]
fn any_sequence_of_intents_keeps_every_deadline_and_summary_right() {
    any_sequence_of_intents::<MAX_CONNECTIONS>();
}

#[test]
fn any_sequence_of_intents_at_64_connections() {
    any_sequence_of_intents::<64>();
}

/// Random intents on a table of `C` slots, each checked against a model of every slot.
fn any_sequence_of_intents<const C: usize>() {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    for _round in 0..20 {
        let mut table = ConnectionTable::<C>::new(0x100);
        let mut device = Block;
        let mut model: [Option<Model>; C] = [None; C];
        let mut now = 1_000u64;
        for n in 0..1_500u16 {
            let at = Instant(now);
            match rng.below(16) {
                0..=2 => {
                    let conn = connection(&mut rng, &table, n);
                    let m = Model {
                        expires: at.add(Duration::from_micros(
                            conn.timeout.as_micros().max(FIRST_PACKET_GRACE_US),
                        )),
                        last: at,
                        timeout: conn.timeout.as_micros(),
                        producer: conn.producer().map(|p| ModelProducer {
                            instance: p.instance,
                            rpi: u64::from(conn.t_o_rpi),
                            inhibit: p.inhibit.as_micros(),
                            triggers: p.trigger != Trigger::Cyclic,
                            next: now,
                            inhibit_until: now,
                            triggered: false,
                            to_clock_grid: p.trigger == Trigger::Cyclic,
                        }),
                    };
                    if let Some(slot) = table.open(conn, at) {
                        model[slot] = Some(m);
                    }
                }
                3..=5 => {
                    let slot = rng.below(C as u64) as usize;
                    table.feed(slot, at);
                    if let Some(m) = &mut model[slot] {
                        m.expires = Instant(now + m.timeout);
                        m.last = at;
                    }
                }
                6 | 7 => {
                    let instance = INPUTS[rng.below(2) as usize];
                    let all = rng.below(4) == 0;
                    if all {
                        table.trigger_all();
                    } else {
                        table.trigger(instance);
                    }
                    for p in model
                        .iter_mut()
                        .flatten()
                        .filter_map(|m| m.producer.as_mut())
                    {
                        if p.triggers && (all || p.instance == instance) {
                            p.triggered = true;
                        }
                    }
                }
                8..=10 => {
                    // Everything due goes, in the order the model expects. A production that
                    // is declined (no room for the datagram), or names another T->O ID (a
                    // connection closed and reopened since), moves nothing.
                    while let Some(slot) = table.due(at) {
                        let stale = table.get(slot).map(|c| c.t_o_id ^ 1);
                        assert_eq!(table.produce(slot, stale, at, |_, _, _| Some(())), None);
                        assert_eq!(table.produce(slot, None, at, |_, _, _| None::<()>), None);
                        check(&table, &model, at);
                        let p = model[slot].as_mut().and_then(|m| m.producer.as_mut());
                        let p = p.expect("only a producer is due");
                        let triggered = table.produce(slot, None, at, |_, _, t| Some(t));
                        assert_eq!(triggered, Some(p.triggered), "slot {slot} triggered");
                        if p.triggered {
                            (p.triggered, p.inhibit_until) = (false, now + p.inhibit);
                            p.next = now + p.rpi;
                        } else if p.to_clock_grid {
                            // The first point of the table's grid one RPI on, and after now.
                            p.to_clock_grid = false;
                            let phase = u64::from(table.grid_phase(p.rpi as u32));
                            let earliest = (p.next + p.rpi).max(now + 1);
                            p.next = phase + (earliest - phase).div_ceil(p.rpi) * p.rpi;
                        } else {
                            while p.next <= now {
                                p.next += p.rpi;
                            }
                        }
                        check(&table, &model, at);
                    }
                }
                11 => {
                    let slot = rng.below(C as u64) as usize;
                    table.close(slot, CloseReason::ForwardClose, &mut device);
                }
                12 => {
                    table.expire(at, &mut device);
                    for (slot, m) in model.iter().enumerate() {
                        if m.is_some_and(|m| m.expires <= at) {
                            assert!(table.get(slot).is_none(), "slot {slot} expired");
                        }
                    }
                }
                13 => now += FIRST_PACKET_GRACE_US / 2 + rng.below(20_000),
                _ => now += rng.below(6_000),
            }
            // A close takes the listen-only connections that follow it along: the model
            // follows the table's slots (their timing is what is checked).
            for (slot, m) in model.iter_mut().enumerate() {
                if table.get(slot).is_none() {
                    *m = None;
                }
            }
            check(&table, &model, Instant(now));
        }
    }
}

#[test]
fn a_closed_slot_reopens_with_fresh_timing() {
    let mut rng = Rng(7);
    let mut table: ConnectionTable = ConnectionTable::new(1);
    let mut device = Block;
    let conn = loop {
        let c = connection(&mut rng, &table, 1);
        if c.producer().is_some_and(|p| p.trigger != Trigger::Cyclic) {
            break c;
        }
    };
    let slot = table.open(conn.clone(), Instant(0)).unwrap();
    table.trigger_all();
    table.feed(slot, Instant(500));
    table.close(slot, CloseReason::ForwardClose, &mut device);
    assert_eq!(table.next_deadline(), None);
    assert_eq!(table.expires(slot), None);
    assert_eq!(table.open(conn, Instant(9_000)), Some(slot));
    assert!(!table.timing.triggered(slot), "no trigger carried over");
    assert_eq!(table.next_production(slot), Some(Instant(9_000)));
    assert_eq!(table.last_activity(slot), Some(Instant(9_000)));
}

/// [`Block`] with its output assembly shrunk to 2 bytes: a connection consuming 4 of it no
/// longer fits; its inputs are unchanged.
struct OutputShrunk;

const SHRUNK: [AssemblyInfo; 2] = [
    ASSEMBLIES[0],
    AssemblyInfo {
        size: 2,
        ..ASSEMBLIES[2]
    },
];

impl Device for OutputShrunk {
    fn identity(&self) -> &IdentityInfo {
        &IDENTITY
    }
    fn assemblies(&self) -> &[AssemblyInfo] {
        &SHRUNK
    }
    fn read_assembly(&mut self, _instance: u16, out: &mut [u8]) -> CipResult<usize> {
        out.fill(0x5A);
        Ok(out.len())
    }
    fn write_assembly(&mut self, _instance: u16, _data: &[u8]) -> CipResult {
        Ok(())
    }
}

#[test]
fn an_output_resized_under_a_shared_production_leaves_it_to_its_sharer() {
    let mut table: ConnectionTable = ConnectionTable::new(1);
    // An exclusive owner consuming output 150 and producing input 100 to the group, and an
    // input-only connection that joined that production.
    let mut rng = Rng(3);
    let owner = loop {
        let c = connection(&mut rng, &table, 1);
        if c.kind == Kind::ExclusiveOwner {
            break c;
        }
    };
    let owner = Connection {
        transport: match owner.transport {
            Transport::Class1 { consumer, producer } => Transport::Class1 {
                consumer,
                producer: producer.map(|p| Producer {
                    instance: 100,
                    trigger: Trigger::Cyclic,
                    ..p
                }),
            },
            t => t,
        },
        ..owner
    };
    let t_o_id = owner.t_o_id;
    let follower = Connection {
        kind: Kind::InputOnly,
        triad: Triad {
            connection_serial: 2,
            ..owner.triad
        },
        transport: Transport::Class1 {
            consumer: Consumer {
                instance: 152,
                size: 0,
                run_idle: false,
                last_sequence: None,
                last_encap_sequence: None,
                run: false,
            },
            producer: None,
        },
        ..owner.clone()
    };
    let producer = table.open(owner, Instant(0)).unwrap();
    let sharer = table.open(follower, Instant(0)).unwrap();
    assert!(table
        .get(producer)
        .is_some_and(Connection::produces_multicast));

    // The output shrinks: the owner closes, but input 100 still fits its production, which
    // goes on in the input-only connection.
    table.close_resized(&mut OutputShrunk);
    assert!(table.get(producer).is_none());
    let heir = table
        .get(sharer)
        .expect("the input-only connection stays open");
    assert_eq!(heir.t_o_id, t_o_id);
    assert!(heir.produces_multicast());
    assert!(table.next_production(sharer).is_some());
}
