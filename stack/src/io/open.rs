//! Forward_Open validation: every check answered with its own extended status, then the
//! new connection entry.

use core::net::{Ipv4Addr, SocketAddrV4};

use super::connection::{Connection, Consumer, Producer, Transport};
use super::table::ConnectionTable;
use crate::cip::class_id;
use crate::cip::connection_status as ext;
use crate::cip::status::{CipError, CipResult};
use crate::config::{IO_PORT, MAX_EXPLICIT_CONNECTED, MAX_RPI_US, MIN_RPI_US};
use crate::device::admission::{rpi_check, rpi_mismatch};
use crate::device::electronic_key::{self, KeyMismatch};
use crate::device::{
    AssemblyInfo, AssemblyRole, ConnectionEvent, ConnectionPoints, Device, Direction, Kind,
    OpenRequest, Trigger,
};
use crate::time::{Duration, Instant};
use crate::wire::cpf::SockAddrRepr;
use crate::wire::epath::{
    ElectronicKey, LogicalType, SegmentRepr, Segments, NETWORK_PRODUCTION_INHIBIT_MS,
};
use crate::wire::forward_open::{ConnectionType, ForwardOpenRepr, NetworkParams};
use crate::wire::io_datagram::{RUN_IDLE_LEN, SEQUENCE_LEN};

/// Where a Forward_Open came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Origin {
    /// The originator's IP address (the TCP peer).
    pub ip: Ipv4Addr,
    /// Socket index of its encapsulation session.
    pub socket: u8,
    /// T->O socket address item it sent, if any (its UDP port for point-to-point data).
    pub t_o_sockaddr: Option<SockAddrRepr>,
}

/// The network facts a Forward_Open needs: our address, multicast group and TTL.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NetFacts {
    /// Our IP address.
    pub ip: Ipv4Addr,
    /// Our network mask.
    pub netmask: Ipv4Addr,
    /// The T->O multicast group (TCP/IP attribute 9).
    pub multicast: Ipv4Addr,
    /// Multicast TTL (TCP/IP attribute 8).
    pub ttl: u8,
    /// The DSCP of the T->O packets: the QoS object's for the T->O priority.
    pub t_o_dscp: u8,
}

/// The decoded connection path.
#[derive(Debug, Default)]
struct ConnPath<'a> {
    key: Option<ElectronicKey>,
    class: Option<u32>,
    points: heapless::Vec<u32, 3>,
    inhibit_ms: Option<u8>,
    config_data: Option<&'a [u8]>,
}

fn bad_segment() -> CipError {
    CipError::connection(ext::BAD_SEGMENT)
}

impl<'a> ConnPath<'a> {
    /// The production inhibit time the path asks for (zero if none).
    fn inhibit(&self) -> Duration {
        Duration::from_millis(u64::from(self.inhibit_ms.unwrap_or(0)))
    }

