//! Opening connections on the generic profile and running Class 1 I/O: O->T at the RPI from
//! a sender thread, T->O recorded with arrival times.

use std::collections::BTreeMap;
use std::io;
use std::net::{Ipv4Addr, SocketAddrV4, UdpSocket};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread;
use std::time::{Duration, Instant};

use enip_stack::config::IO_PORT;
use enip_stack::originator;
use enip_stack::wire::forward_open::{ForwardOpenRepr, NetworkParams, Triad};
use enip_stack::wire::io_datagram::Packet;

use super::session::Session;
use super::stats::{connection_stats, Summary};
use crate::stop_file::StopFile;

/// Data bytes of the generic profile's input and output assemblies.
const DATA: u16 = 32;
/// The generic profile's exclusive owner: configuration 151, outputs 150, inputs 100.
pub const OWNER_PATH: [u8; 8] = [0x20, 0x04, 0x24, 151, 0x2C, 150, 0x2C, 100];
/// Its input-only connection: heartbeat point 152, inputs 100.
pub const INPUT_ONLY_PATH: [u8; 6] = [0x20, 0x04, 0x2C, 152, 0x2C, 100];
/// O->T size of the owner: sequence count, run/idle header, the outputs.
pub const OWNER_O_T: u16 = 2 + 4 + DATA;
/// O->T size of a heartbeat: the sequence count alone.
pub const HEARTBEAT_O_T: u16 = 2;

/// A point-to-point Class 1 Forward_Open on the generic profile along `path`: O->T of
/// `o_t_size` bytes, T->O the sequence count and the 32 bytes of inputs, both at `rpi_us`;
/// the T->O connection ID `t_o_id` proposed, timeout multiplier code `multiplier`.
pub fn generic_forward_open(
    triad: Triad,
    t_o_id: u32,
    path: &[u8],
    o_t_size: u16,
    multiplier: u8,
    rpi_us: u32,
) -> ForwardOpenRepr<'_> {
    ForwardOpenRepr {
        large: false,
        priority_tick: 0x0A,
        timeout_ticks: 0x0E,
        o_t_connection_id: 0,
        t_o_connection_id: t_o_id,
        triad,
        timeout_multiplier: multiplier,
        o_t_rpi: rpi_us,
        o_t_params: NetworkParams::from_u16(0x4800 | o_t_size),
        t_o_rpi: rpi_us,
        t_o_params: NetworkParams::from_u16(0x4800 | (2 + DATA)),
        transport: 0x01,
        path,
    }
}

/// An open connection, as the scanner needs it for I/O.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Opened {
    /// O->T connection ID to send with.
    pub o_t_id: u32,
    /// T->O connection ID to expect.
    pub t_o_id: u32,
    /// Its triad, for Forward_Close.
    pub triad: Triad,
    /// O->T application data bytes (0 for a heartbeat).
    pub o_t_data: u16,
}

/// Opens `n` connections at `rpi_us` on the generic profile: an exclusive owner (150 -> 100,
/// config 151) and `n - 1` input-only (heartbeat 152 -> 100), point-to-point, timeout
/// multiplier code `multiplier` (0 = x4).
pub fn open_generic(
    session: &mut Session,
    n: usize,
    rpi_us: u32,
    multiplier: u8,
) -> io::Result<Vec<Opened>> {
    open_generic_triggered(session, n, rpi_us, multiplier, 0x01)
}

/// [`open_generic`] with the transport class and trigger byte `transport` (0x01 cyclic,
/// 0x11 change of state, 0x21 application triggered; class 1, no inhibit time).
pub fn open_generic_triggered(
    session: &mut Session,
    n: usize,
    rpi_us: u32,
    multiplier: u8,
    transport: u8,
) -> io::Result<Vec<Opened>> {
    let mut opened = Vec::new();
    for i in 0..n {
        let owner = i == 0;
        let (path, o_t_size, o_t_data): (&[u8], _, _) = if owner {
            (&OWNER_PATH, OWNER_O_T, DATA)
        } else {
            (&INPUT_ONLY_PATH, HEARTBEAT_O_T, 0)
        };
        let triad = Triad {
            connection_serial: 0x100 + i as u16,
            vendor_id: 0xF00D,
            originator_serial: std::process::id(),
        };
        let t_o_id = 0x5C00_0000 + i as u32;
        let mut fo = generic_forward_open(triad, t_o_id, path, o_t_size, multiplier, rpi_us);
        fo.transport = transport;
        match session.forward_open(&fo)? {
            Ok(r) => opened.push(Opened {
                o_t_id: r.o_t_connection_id,
                t_o_id: r.t_o_connection_id,
                triad,
                o_t_data,
            }),
            Err(e) => {
                return Err(io::Error::other(format!(
                    "Forward_Open {i} refused: status {:#x} {:04x?}",
                    e.general, e.additional
                )))
            }
        }
    }
    Ok(opened)
}

