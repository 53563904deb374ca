//! Class 1 production: exact deadlines (next = previous + RPI), sequence numbers per trigger,
//! datagrams built straight into the caller's buffer.

use core::net::SocketAddrV4;

use super::connection::{Producer, Transport, Trigger};
use super::table::ConnectionTable;
use crate::device::Device;
use crate::time::{Duration, Instant};
use crate::wire::bytes::put_u16;
use crate::wire::io_datagram::{emit_header, HEADER_LEN, SEQUENCE_LEN};

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

/// A T->O datagram due for sending, from [`next_due`]: where it goes, its largest length,
/// and the producer that builds it with [`write()`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IoDue {
    /// Destination: UDP port 2222 of the originator, or the multicast group.
    pub to: SocketAddrV4,
    /// Largest length of the datagram (the connection's size); the device may fill less.
    pub max_len: usize,
    slot: usize,
    t_o_id: u32,
    /// When the next of the other producers is due.
    others: Instant,
    /// The table's production bound when this was picked.
    bound: Instant,
}

/// The most overdue producer at `now`, or `None` if none is due (the table then remembers
/// when one will be).
pub fn next_due(table: &mut ConnectionTable, now: Instant) -> Option<IoDue> {
    if now < table.production_bound {
        return None;
    }
    // The most overdue producer, and when the next of the others is due.
    let (slot, first, others) = table.earliest_due();
    if first > now {
        table.production_bound = first;
        return None;
    }
    let conn = table.get(slot)?;
    let p = conn.producer()?;
    Some(IoDue {
        to: p.destination,
        max_len: (HEADER_LEN + SEQUENCE_LEN).saturating_add(usize::from(p.size)),
        slot,
        t_o_id: conn.t_o_id,
        others,
        bound: table.production_bound,
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
    if out.as_ref().is_some_and(|o| o.len() < due.max_len) {
        return 0;
    }
    let bound = table.production_bound;
    let Some(conn) = table.get_mut(due.slot).filter(|c| c.t_o_id == due.t_o_id) else {
        return 0;
    };
    let rpi = conn.t_o_rpi;
    let Transport::Class1 {
        producer: Some(p), ..
    } = &mut conn.transport
    else {
        return 0;
    };
    let triggered = p.triggered;
    if p.trigger == Trigger::Cyclic || triggered {
        p.sequence = p.sequence.wrapping_add(1);
    }
    p.encap_sequence = p.encap_sequence.wrapping_add(1);
    let len = match out {
        Some(out) => emit(device, p, due.t_o_id, out),
        None => 0,
    };
    if triggered {
        p.triggered = false;
        p.inhibit_until = now.add(p.inhibit);
        p.next = now.add(Duration::from_micros(u64::from(rpi)));
    } else {
        p.next = advance(p.next, rpi, now);
    }
    let due_at = p.due_at();
    let exact = due.others.min(due_at);
    // A connection opened or a trigger since `due` was picked lowered the bound: keep it.
    table.production_bound = if bound == due.bound {
        exact
    } else {
        bound.min(exact)
    };
    table.set_due(due.slot, due_at);
    len
}

/// Builds the datagram of producer `p` (already counted) into `out`; returns its length.
fn emit<D: Device>(device: &mut D, p: &Producer, t_o_id: u32, out: &mut [u8]) -> usize {
    let data_at = HEADER_LEN + SEQUENCE_LEN;
    let Some(data) = out.get_mut(data_at..data_at.saturating_add(usize::from(p.size))) else {
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
    // `size` is at most the connection's u16 size: no overflow in these sums.
    let connected = SEQUENCE_LEN.saturating_add(size);
    if emit_header(out, t_o_id, p.encap_sequence, connected).is_err() {
        return 0;
    }
    put_u16(out, HEADER_LEN, p.sequence);
    data_at.saturating_add(size)
}

/// Writes the most overdue datagram into `out` and returns where it goes and its length;
/// `None` if nothing is due at `now` (or `out` is too short for it).
pub fn produce_due<D: Device>(
    table: &mut ConnectionTable,
    device: &mut D,
    now: Instant,
    out: &mut [u8],
) -> Option<(SocketAddrV4, usize)> {
    let due = next_due(table, now)?;
    let len = write(table, device, due, now, Some(out));
    (len > 0).then_some((due.to, len))
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