    /// Accepts: [port 1 link 0] [key] class [instance/points...] [attribute] [inhibit] [data].
    fn parse(raw: &'a [u8]) -> CipResult<ConnPath<'a>> {
        let mut p = ConnPath::default();
        for (i, seg) in Segments::new(raw).enumerate() {
            match seg.map_err(|_| bad_segment())? {
                SegmentRepr::Port { port: 1, link: [0] } if i == 0 => {}
                SegmentRepr::ElectronicKey(k) if p.key.is_none() && p.class.is_none() => {
                    p.key = Some(k)
                }
                SegmentRepr::Logical(LogicalType::Class, c) if p.class.is_none() => {
                    p.class = Some(c)
                }
                SegmentRepr::Logical(LogicalType::Instance | LogicalType::ConnectionPoint, v)
                    if p.class.is_some() && p.config_data.is_none() =>
                {
                    p.points.push(v).map_err(|_| bad_segment())?;
                }
                SegmentRepr::Logical(LogicalType::Attribute, _) if !p.points.is_empty() => {}
                SegmentRepr::Network {
                    kind: NETWORK_PRODUCTION_INHIBIT_MS,
                    data: [ms],
                } => p.inhibit_ms = Some(*ms),
                SegmentRepr::Data(d) if p.config_data.is_none() => p.config_data = Some(d),
                _ => return Err(bad_segment()),
            }
        }
        if p.class.is_none() {
            return Err(bad_segment());
        }
        Ok(p)
    }
}

/// 0x0112 with the acceptable values if an RPI in use lies outside the stack's range.
fn check_rpis(fo: &ForwardOpenRepr<'_>) -> CipResult {
    let used = |p: &NetworkParams| p.connection_type != ConnectionType::Null;
    rpi_check(
        [
            (fo.o_t_rpi, used(&fo.o_t_params)),
            (fo.t_o_rpi, used(&fo.t_o_params)),
        ],
        MIN_RPI_US,
        MAX_RPI_US,
    )
}

/// The data bytes a connection to `assembly` carries, given its network parameters and
/// the `overhead` before the data (sequence count, run/idle header); `None` if refused.
/// Fixed: what the device accepts ([`Device::accepts_connection_size`], by default exactly
/// the assembly's size), never more than the assembly; variable: the assembly's size, which
/// the requested size must hold.
fn data_size<D: Device>(
    device: &D,
    assembly: &AssemblyInfo,
    params: &NetworkParams,
    overhead: usize,
) -> Option<u16> {
    let full = usize::from(assembly.size);
    if params.variable {
        return size_ok(params, overhead.saturating_add(full)).then_some(assembly.size);
    }
    let data = usize::from(params.size).checked_sub(overhead)?;
    u16::try_from(data)
        .ok()
        .filter(|_| data <= full && device.accepts_connection_size(assembly, data))
}

fn size_error(code: u16, expected: usize) -> CipError {
    CipError::connection(code).with_additional(code, expected as u16)
}

/// A size field matches `expected` exactly, or bounds it when the size is variable.
fn size_ok(p: &NetworkParams, expected: usize) -> bool {
    let size = usize::from(p.size);
    size == expected || (p.variable && size >= expected)
}

/// The whole Forward_Open check. On success the connection is in the table and its slot
/// is returned.
pub fn forward_open<D: Device, const C: usize>(
    table: &mut ConnectionTable<C>,
    device: &mut D,
    fo: &ForwardOpenRepr<'_>,
    origin: &Origin,
    net: &NetFacts,
    now: Instant,
) -> CipResult<usize> {
    if fo.timeout_multiplier > 7 {
        return Err(CipError::connection(ext::BAD_TIMEOUT_MULTIPLIER));
    }
    let (ot, to) = (fo.o_t_params.connection_type, fo.t_o_params.connection_type);
    if ot == ConnectionType::Null && to == ConnectionType::Null {
        return Err(CipError::connection(ext::NULL_FORWARD_OPEN));
    }
    // Redundant owners share outputs by a protocol this stack does not have: opening one as
    // an exclusive owner would hide that from the originator.
    if fo.o_t_params.redundant_owner {
        return Err(CipError::connection(ext::REDUNDANT_OWNER));
    }
    let trigger = match (fo.transport_class(), fo.trigger()) {
        (1, 0) => Trigger::Cyclic,
        (1, 1) => Trigger::ChangeOfState,
        (1, 2) | (3, 0 | 2) => Trigger::Application,
        _ => return Err(CipError::connection(ext::TRANSPORT_NOT_SUPPORTED)),
    };
    if table.find_triad(&fo.triad).is_some() {
        return Err(CipError::connection(ext::DUPLICATE));
    }
    let mut path = ConnPath::parse(fo.path)?;
    if let Some(key) = &path.key {
        electronic_key::check(key, device.identity()).map_err(KeyMismatch::connection_failure)?;
    }
    check_rpis(fo)?;
    if ot != ConnectionType::PointToPoint
        || !(to == ConnectionType::PointToPoint
            || (to == ConnectionType::Multicast && fo.transport_class() == 1))
    {
        return Err(CipError::connection(ext::BAD_NETWORK_PARAMS));
    }
    // The multiplier code is at most 7 (checked above): x4 to x512.
    let multiplier = 4u64 << fo.timeout_multiplier;
    let timeout = Duration::from_micros(u64::from(fo.o_t_rpi).saturating_mul(multiplier));
    let base = Connection {
        kind: Kind::Explicit,
        triad: fo.triad,
        originator: origin.ip,
        points: ConnectionPoints::default(),
        socket: origin.socket,
        o_t_id: 0,
        t_o_id: fo.t_o_connection_id,
        o_t_rpi: fo.o_t_rpi,
        t_o_rpi: fo.t_o_rpi,
        timeout,
        transport: Transport::Class3 {
            last_sequence: None,
        },
    };
    let conn = if fo.transport_class() == 3 {
        explicit(fo, &path, base)?
    } else {
        class1(table, device, fo, &mut path, origin, net, trigger, base)?
    };
    device.admit(&OpenRequest {
        kind: conn.kind,
        transport_class: fo.transport_class(),
        trigger,
        // The time asked for: a connection joining a multicast production has no producer
        // of its own, but asked for (and got) that production's.
        inhibit: match conn.transport {
            Transport::Class1 { .. } => path.inhibit(),
            Transport::Class3 { .. } => Duration::from_micros(0),
        },
        points: conn.points,
        o_t: Direction {
            rpi_us: fo.o_t_rpi,
            params: fo.o_t_params,
        },
        t_o: Direction {
            rpi_us: fo.t_o_rpi,
            params: fo.t_o_params,
        },
        timeout_multiplier: fo.timeout_multiplier,
        originator: origin.ip,
        triad: fo.triad,
        key: path.key,
        config_data: path.config_data,
    })?;
    // What the table holds is judged after the request itself: outputs owned, free slots.
    let owned = conn.consumer().map(|c| c.instance);
    if conn.kind == Kind::ExclusiveOwner
        && owned.is_some_and(|i| table.owned_outputs().contains(&i))
    {
        return Err(CipError::connection(ext::OWNERSHIP_CONFLICT));
    }
    let slot = table
        .free_slot()
        .ok_or(CipError::connection(ext::OUT_OF_CONNECTIONS))?;
    let mut conn = conn;
    conn.o_t_id = table.new_id(slot);
    if conn.produces_multicast() {
        conn.t_o_id = table.new_id(slot);
    }
    let gained = conn.kind == Kind::ExclusiveOwner && table.owned_outputs().is_empty();
    if let (Some(data), Some(config)) = (path.config_data, conn.points.config) {
        // The configuration belongs to the open connections that name it: a new connection
        // may repeat it, not change it under them (0x0106, as OpENer does).
        if table.iter().any(|(_, c)| c.points.config == Some(config)) {
            if !configured_with(device, config, data) {
                return Err(CipError::connection(ext::OWNERSHIP_CONFLICT));
            }
        } else {
            device
                .write_assembly(config, data)
                .map_err(configuration_refused)?;
        }
    }
    let info = conn.info(slot);
    table
        .open(conn, now)
        .ok_or(CipError::connection(ext::OUT_OF_CONNECTIONS))?;
    info!(
        "connection {} opened: {:?} from {}, points {:?}/{:?}/{:?}, RPI O->T {} us T->O {} us",
        slot,
        info.kind,
        info.originator,
        info.points.config,
        info.points.consumed,
        info.points.produced,
        info.o_t_rpi_us,
        info.t_o_rpi_us
    );
    device.connection_event(ConnectionEvent::Opened(info));
    if gained {
        device.connection_event(ConnectionEvent::OwnershipGained);
    }
    Ok(slot)
}

/// The longest configuration [`configured_with`] compares; a longer one held by another
/// connection cannot be shown to match.
const MAX_COMPARED_CONFIG: usize = 512;

/// True if the configuration assembly `config` holds `data` now.
fn configured_with(device: &mut impl Device, config: u16, data: &[u8]) -> bool {
    let mut current = [0u8; MAX_COMPARED_CONFIG];
    match device.read_assembly(config, &mut current) {
        Ok(len) => current.get(..len) == Some(data),
        Err(_) => false,
    }
}

/// A configuration the device refused to take at Forward_Open: its connection failure as
/// given, anything else 0x01/0x0110 (target not configured).
fn configuration_refused(e: CipError) -> CipError {
    if e.general == crate::cip::General::ConnectionFailure {
        e
    } else {
        CipError::connection(ext::NOT_CONFIGURED)
    }
}

/// Class 3: a path to the Message Router, sizes within the explicit message buffer.
fn explicit(
    fo: &ForwardOpenRepr<'_>,
    path: &ConnPath<'_>,
    base: Connection,
) -> CipResult<Connection> {
    let router = path.class == Some(u32::from(class_id::MESSAGE_ROUTER))
        && matches!(path.points.as_slice(), [] | [1])
        && path.config_data.is_none();
    if !router {
        return Err(bad_segment());
    }
    let max = MAX_EXPLICIT_CONNECTED + SEQUENCE_LEN;
    if usize::from(fo.o_t_params.size) > max || usize::from(fo.t_o_params.size) > max {
        return Err(size_error(ext::BAD_SIZE, max));
    }
    Ok(base)
}

fn assembly(device: &impl Device, instance: u32) -> Option<AssemblyInfo> {
    crate::device::assembly(device, instance)
}

/// Class 1: application paths, sizes, ownership and multicast rules.
#[allow(clippy::too_many_arguments)]
fn class1<D: Device, const C: usize>(
    table: &ConnectionTable<C>,
    device: &D,
    fo: &ForwardOpenRepr<'_>,
    path: &mut ConnPath<'_>,
    origin: &Origin,
    net: &NetFacts,
    trigger: Trigger,
    base: Connection,
) -> CipResult<Connection> {
    if path.class != Some(u32::from(class_id::ASSEMBLY)) {
        return Err(bad_segment());
    }
    let (config, consume, produce) = match path.points.as_slice() {
        [c, o, t] => (Some(*c), *o, *t),
        [o, t] => (None, *o, *t),
        _ => return Err(bad_segment()),
    };
    if let Some(c) = config {
        let info = assembly(device, c).filter(|a| a.role == AssemblyRole::Config);
        match (info, path.config_data) {
            (None, _) => return Err(CipError::connection(ext::BAD_CONFIG_PATH)),
            // The data segment counts 16-bit words: an odd size comes with a pad byte,
            // which the device does not see.
            (Some(a), Some(d)) if a.size % 2 == 1 && d.len() == usize::from(a.size) + 1 => {
                path.config_data = d.get(..usize::from(a.size));
            }
            // So does 0x0126's size (Vol 1 table 3-5.33: "the error code plus the max size
            // in words").
            (Some(a), Some(d)) if d.len() != usize::from(a.size) => {
                let words = usize::from(a.size).div_ceil(2);
                return Err(size_error(ext::BAD_CONFIG_SIZE, words));
            }
            _ => {}
        }
    } else if path.config_data.is_some() {
        return Err(CipError::connection(ext::BAD_CONFIG_PATH));
    }
    let consumer_info =
        assembly(device, consume).ok_or(CipError::connection(ext::BAD_CONSUMING_PATH))?;
    let kind = match consumer_info.role {
        AssemblyRole::Output => Kind::ExclusiveOwner,
        AssemblyRole::InputOnlyHeartbeat => Kind::InputOnly,
        AssemblyRole::ListenOnlyHeartbeat => Kind::ListenOnly,
        _ => return Err(CipError::connection(ext::BAD_CONSUMING_PATH)),
    };
    let producer_info = assembly(device, produce)
        .filter(|a| a.role == AssemblyRole::Input)
        .ok_or(CipError::connection(ext::BAD_PRODUCING_PATH))?;

    let o_t_size = usize::from(fo.o_t_params.size);
    let (run_idle, consumed) = if consumer_info.size == 0 {
        // Heartbeat: sequence count alone, or with a run/idle header (a Class 1 datagram
        // always carries the count: 0 is no size, as OpENer says too).
        match o_t_size {
            SEQUENCE_LEN => (false, 0),
            6 => (true, 0),
            _ => return Err(size_error(ext::BAD_O_T_SIZE, SEQUENCE_LEN)),
        }
    } else {
        let header = if consumer_info.run_idle_header {
            RUN_IDLE_LEN
        } else {
            0
        };
        let data = data_size(
            device,
            &consumer_info,
            &fo.o_t_params,
            SEQUENCE_LEN.saturating_add(header),
        )
        .ok_or_else(|| {
            let expected = SEQUENCE_LEN
                .saturating_add(header)
                .saturating_add(usize::from(consumer_info.size));
            size_error(ext::BAD_O_T_SIZE, expected)
        })?;
        (consumer_info.run_idle_header, data)
    };
    let produced =
        data_size(device, &producer_info, &fo.t_o_params, SEQUENCE_LEN).ok_or_else(|| {
            size_error(
                ext::BAD_T_O_SIZE,
                SEQUENCE_LEN + usize::from(producer_info.size),
            )
        })?;

    let multicast = fo.t_o_params.connection_type == ConnectionType::Multicast;
    let mask = u32::from(net.netmask);
    if multicast && net.ttl <= 1 && u32::from(origin.ip) & mask != u32::from(net.ip) & mask {
        return Err(CipError::connection(ext::MULTICAST_OFF_SUBNET));
    }
    let inhibit = path.inhibit();
    if trigger != Trigger::Cyclic && inhibit.as_micros() > u64::from(fo.t_o_rpi) {
        return Err(CipError::connection(ext::RPI_BELOW_INHIBIT));
    }

    let points = ConnectionPoints {
        config: config.and_then(|c| u16::try_from(c).ok()),
        consumed: Some(consumer_info.instance),
        produced: Some(producer_info.instance),
    };
    let consumer = Consumer {
        instance: consumer_info.instance,
        size: consumed,
        run_idle,
        last_sequence: None,
        last_encap_sequence: None,
        run: false,
    };
    if kind == Kind::ListenOnly && !multicast {
        return Err(CipError::connection(ext::BAD_NETWORK_PARAMS));
    }
    if multicast {
        // The input already goes to the group: join that production, on its terms.
        let group = SocketAddrV4::new(net.multicast, IO_PORT);
        let shared = table.iter().map(|(_, c)| c).find(|c| {
            c.producer()
                .is_some_and(|p| p.instance == producer_info.instance && p.destination == group)
        });
        if let Some((existing, p)) = shared.and_then(|c| Some((c, c.producer()?))) {
            check_join(fo, existing.t_o_rpi, p, trigger, inhibit, produced)?;
            return Ok(Connection {
                kind,
                points,
                t_o_id: existing.t_o_id,
                t_o_rpi: existing.t_o_rpi,
                transport: Transport::Class1 {
                    consumer,
                    producer: None,
                },
                ..base
            });
        }
    }
    if kind == Kind::ListenOnly {
        return Err(CipError::connection(ext::NO_OWNER_FOR_LISTEN_ONLY));
    }
    let destination = if multicast {
        SocketAddrV4::new(net.multicast, IO_PORT)
    } else {
        let port = origin.t_o_sockaddr.map_or(IO_PORT, |s| s.port);
        SocketAddrV4::new(origin.ip, port)
    };
    let producer = Producer {
        instance: producer_info.instance,
        size: produced,
        destination,
        inhibit,
        trigger,
        encap_sequence: 0,
        sequence: 0,
        dscp: net.t_o_dscp,
        priority: fo.t_o_params.priority,
        variable: fo.t_o_params.variable,
    };
    Ok(Connection {
        kind,
        points,
        transport: Transport::Class1 {
            consumer,
            producer: Some(producer),
        },
        ..base
    })
}

/// A multicast production `p` (at `rpi`) can take one more connection only on the same T->O
/// terms (CIP Vol 1 table 3-5.33): its RPI (0x0112 naming the one required), fixed or
/// variable size, priority, trigger, inhibit time (of a triggered one) and size.
fn check_join(
    fo: &ForwardOpenRepr<'_>,
    rpi: u32,
    p: &Producer,
    trigger: Trigger,
    inhibit: Duration,
    size: u16,
) -> CipResult {
    let mismatch = if fo.t_o_rpi != rpi {
        return Err(rpi_mismatch(fo.o_t_rpi, rpi));
    } else if fo.t_o_params.variable != p.variable {
        ext::MISMATCHED_FIXED_VARIABLE
    } else if fo.t_o_params.priority != p.priority {
        ext::MISMATCHED_PRIORITY
    } else if trigger != p.trigger {
        ext::MISMATCHED_TRIGGER
    } else if trigger != Trigger::Cyclic && inhibit != p.inhibit {
        ext::MISMATCHED_INHIBIT
    } else if size != p.size {
        return Err(size_error(
            ext::BAD_T_O_SIZE,
            SEQUENCE_LEN.saturating_add(usize::from(p.size)),
        ));
    } else {
        return Ok(());
    };
    Err(CipError::connection(mismatch))
}