/// Every T->O packet received: per T->O connection ID, (arrival µs since start, 32-bit
/// sequence, first data bytes).
#[derive(Debug, Default, Clone)]
pub struct Record {
    /// Packets by connection ID.
    pub packets: BTreeMap<u32, Vec<(u64, u32, [u8; 4])>>,
    /// O->T datagrams sent.
    pub sent: u64,
    /// Microseconds from the start to the end of the run (the whole duration unless it was
    /// stopped early).
    pub ended_us: u64,
}

impl Record {
    /// Interval statistics; a connection counts as timed out if its last packet is more than
    /// `quiet_us` before `end_us`.
    pub fn summary(&self, end_us: u64, quiet_us: u64) -> Summary {
        let connections: Vec<_> = self
            .packets
            .iter()
            .map(|(id, p)| {
                connection_stats(*id, &p.iter().map(|(t, s, _)| (*t, *s)).collect::<Vec<_>>())
            })
            .collect();
        let timeouts = self
            .packets
            .values()
            .filter(|p| {
                p.last()
                    .is_none_or(|(t, _, _)| end_us.saturating_sub(*t) > quiet_us)
            })
            .count();
        Summary {
            connections,
            timeouts,
        }
    }
}

/// Runs I/O with `opened` on `target` for `duration`: O->T every `rpi` carrying `data(k)`
/// (k = tick number) in Run mode, T->O recorded. Binds UDP `IO_PORT` locally.
pub fn exchange(
    target: Ipv4Addr,
    opened: &[Opened],
    rpi: Duration,
    duration: Duration,
    data: impl Fn(u32) -> [u8; 32] + Send + 'static,
) -> io::Result<Record> {
    exchange_until(target, opened, rpi, duration, data, StopFile::new(None))
}

/// [`exchange`] that also ends once `stop` is asked.
pub fn exchange_until(
    target: Ipv4Addr,
    opened: &[Opened],
    rpi: Duration,
    duration: Duration,
    data: impl Fn(u32) -> [u8; 32] + Send + 'static,
    mut stop: StopFile,
) -> io::Result<Record> {
    let socket = UdpSocket::bind(SocketAddrV4::new(Ipv4Addr::UNSPECIFIED, IO_PORT))?;
    socket.set_read_timeout(Some(Duration::from_millis(5)))?;
    let sender = socket.try_clone()?;
    let to = SocketAddrV4::new(target, IO_PORT);
    let start = Instant::now();
    let end = start + duration;
    let conns = opened.to_vec();
    // Set when the receiving loop ends early: the sender ends at its next tick.
    let halted = Arc::new(AtomicBool::new(false));
    let halt = Arc::clone(&halted);
    let send_thread = thread::spawn(move || -> io::Result<u64> {
        let mut sent = 0u64;
        let mut buf = [0u8; 128];
        let ticks = (duration.as_micros() / rpi.as_micros().max(1)) as u32;
        for k in 1..=ticks {
            let at = start + rpi * k;
            if let Some(wait) = at.checked_duration_since(Instant::now()) {
                thread::sleep(wait);
            }
            if halt.load(Ordering::Relaxed) {
                break;
            }
            let payload = data(k);
            for c in &conns {
                let run = if c.o_t_data > 0 { Some(true) } else { None };
                let body = if c.o_t_data > 0 {
                    &payload[..]
                } else {
                    &[][..]
                };
                let n = originator::io_datagram(&mut buf, c.o_t_id, k, k as u16, run, body)
                    .map_err(|e| io::Error::other(format!("{e:?}")))?;
                sender.send_to(&buf[..n], to)?;
                sent += 1;
            }
        }
        Ok(sent)
    });
    let mut record = Record::default();
    let mut buf = [0u8; 1500];
    // Bounded by time: every read times out after 5 ms.
    while Instant::now() < end && !stop.asked() {
        match socket.recv_from(&mut buf) {
            Ok((n, _)) => {
                let at = start.elapsed().as_micros() as u64;
                if let Ok(p) = Packet::new_checked(&buf[..n]) {
                    let d = p.connected_data();
                    let head = [
                        d.get(2).copied().unwrap_or(0),
                        d.get(3).copied().unwrap_or(0),
                        d.get(4).copied().unwrap_or(0),
                        d.get(5).copied().unwrap_or(0),
                    ];
                    record.packets.entry(p.connection_id()).or_default().push((
                        at,
                        p.encap_sequence(),
                        head,
                    ));
                }
            }
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut
                ) => {}
            Err(e) => return Err(e),
        }
    }
    record.ended_us = start.elapsed().as_micros() as u64;
    halted.store(true, Ordering::Relaxed);
    record.sent = send_thread
        .join()
        .map_err(|_| io::Error::other("sender panicked"))??;
    Ok(record)
}
