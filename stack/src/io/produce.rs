//! Class 1 production: sequence numbers per trigger, datagrams built straight into the
//! caller's buffer. When a producer is due, and where its deadline moves (the exact grid
//! `previous + RPI`; a cyclic producer's on the adapter's clock from its second production,
//! `io/timing.rs`), is the connection table's (its `due` and `produce`).

use core::net::SocketAddrV4;

use super::connection::Producer;
use super::table::ConnectionTable;
use crate::device::{Device, Trigger};
use crate::time::Instant;
use crate::wire::io_datagram::{IoDatagramRepr, HEADER_LEN, SEQUENCE_LEN};
use crate::wire::Writer;

/// A T->O datagram due for sending, from [`crate::Adapter::io_due`]: where it goes, its
/// largest length, and the producer that builds it with [`crate::Adapter::write_io`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IoDue {
    /// Destination: UDP port 2222 of the originator, or the multicast group.
    pub to: SocketAddrV4,
    /// Largest length of the datagram (the connection's size); the device may fill less.
    pub max_len: usize,
    /// The DSCP its IPv4 header carries (the connection's, chosen when it opened).
    pub dscp: u8,
    slot: usize,
    t_o_id: u32,
}

/// Length of a datagram carrying `size` bytes of application data.
fn datagram_len(size: u16) -> usize {
    // A u16 and a small constant: no overflow.
    (HEADER_LEN + SEQUENCE_LEN).saturating_add(usize::from(size))
}

/// The most overdue producer at `now`, or `None` if none is due.
pub fn next_due<const C: usize>(table: &ConnectionTable<C>, now: Instant) -> Option<IoDue> {
    let slot = table.due(now)?;
    let conn = table.get(slot)?;
    let p = conn.producer()?;
    Some(IoDue {
        to: p.destination,
        max_len: datagram_len(p.size),
        dscp: p.dscp,
        slot,
        t_o_id: conn.t_o_id,
    })
}

/// Writes the datagram of `due` into `out` (at least `due.max_len` bytes) and moves its
/// producer to its next deadline; returns the datagram's length. With `out` `None` the
/// datagram is skipped (nowhere to send it) and the producer moves on all the same.
/// Returns 0, changing nothing, if `out` is too short or the connection closed since.
pub fn write<D: Device, const C: usize>(
    table: &mut ConnectionTable<C>,
    device: &mut D,
    due: IoDue,
    now: Instant,
    out: Option<&mut [u8]>,
) -> usize {
    produce_slot(table, device, due.slot, Some(due.t_o_id), now, out).map_or(0, |(_, len)| len)
}

/// Produces the connection in `slot` (if its T->O ID is still `t_o_id`, when given) into
/// `out` and lets the table move it to its next deadline: where the datagram goes and its
/// length. `None`, changing nothing, if there is no such producer or `out` is too short for
/// its datagram.
#[inline(always)]
fn produce_slot<D: Device, const C: usize>(
    table: &mut ConnectionTable<C>,
    device: &mut D,
    slot: usize,
    t_o_id: Option<u32>,
    now: Instant,
    out: Option<&mut [u8]>,
) -> Option<(SocketAddrV4, usize)> {
    table.produce(slot, t_o_id, now, |p, t_o_id, triggered| {
        if out.as_ref().is_some_and(|o| o.len() < datagram_len(p.size)) {
            return None;
        }
        // New data: every production of a cyclic producer, a triggered one's when triggered.
        if p.trigger == Trigger::Cyclic || triggered {
            p.sequence = p.sequence.wrapping_add(1);
        }
        p.encap_sequence = p.encap_sequence.wrapping_add(1);
        let len = match out {
            Some(out) => emit(device, p, t_o_id, out),
            None => 0,
        };
        Some((p.destination, len))
    })
}

/// Builds the datagram of producer `p` (already counted) into `out`; returns its length.
#[inline(always)]
fn emit<D: Device>(device: &mut D, p: &Producer, t_o_id: u32, out: &mut [u8]) -> usize {
    let Some((head, rest)) = out.split_first_chunk_mut::<{ HEADER_LEN + SEQUENCE_LEN }>() else {
        return 0;
    };
    let Some(data) = rest.get_mut(..usize::from(p.size)) else {
        return 0;
    };
    // The device's length is honoured (never more than the connection's size); an error
    // sends zeros rather than stale bytes.
    let size = match device.read_assembly(p.instance, data) {
        Ok(n) => n.min(data.len()),
        Err(_) => {
            data.fill(0);
            data.len()
        }
    };
    // `size` is at most the connection's u16 size.
    let Ok(connected) = u16::try_from(SEQUENCE_LEN.saturating_add(size)) else {
        return 0;
    };
    let front = IoDatagramRepr {
        connection_id: t_o_id,
        encap_sequence: p.encap_sequence,
        connected_len: connected,
        sequence: p.sequence,
    };
    if front.emit(&mut Writer::new(head)).is_err() {
        return 0;
    }
    head.len().saturating_add(size)
}
