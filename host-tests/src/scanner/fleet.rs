//! The scanner against a fleet: one exclusive owner on the generic profile of each of many
//! devices, all at one RPI, O->T from one sender thread and T->O on one socket, and an
//! explicit request to every device once a second from another thread, spread over the
//! second; every T->O arrival recorded per device.

use std::collections::HashMap;
use std::io;
use std::net::{Ipv4Addr, SocketAddrV4, UdpSocket};
use std::thread;
use std::time::{Duration, Instant};

use enip_stack::config::IO_PORT;
use enip_stack::originator;
use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use enip_stack::wire::forward_open::Triad;
use enip_stack::wire::io_datagram::Packet;

use super::exchange::{generic_forward_open, Opened, OWNER_O_T, OWNER_PATH};
use super::session::Session;

/// Identity object, instance 1, attribute 1 (vendor ID): the explicit request.
const VENDOR: [SegmentRepr<'static>; 3] = [
    SegmentRepr::Logical(LogicalType::Class, 1),
    SegmentRepr::Logical(LogicalType::Instance, 1),
    SegmentRepr::Logical(LogicalType::Attribute, 1),
];
/// Receive buffer of the T->O socket: 256 devices' datagrams for a scheduling stall of the
/// scanner's own (the kernel would drop them, and count them against the devices).
const RECEIVE_BUFFER: usize = 16 << 20;

/// One device of the fleet, its session and its owner connection.
#[derive(Debug)]
pub struct Owned {
    /// Its address.
    pub ip: Ipv4Addr,
    /// The session the connection was opened on (and the explicit requests go on).
    pub session: Session,
    /// The connection.
    pub opened: Opened,
}

/// Opens an exclusive owner (generic profile, 150 -> 100, config 151) at `rpi_us` on each
/// of `targets`, timeout multiplier code `multiplier`.
pub fn open_owners(targets: &[Ipv4Addr], rpi_us: u32, multiplier: u8) -> io::Result<Vec<Owned>> {
    let mut owned = Vec::with_capacity(targets.len());
    for (i, ip) in (0u32..).zip(targets) {
        let mut session = Session::connect(*ip, Duration::from_secs(3))
            .map_err(|e| io::Error::other(format!("{ip}: {e}")))?;
        let triad = Triad {
            connection_serial: i as u16,
            vendor_id: 0xF00D,
            originator_serial: std::process::id(),
        };
        let t_o_id = 0x5D00_0000 + i;
        let fo = generic_forward_open(triad, t_o_id, &OWNER_PATH, OWNER_O_T, multiplier, rpi_us);
        let r = session.forward_open(&fo)?.map_err(|e| {
            io::Error::other(format!(
                "{ip}: Forward_Open refused: {:#x} {:04x?}",
                e.general, e.additional
            ))
        })?;
        let opened = Opened {
            o_t_id: r.o_t_connection_id,
            t_o_id: r.t_o_connection_id,
            triad,
            o_t_data: 32,
        };
        owned.push(Owned {
            ip: *ip,
            session,
            opened,
        });
    }
    Ok(owned)
}

/// What a run recorded.
#[derive(Debug, Default)]
pub struct FleetRecord {
    /// Per device (in the order given): (arrival µs since start, sequence) of each T->O.
    pub packets: Vec<Vec<(u64, u32)>>,
    /// O->T datagrams sent.
    pub sent: u64,
    /// Explicit requests answered with status 0.
    pub explicit_ok: u64,
    /// Explicit requests failed, refused or unanswered within the session's timeout.
    pub explicit_failed: u64,
    /// The slowest explicit reply, µs.
    pub explicit_worst_us: u64,
}

