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

/// Writes the most overdue datagram into `out` and returns where it goes and its length;
/// `None` if nothing is due at `now`.
pub fn produce_due<D: Device>(
    table: &mut ConnectionTable,
    device: &mut D,
    now: Instant,
    out: &mut [u8],
) -> Option<(SocketAddrV4, usize)> {
    if now < table.production_bound {
        return None;
    }
    // The most overdue producer, and when the next of the others is due.
    let mut first: Option<(usize, Instant)> = None;
    let mut others = Instant(u64::MAX);
    for (i, at) in table
        .iter()
        .filter_map(|(i, c)| c.producer().map(|p| (i, p.due_at())))
    {
        match first {
            Some((_, best)) if best <= at => others = others.min(at),
            _ => {
                if let Some((_, best)) = first {
                    others = others.min(best);
                }
                first = Some((i, at));
            }
        }
    }
    let Some((slot, _)) = first.filter(|&(_, at)| at <= now) else {
        table.production_bound = first.map_or(Instant(u64::MAX), |(_, at)| at);
        return None;
    };
    let conn = table.get_mut(slot)?;
    let (t_o_id, rpi) = (conn.t_o_id, conn.t_o_rpi);
    let Transport::Class1 {
        producer: Some(p), ..
    } = &mut conn.transport
    else {
        return None;
    };
    let triggered = p.triggered;
    if p.trigger == Trigger::Cyclic || triggered {
        p.sequence = p.sequence.wrapping_add(1);
    }
    p.encap_sequence = p.encap_sequence.wrapping_add(1);
    let data_at = HEADER_LEN + SEQUENCE_LEN;
    let data = out.get_mut(data_at..data_at + usize::from(p.size))?;
    // The device's length is honoured (never more than the connection's size); an error
    // sends zeros rather than stale bytes.
    let size = match device.read_assembly(p.instance, data) {
        Ok(n) => n.min(data.len()),
        Err(_) => {
            data.fill(0);
            data.len()
        }
    };
    emit_header(
        out,
        t_o_id,
        p.encap_sequence,
        SEQUENCE_LEN.saturating_add(size),
    )
    .ok()?;
    put_u16(out, HEADER_LEN, p.sequence);
    if triggered {
        p.triggered = false;
        p.inhibit_until = now.add(p.inhibit);
        p.next = now.add(Duration::from_micros(u64::from(rpi)));
    } else {
        p.next = advance(p.next, rpi, now);
    }
    let (to, due) = (p.destination, p.due_at());
    table.production_bound = others.min(due);
    Some((to, data_at.saturating_add(size)))
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
    for slot in 0..crate::config::MAX_CONNECTIONS {
        if let Some(Transport::Class1 {
            producer: Some(p), ..
        }) = table.get_mut(slot).map(|c| &mut c.transport)
        {
            if p.trigger != Trigger::Cyclic && pick(p) {
                p.triggered = true;
                let due = p.due_at();
                table.production_bound = table.production_bound.min(due);
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
