//! Class 1 traffic for the fault tests that break things while I/O runs (link flap, Identity
//! Reset): O->T to each connection at its own RPI while it is fed, every T->O recorded with
//! its arrival instant. A failed send (the link is down) is counted, not fatal.

use std::io::{self, ErrorKind};
use std::net::{SocketAddrV4, UdpSocket};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use enip_stack::originator;
use enip_stack::wire::forward_open::ForwardOpenReplyRepr;
use enip_stack::wire::io_datagram::Packet;
use host_tests::faults::{ms, pid_in, real_time_process, real_time_thread};
use host_tests::rig::{Rig, BOARD_IP};

/// Class 1 UDP port.
pub const IO_PORT: u16 = 2222;
/// SCHED_FIFO priority of the scanner's I/O threads and of the board under test.
pub const SCANNER_PRIORITY: i32 = 10;

/// Puts every thread of the rig's board under SCHED_FIFO [`SCANNER_PRIORITY`], as a device
/// on its own CPU: at normal priority on this shared VM the board stalls for more than a
/// 40 ms timeout, and on resuming it times connections out before it reads the O->T
/// datagrams queued meanwhile.
pub fn board_real_time(rig: &Rig) {
    let pid = pid_in(rig.ns(), "enip-host").expect("board pid");
    real_time_process(pid, SCANNER_PRIORITY).expect("SCHED_FIFO for the board");
}

/// One connection to feed with O->T.
#[derive(Debug)]
pub struct Feed {
    /// O->T connection ID to send with.
    pub o_t_id: u32,
    /// O->T period.
    pub rpi: Duration,
    /// O->T carries a run/idle header and 32 data bytes (an exclusive owner).
    pub owner: bool,
    /// O->T is sent while this is set.
    pub fed: AtomicBool,
}

impl Feed {
    /// A fed connection from its Forward_Open reply.
    pub fn new(reply: &ForwardOpenReplyRepr<'_>, rpi: Duration, owner: bool) -> Feed {
        Feed {
            o_t_id: reply.o_t_connection_id,
            rpi,
            owner,
            fed: AtomicBool::new(true),
        }
    }

    /// Stops its O->T from now on.
    pub fn starve(&self) {
        self.fed.store(false, Ordering::Relaxed);
    }
}

/// What one run of [`drive`] saw.
#[derive(Debug, Default)]
pub struct Traffic {
    /// Every T->O datagram: (arrival, connection ID, sequence number).
    pub t_o: Vec<(Instant, u32, u32)>,
    /// Per feed (same order), when its last O->T was handed to the kernel.
    pub last_sent: Vec<Option<Instant>>,
    /// Per feed, the longest time between two of its O->T while fed (this machine's
    /// scheduling of the sender).
    pub max_gap: Vec<Duration>,
    /// O->T sends the kernel refused.
    pub send_errors: u64,
}

impl Traffic {
    /// Arrivals of T->O connection `id` (in order).
    pub fn arrivals(&self, id: u32) -> impl Iterator<Item = Instant> + '_ {
        self.t_o
            .iter()
            .filter(move |(_, c, _)| *c == id)
            .map(|(at, _, _)| *at)
    }

    /// The last T->O of `id` before `before`.
    pub fn last_before(&self, id: u32, before: Instant) -> Option<Instant> {
        self.arrivals(id).filter(|at| *at < before).max()
    }

    /// The first T->O of `id` after `after`.
    pub fn first_after(&self, id: u32, after: Instant) -> Option<Instant> {
        self.arrivals(id).find(|at| *at > after)
    }
}

/// Feeds `feeds` through `udp` (bound to [`IO_PORT`] in the namespace) and records T->O until
/// `end`, from the calling thread and one more, both under SCHED_FIFO priority
/// [`SCANNER_PRIORITY`] from now on: this shared VM stalls plain threads for tens of
/// milliseconds, and a stalled scanner is a silent originator the adapter rightly times out.
pub fn drive(udp: &UdpSocket, feeds: &[Feed], end: Instant) -> io::Result<Traffic> {
    udp.set_read_timeout(Some(Duration::from_millis(2)))?;
    let sender = udp.try_clone()?;
    // The sender inherits it.
    real_time_thread(SCANNER_PRIORITY)?;
    std::thread::scope(|s| {
        let send = s.spawn(move || send_until(&sender, feeds, end));
        let mut t_o = Vec::new();
        let mut buf = [0u8; 1500];
        // Bounded by time: every read times out after 2 ms.
        while Instant::now() < end {
            match udp.recv_from(&mut buf) {
                Ok((n, _)) => {
                    if let Ok(p) = Packet::new_checked(&buf[..n]) {
                        t_o.push((Instant::now(), p.connection_id(), p.encap_sequence()));
                    }
                }
                Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {}
                Err(e) => return Err(e),
            }
        }
        let sent = send
            .join()
            .map_err(|_| io::Error::other("sender panicked"))??;
        Ok(Traffic { t_o, ..sent })
    })
}

/// The sender: each feed's O->T at its own absolute deadlines while fed, until `end`;
/// returns what it did (no T->O).
fn send_until(udp: &UdpSocket, feeds: &[Feed], end: Instant) -> io::Result<Traffic> {
    let to = SocketAddrV4::new(BOARD_IP, IO_PORT);
    let start = Instant::now();
    let mut ticks = vec![0u32; feeds.len()];
    let mut sent = Traffic {
        last_sent: vec![None; feeds.len()],
        max_gap: vec![Duration::ZERO; feeds.len()],
        ..Traffic::default()
    };
    let mut buf = [0u8; 128];
    loop {
        let due = |i: usize| start + feeds[i].rpi * ticks[i];
        let Some(next) = (0..feeds.len()).min_by_key(|&i| due(i)) else {
            return Ok(sent);
        };
        let at = due(next);
        if at >= end {
            return Ok(sent);
        }
        if let Some(wait) = at.checked_duration_since(Instant::now()) {
            std::thread::sleep(wait);
        }
        ticks[next] += 1;
        let f = &feeds[next];
        if !f.fed.load(Ordering::Relaxed) {
            continue;
        }
        let k = ticks[next];
        let (run, data) = if f.owner {
            (Some(true), &[k as u8; 32][..])
        } else {
            (None, &[][..])
        };
        let n = originator::io_datagram(&mut buf, f.o_t_id, k, k as u16, run, data)
            .map_err(|e| io::Error::other(format!("{e:?}")))?;
        match udp.send_to(&buf[..n], to) {
            Ok(_) => {
                let now = Instant::now();
                if let Some(prev) = sent.last_sent[next] {
                    sent.max_gap[next] = sent.max_gap[next].max(now - prev);
                }
                sent.last_sent[next] = Some(now);
            }
            Err(_) => sent.send_errors += 1,
        }
    }
}

/// Milliseconds from `from` to `to` (to 0.1 ms), negative if `to` is earlier.
pub fn ms_between(from: Instant, to: Instant) -> f64 {
    match to.checked_duration_since(from) {
        Some(d) => ms(d),
        None => -ms(from.duration_since(to)),
    }
}