/// Runs I/O with every device of `owned` for `duration`: O->T every `rpi` in Run mode, T->O
/// recorded, a Get_Attribute_Single to each device once a second. Binds UDP `IO_PORT`.
/// `started` is called as the run starts, `ended` as it ends (e.g. to sample CPU time).
pub fn run(
    owned: &mut [Owned],
    rpi: Duration,
    duration: Duration,
    started: impl FnOnce(),
    ended: impl FnOnce(),
) -> io::Result<FleetRecord> {
    let socket = UdpSocket::bind(SocketAddrV4::new(Ipv4Addr::UNSPECIFIED, IO_PORT))?;
    // Forcing needs CAP_NET_ADMIN; without it the kernel's maximum applies.
    if rustix::net::sockopt::set_socket_recv_buffer_size_force(&socket, RECEIVE_BUFFER).is_err() {
        rustix::net::sockopt::set_socket_recv_buffer_size(&socket, RECEIVE_BUFFER)?;
    }
    socket.set_read_timeout(Some(Duration::from_millis(5)))?;
    let sender = socket.try_clone()?;
    let index: HashMap<u32, usize> = owned
        .iter()
        .enumerate()
        .map(|(i, o)| (o.opened.t_o_id, i))
        .collect();
    let targets: Vec<(SocketAddrV4, u32)> = owned
        .iter()
        .map(|o| (SocketAddrV4::new(o.ip, IO_PORT), o.opened.o_t_id))
        .collect();
    let mut record = FleetRecord {
        packets: vec![Vec::with_capacity(duration.as_millis() as usize); owned.len()],
        ..FleetRecord::default()
    };
    started();
    let start = Instant::now();
    let end = start + duration;
    let explicit = thread::scope(|s| -> io::Result<(u64, u64, u64)> {
        let sending = s.spawn(|| send(&sender, &targets, start, rpi, duration));
        let asking = s.spawn(|| ask(owned, start, end));
        let mut buf = [0u8; 1500];
        // Bounded by time: every read times out after 5 ms.
        while Instant::now() < end {
            match socket.recv_from(&mut buf) {
                Ok((n, _)) => {
                    let at = start.elapsed().as_micros() as u64;
                    let Ok(p) = Packet::new_checked(&buf[..n]) else {
                        continue;
                    };
                    let device = index.get(&p.connection_id()).copied();
                    if let Some(packets) = device.and_then(|d| record.packets.get_mut(d)) {
                        packets.push((at, p.encap_sequence()));
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
        ended();
        record.sent = sending
            .join()
            .map_err(|_| io::Error::other("sender panicked"))??;
        asking
            .join()
            .map_err(|_| io::Error::other("explicit requester panicked"))
    })?;
    (
        record.explicit_ok,
        record.explicit_failed,
        record.explicit_worst_us,
    ) = explicit;
    Ok(record)
}

/// O->T to every target every `rpi` for `duration` from `start`; returns the datagrams sent.
fn send(
    socket: &UdpSocket,
    targets: &[(SocketAddrV4, u32)],
    start: Instant,
    rpi: Duration,
    duration: Duration,
) -> io::Result<u64> {
    let mut sent = 0u64;
    let mut buf = [0u8; 128];
    let payload = [0x5Au8; 32];
    let ticks = (duration.as_micros() / rpi.as_micros().max(1)) as u32;
    for k in 1..=ticks {
        let at = start + rpi * k;
        if let Some(wait) = at.checked_duration_since(Instant::now()) {
            thread::sleep(wait);
        }
        for (to, o_t_id) in targets {
            let n = originator::io_datagram(&mut buf, *o_t_id, k, k as u16, Some(true), &payload)
                .map_err(|e| io::Error::other(format!("{e:?}")))?;
            socket.send_to(&buf[..n], to)?;
            sent += 1;
        }
    }
    Ok(sent)
}

/// One Get_Attribute_Single to each device every second until `end`, device `i` of `n` at
/// `i / n` s into each second; returns (answered, failed, slowest µs).
fn ask(owned: &mut [Owned], start: Instant, end: Instant) -> (u64, u64, u64) {
    let (mut ok, mut failed, mut worst) = (0, 0, 0);
    let n = owned.len().max(1) as u32;
    let step = Duration::from_secs(1) / n;
    for second in 0u32.. {
        for (i, o) in (0u32..).zip(owned.iter_mut()) {
            let at = start + Duration::from_secs(u64::from(second)) + step * i;
            if at >= end {
                return (ok, failed, worst);
            }
            if let Some(wait) = at.checked_duration_since(Instant::now()) {
                thread::sleep(wait);
            }
            let asked = Instant::now();
            match o.session.request(0x0E, &VENDOR, &[]) {
                Ok(r) if r.general == 0 => ok += 1,
                _ => failed += 1,
            }
            worst = worst.max(asked.elapsed().as_micros() as u64);
        }
    }
    (ok, failed, worst)
}
