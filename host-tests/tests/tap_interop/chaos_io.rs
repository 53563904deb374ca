//! The chaos soak's steady load: Class 1 connections at a 1 ms RPI fed and watched for the
//! whole run (every T->O gap longer than [`GAP`] recorded with its window), and explicit
//! messaging every [`EXPLICIT_PERIOD`] on a session of its own (every failed request
//! recorded with its time). The scheduler in `chaos.rs` replaces the connections a fault
//! ended; a gap spans the replacement, from the old connection's last T->O to the new one's
//! first.

use std::io::{self, ErrorKind};
use std::net::{Ipv4Addr, SocketAddrV4, UdpSocket};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use crate::common::REPLY;
use crate::fault_io::{IO_PORT, SCANNER_PRIORITY};
use crate::faults::session;
use enip_stack::originator;
use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use enip_stack::wire::io_datagram::Packet;
use host_tests::faults::real_time_thread;
use host_tests::rig::BOARD_IP;
use host_tests::scanner::Opened;

/// The RPI of every Class 1 connection of the soak.
pub const RPI: Duration = Duration::from_millis(1);
/// A T->O interval longer than this is a gap that a fault must explain (the connections'
/// watchdog is x32, 32 ms: a gap this long is one the originator would see as a hiccup).
pub const GAP: Duration = Duration::from_millis(20);
/// A stall of the host's own 1 ms timer loop longer than this is recorded.
pub const HOST_STALL: Duration = Duration::from_millis(10);
/// The explicit load's request period.
pub const EXPLICIT_PERIOD: Duration = Duration::from_millis(10);

/// One connection the sender feeds; `tracked` ones are watched for gaps.
#[derive(Debug, Clone, Copy)]
pub struct Slot {
    /// The open connection, `None` while being replaced or after its close.
    pub conn: Option<Opened>,
    /// Watched for gaps (the steady connections; not the short bursts).
    pub tracked: bool,
}

/// A T->O gap of a tracked slot: from its last T->O to the next one.
#[derive(Debug, Clone, Copy)]
pub struct Gap {
    /// Slot index.
    pub slot: usize,
    /// Last T->O before the gap.
    pub from: Instant,
    /// First T->O after it (the end of the run if none came).
    pub to: Instant,
}

/// What the load threads and the scheduler share.
#[derive(Debug, Default)]
pub struct Load {
    /// The fed connections.
    pub slots: Mutex<Vec<Slot>>,
    /// Per slot, the arrival of its last T->O.
    pub last: Mutex<Vec<Option<Instant>>>,
    /// Gaps seen so far.
    pub gaps: Mutex<Vec<Gap>>,
    /// T->O datagrams received.
    pub t_o: AtomicU64,
    /// O->T datagrams sent, and sends the kernel refused (the link down).
    pub o_t: AtomicU64,
    pub send_errors: AtomicU64,
    /// Explicit requests answered with status 0.
    pub explicit_ok: AtomicU64,
    /// When explicit requests failed (no reply in time, connection lost, bad status).
    pub explicit_failures: Mutex<Vec<Instant>>,
    /// Stalls of a 1 ms sleep loop beside the scanner, at its priority: (from, to).
    pub host_stalls: Mutex<Vec<(Instant, Instant)>>,
    /// Set to end the load threads.
    pub stop: AtomicBool,
}

impl Load {
    /// Puts `conn` in slot `i` (growing the table), keeping the slot's last arrival so that a
    /// gap spans a replacement.
    pub fn set(&self, i: usize, conn: Option<Opened>, tracked: bool) {
        let mut slots = self.slots.lock().unwrap_or_else(|e| e.into_inner());
        let mut last = self.last.lock().unwrap_or_else(|e| e.into_inner());
        if slots.len() <= i {
            slots.resize(
                i + 1,
                Slot {
                    conn: None,
                    tracked: false,
                },
            );
            last.resize(i + 1, None);
        }
        slots[i] = Slot { conn, tracked };
        if !tracked {
            last[i] = None;
        }
    }

    /// The connection in slot `i`.
    pub fn conn(&self, i: usize) -> Option<Opened> {
        let slots = self.slots.lock().unwrap_or_else(|e| e.into_inner());
        slots.get(i).and_then(|s| s.conn)
    }

    /// The last T->O arrival of slot `i`.
    pub fn last_arrival(&self, i: usize) -> Option<Instant> {
        let last = self.last.lock().unwrap_or_else(|e| e.into_inner());
        last.get(i).copied().flatten()
    }

    /// Closes the open gaps of the tracked slots at `end` (called when the load stops).
    pub fn close_gaps(&self, end: Instant) {
        let slots = self.slots.lock().unwrap_or_else(|e| e.into_inner());
        let last = self.last.lock().unwrap_or_else(|e| e.into_inner());
        let mut gaps = self.gaps.lock().unwrap_or_else(|e| e.into_inner());
        for (i, (s, at)) in slots.iter().zip(last.iter()).enumerate() {
            if let (true, Some(at)) = (s.tracked, at) {
                if end.duration_since(*at) > GAP {
                    gaps.push(Gap {
                        slot: i,
                        from: *at,
                        to: end,
                    });
                }
            }
        }
    }
}

