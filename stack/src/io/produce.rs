//! Class 1 production: exact deadlines (next = previous + RPI), sequence numbers per trigger,
//! datagrams built straight into the caller's buffer.

use core::net::SocketAddrV4;

use super::connection::{Producer, Transport};
use super::table::ConnectionTable;
use crate::device::Device;
use crate::device::Trigger;
use crate::time::{Duration, Instant};
use crate::wire::io_datagram::{IoDatagramRepr, HEADER_LEN, SEQUENCE_LEN};
use crate::wire::Writer;

/// The first deadline on the grid `previous + k * rpi` that is after `now` (k >= 1).
fn advance(previous: Instant, rpi: u32, now: Instant) -> Instant {
    let rpi = u64::from(rpi.max(1));
    let next = previous.add(Duration::from_micros(rpi));
    if next > now {
        return next;
    }
    let missed = now
        .since(previous)
        .as_micros()
        .checked_div(rpi)
        .unwrap_or(0)
        .saturating_add(1);
    previous.add(Duration::from_micros(missed.saturating_mul(rpi)))
}

/// A T->O datagram due for sending, from [`crate::Adapter::io_due`]: where it goes, its
/// largest length, and the producer that builds it with [`crate::Adapter::write_io`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IoDue {
    /// Destination: UDP port 2222 of the originator, or the multicast group.
    pub to: SocketAddrV4,
    /// Largest length of the datagram (the connection's size); the device may fill less.
    pub max_len: usize,
    slot: usize,
    t_o_id: u32,
}

/// Length of a datagram carrying `size` bytes of application data.
fn datagram_len(size: u16) -> usize {
    // A u16 and a small constant: no overflow.
    (HEADER_LEN + SEQUENCE_LEN).saturating_add(usize::from(size))
}

/// The most overdue producer at `now`, or `None` if none is due.
pub fn next_due(table: &ConnectionTable, now: Instant) -> Option<IoDue> {
    let (slot, at) = table.next_producer();
    if now < at {
        return None;
    }
    let conn = table.get(slot)?;
    let p = conn.producer()?;
    Some(IoDue {
        to: p.destination,
        max_len: datagram_len(p.size),
        slot,
        t_o_id: conn.t_o_id,
    })
}

/// Writes the datagram of `due` into `out` (at least `due.max_len` bytes) and moves its
/// producer to its next deadline; returns the datagram's length. With `out` `None` the
/// datagram is skipped (nowhere to send it) and the producer moves on all the same.
/// Returns 0, changing nothing, if `out` is too short or the connection closed since.
pub fn write<D: Device>(
    table: &mut ConnectionTable,
    device: &mut D,
    due: IoDue,
    now: Instant,
    out: Option<&mut [u8]>,
) -> usize {
    produce_slot(table, device, due.slot, Some(due.t_o_id), now, out).map_or(0, |(_, len)| len)
}

/// Writes the most overdue datagram into `out` and returns where it goes and its length;
/// `None` if nothing is due at `now` (or `out` is too short for it).
pub fn produce_due<D: Device>(
    table: &mut ConnectionTable,
    device: &mut D,
    now: Instant,
    out: &mut [u8],
) -> Option<(SocketAddrV4, usize)> {
    let (slot, at) = table.next_producer();
    if now < at {
        return None;
    }
    produce_slot(table, device, slot, None, now, Some(out)).filter(|&(_, len)| len > 0)
}

/// Produces the connection in `slot` (if its T->O ID is still `t_o_id`, when given) into
/// `out` and moves it to its next deadline: where the datagram goes and its length. `None`,
/// changing nothing, if there is no such producer or `out` is too short for its datagram.
#[inline(always)]
fn produce_slot<D: Device>(
    table: &mut ConnectionTable,
    device: &mut D,
    slot: usize,
    t_o_id: Option<u32>,
    now: Instant,
    out: Option<&mut [u8]>,
) -> Option<(SocketAddrV4, usize)> {
    let conn = table
        .get_mut(slot)
        .filter(|c| t_o_id.is_none_or(|id| c.t_o_id == id))?;
    let (rpi, t_o_id) = (conn.t_o_rpi, conn.t_o_id);
    let Transport::Class1 {
        producer: Some(p), ..
    } = &mut conn.transport
    else {
        return None;
    };
    if out.as_ref().is_some_and(|o| o.len() < datagram_len(p.size)) {
        return None;
    }
    let to = p.destination;
    let len = produce(device, p, t_o_id, rpi, now, out);
    let due_at = p.due_at();
    table.set_due(slot, due_at);
    Some((to, len))
}

/// One production of `p` at `now`: counts it, builds its datagram into `out` (if any, of at
/// least its largest length) and moves it to its next deadline; returns the datagram's length.
fn produce<D: Device>(
    device: &mut D,
    p: &mut Producer,
    t_o_id: u32,
    rpi: u32,
    now: Instant,
    out: Option<&mut [u8]>,
) -> usize {
    let triggered = p.triggered;
    if p.trigger == Trigger::Cyclic || triggered {
        p.sequence = p.sequence.wrapping_add(1);
    }
    p.encap_sequence = p.encap_sequence.wrapping_add(1);
    let len = match out {
        Some(out) => emit(device, p, t_o_id, out),
        None => 0,
    };
    if triggered {
        p.triggered = false;
        p.inhibit_until = now.add(p.inhibit);
        p.next = now.add(Duration::from_micros(u64::from(rpi)));
    } else {
        p.next = advance(p.next, rpi, now);
    }
    len
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

/// Marks the producers of assembly `instance` with a change-of-state or application trigger
/// as having new data.
pub fn trigger(table: &mut ConnectionTable, instance: u16) {
    trigger_where(table, |p| p.instance == instance);
}

/// Marks every producer with a change-of-state or application trigger as having new data.
pub fn trigger_all(table: &mut ConnectionTable) {
    trigger_where(table, |_| true);
}

fn trigger_where(table: &mut ConnectionTable, pick: impl Fn(&Producer) -> bool) {
    for slot in table.slots_in_use() {
        if let Some(Transport::Class1 {
            producer: Some(p), ..
        }) = table.get_mut(slot).map(|c| &mut c.transport)
        {
            if p.trigger != Trigger::Cyclic && pick(p) {
                p.triggered = true;
                let due = p.due_at();
                table.set_due(slot, due);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn advance_keeps_the_grid() {
        assert_eq!(advance(Instant(1000), 1000, Instant(1000)), Instant(2000));
        assert_eq!(advance(Instant(1000), 1000, Instant(1999)), Instant(2000));
        assert_eq!(advance(Instant(1000), 1000, Instant(2000)), Instant(3000));
        assert_eq!(advance(Instant(1000), 1000, Instant(4500)), Instant(5000));
    }
}
