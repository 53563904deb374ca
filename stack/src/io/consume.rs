//! Class 1 consumption: O->T datagrams from the originator, sequence rules, run/idle; an
//! accepted datagram feeds the connection's inactivity watchdog (the table's).

use core::net::SocketAddrV4;

use super::connection::Transport;
use super::table::ConnectionTable;
use crate::device::{ConnectionEvent, Device, Kind};
use crate::time::Instant;
use crate::wire::bytes::{get_u16, get_u32};
use crate::wire::io_datagram::{Packet, RUN_IDLE_LEN, SEQUENCE_LEN};

/// Why an O->T datagram was not accepted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Discard {
    /// Not a well-formed I/O datagram.
    Malformed,
    /// No Class 1 connection consumes this connection ID from this sender.
    UnknownConnection,
    /// The data length does not match the connection.
    WrongSize,
    /// An older or repeated encapsulation sequence number.
    Stale,
}

/// The outcome of an accepted datagram.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Accepted {
    /// New data, handed to the device.
    NewData,
    /// A repeated sequence count (or idle): the watchdog was fed, no data applied.
    NoNewData,
}

/// True if `new` is after `old` in 16-bit serial arithmetic.
const fn newer16(new: u16, old: u16) -> bool {
    (new.wrapping_sub(old) as i16) > 0
}

/// True if `new` is after `old` in 32-bit serial arithmetic.
const fn newer32(new: u32, old: u32) -> bool {
    (new.wrapping_sub(old) as i32) > 0
}

/// Handles an O->T datagram from `from`.
pub fn consume<D: Device, const C: usize>(
    table: &mut ConnectionTable<C>,
    device: &mut D,
    from: SocketAddrV4,
    datagram: &[u8],
    now: Instant,
) -> Result<Accepted, Discard> {
    let packet = Packet::new_checked(datagram).map_err(|_| Discard::Malformed)?;
    let (slot, conn) = table
        .find_o_t_mut(packet.connection_id())
        .ok_or(Discard::UnknownConnection)?;
    if conn.originator != *from.ip() {
        return Err(Discard::UnknownConnection);
    }
    let kind = conn.kind;
    let Transport::Class1 { consumer: c, .. } = &mut conn.transport else {
        return Err(Discard::UnknownConnection);
    };
    let data = packet.connected_data();
    // Small constants and a u16: the sum cannot overflow.
    let header = if c.run_idle {
        SEQUENCE_LEN + RUN_IDLE_LEN
    } else {
        SEQUENCE_LEN
    };
    // An idle datagram may carry its header alone: there is nothing to apply.
    if data.len() != header.saturating_add(usize::from(c.size))
        && !(c.run_idle && data.len() == header && get_u32(data, SEQUENCE_LEN) & 1 == 0)
    {
        return Err(Discard::WrongSize);
    }
    let encap = packet.encap_sequence();
    if c.last_encap_sequence
        .is_some_and(|old| !newer32(encap, old))
    {
        return Err(Discard::Stale);
    }
    c.last_encap_sequence = Some(encap);

    let sequence = get_u16(data, 0);
    let run = !c.run_idle || get_u32(data, SEQUENCE_LEN) & 1 == 1;
    let run_changed = c.run != run;
    c.run = run;
    let fresh = c.last_sequence.is_none_or(|old| newer16(sequence, old));
    if fresh {
        c.last_sequence = Some(sequence);
    }
    let (instance, size, run_idle) = (c.instance, c.size, c.run_idle);
    table.feed(slot, now);
    // Only the outputs' owner runs or idles the device: an input-only or listen-only
    // connection's header speaks for its heartbeat alone.
    if run_changed && run_idle && kind == Kind::ExclusiveOwner {
        device.connection_event(ConnectionEvent::RunIdle(run));
    }
    if !fresh || !run {
        return Ok(Accepted::NoNewData);
    }
    if size > 0 {
        let payload = data.get(header..).unwrap_or(&[]);
        // A device that refuses the data keeps its previous outputs; the connection goes on.
        let _ = device.write_assembly(instance, payload);
    }
    Ok(Accepted::NewData)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn serial_arithmetic_wraps() {
        assert!(newer16(1, 0));
        assert!(newer16(0, 0xFFFF));
        assert!(!newer16(5, 5));
        assert!(!newer16(4, 5));
        assert!(newer32(0, u32::MAX));
        assert!(!newer32(7, 7));
    }
}