/// Runs the Class 1 sender and receiver (under SCHED_FIFO [`SCANNER_PRIORITY`]) and the
/// explicit load until `load.stop`; call from a thread inside the rig's namespace.
pub fn run(load: &Load) -> io::Result<()> {
    let udp = UdpSocket::bind(SocketAddrV4::new(Ipv4Addr::UNSPECIFIED, IO_PORT))?;
    udp.set_read_timeout(Some(Duration::from_millis(5)))?;
    let sender = udp.try_clone()?;
    std::thread::scope(|s| {
        let explicit = s.spawn(|| explicit(load));
        real_time_thread(SCANNER_PRIORITY)?;
        let send = s.spawn(|| send(&sender, load));
        let floor = s.spawn(|| host_floor(load));
        let got = receive(&udp, load);
        load.stop.store(true, Ordering::Relaxed);
        let sent = send
            .join()
            .map_err(|_| io::Error::other("sender panicked"))?;
        floor
            .join()
            .map_err(|_| io::Error::other("timer floor panicked"))?;
        let asked = explicit
            .join()
            .map_err(|_| io::Error::other("explicit load panicked"))?;
        got.and(sent).and(asked)
    })
}

/// Records every T->O: counts it, and a gap if its slot was silent longer than [`GAP`].
fn receive(udp: &UdpSocket, load: &Load) -> io::Result<()> {
    let mut buf = [0u8; 1500];
    while !load.stop.load(Ordering::Relaxed) {
        let n = match udp.recv_from(&mut buf) {
            Ok((n, _)) => n,
            Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => continue,
            Err(e) => return Err(e),
        };
        let Ok(p) = Packet::new_checked(&buf[..n]) else {
            continue;
        };
        let now = Instant::now();
        load.t_o.fetch_add(1, Ordering::Relaxed);
        let slots = load.slots.lock().unwrap_or_else(|e| e.into_inner());
        let Some(i) = slots
            .iter()
            .position(|s| s.conn.is_some_and(|c| c.t_o_id == p.connection_id()))
        else {
            continue;
        };
        let tracked = slots[i].tracked;
        drop(slots);
        let mut last = load.last.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(prev) = last.get_mut(i) {
            if let (true, Some(from)) = (tracked, *prev) {
                if now.duration_since(from) > GAP {
                    let gap = Gap {
                        slot: i,
                        from,
                        to: now,
                    };
                    load.gaps
                        .lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .push(gap);
                }
            }
            *prev = Some(now);
        }
    }
    Ok(())
}

/// The host's timer floor: a 1 ms sleep loop at the scanner's priority, recording every
/// stall longer than [`HOST_STALL`] (when it stalls, the scanner's threads may too, and a
/// T->O gap then says nothing of the adapter).
fn host_floor(load: &Load) {
    let mut prev = Instant::now();
    while !load.stop.load(Ordering::Relaxed) {
        std::thread::sleep(RPI);
        let now = Instant::now();
        if now.duration_since(prev) > HOST_STALL {
            let mut stalls = load.host_stalls.lock().unwrap_or_else(|e| e.into_inner());
            stalls.push((prev, now));
        }
        prev = now;
    }
}

/// O->T to every open slot each [`RPI`], at absolute deadlines.
fn send(udp: &UdpSocket, load: &Load) -> io::Result<()> {
    let to = SocketAddrV4::new(BOARD_IP, IO_PORT);
    let start = Instant::now();
    let mut buf = [0u8; 128];
    for tick in 1u32.. {
        if load.stop.load(Ordering::Relaxed) {
            break;
        }
        if let Some(wait) = (start + RPI * tick).checked_duration_since(Instant::now()) {
            std::thread::sleep(wait);
        }
        let conns: Vec<Opened> = {
            let slots = load.slots.lock().unwrap_or_else(|e| e.into_inner());
            slots.iter().filter_map(|s| s.conn).collect()
        };
        for c in conns {
            let owner = c.o_t_data > 0;
            let (run, data) = if owner {
                (Some(true), &[tick as u8; 32][..])
            } else {
                (None, &[][..])
            };
            let n = originator::io_datagram(&mut buf, c.o_t_id, tick, tick as u16, run, data)
                .map_err(|e| io::Error::other(format!("{e:?}")))?;
            match udp.send_to(&buf[..n], to) {
                Ok(_) => load.o_t.fetch_add(1, Ordering::Relaxed),
                Err(_) => load.send_errors.fetch_add(1, Ordering::Relaxed),
            };
        }
    }
    Ok(())
}

/// Reads the Identity product name every [`EXPLICIT_PERIOD`] on a session of its own,
/// reconnecting after a failure.
fn explicit(load: &Load) -> io::Result<()> {
    let name = [
        SegmentRepr::Logical(LogicalType::Class, 1),
        SegmentRepr::Logical(LogicalType::Instance, 1),
        SegmentRepr::Logical(LogicalType::Attribute, 7),
    ];
    let fail = |load: &Load| {
        let mut f = load
            .explicit_failures
            .lock()
            .unwrap_or_else(|e| e.into_inner());
        f.push(Instant::now());
    };
    let mut s = None;
    while !load.stop.load(Ordering::Relaxed) {
        std::thread::sleep(EXPLICIT_PERIOD);
        let Some(sess) = s.as_mut() else {
            match session() {
                Ok(new) => s = Some(new),
                Err(_) => {
                    fail(load);
                    std::thread::sleep(REPLY / 4);
                }
            }
            continue;
        };
        match sess.request(0x0E, &name, &[]) {
            Ok(r) if r.general == 0 => {
                load.explicit_ok.fetch_add(1, Ordering::Relaxed);
            }
            _ => {
                fail(load);
                s = None;
            }
        }
    }
    Ok(())
}
