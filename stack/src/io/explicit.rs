//! Class 3 connected explicit messaging: connection lookup per session, and the cached
//! reply that answers a repeated sequence count without executing the request again.

use super::connection::Transport;
use super::table::ConnectionTable;
use crate::time::Instant;

/// What to do with a SendUnitData request on a Class 3 connection.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Step {
    /// A new request: execute it, then [`store`] the reply.
    Execute {
        /// Table slot.
        slot: usize,
        /// T->O connection ID for the reply's address item.
        t_o_id: u32,
    },
    /// A repeated sequence count: resend the cached reply of this slot.
    Repeat {
        /// Table slot.
        slot: usize,
        /// T->O connection ID for the reply's address item.
        t_o_id: u32,
    },
}

/// Finds the Class 3 connection `o_t_id` opened by socket `socket`, feeds its watchdog and
/// says whether `sequence` is new.
pub fn lookup<const C: usize>(
    table: &mut ConnectionTable<C>,
    o_t_id: u32,
    socket: u8,
    sequence: u16,
    now: Instant,
) -> Option<Step> {
    let (slot, conn) = table.find_o_t_mut(o_t_id)?;
    let Transport::Class3 { last_sequence } = &conn.transport else {
        return None;
    };
    if conn.socket != socket {
        return None;
    }
    let repeat = *last_sequence == Some(sequence);
    let t_o_id = conn.t_o_id;
    table.feed(slot, now);
    Some(if repeat {
        Step::Repeat { slot, t_o_id }
    } else {
        Step::Execute { slot, t_o_id }
    })
}

/// The reply cached in `slot`.
pub fn cached<const C: usize>(table: &ConnectionTable<C>, slot: usize) -> &[u8] {
    table.cached_reply(slot)
}

/// Caches `reply` as the answer to `sequence` on the connection `o_t_id` in `slot` (a reply
/// too large to cache is executed again if repeated). Nothing if that connection has gone
/// meanwhile: closed by its own request, its slot may hold a new connection already, which
/// starts without a cached reply.
pub fn store<const C: usize>(
    table: &mut ConnectionTable<C>,
    slot: usize,
    o_t_id: u32,
    sequence: u16,
    reply: &[u8],
) {
    if table.get(slot).is_none_or(|c| c.o_t_id != o_t_id) {
        return;
    }
    let cached = table.reply_cache_mut(slot).is_some_and(|cache| {
        cache.clear();
        cache.extend_from_slice(reply).is_ok()
    });
    if let Some(Transport::Class3 { last_sequence, .. }) =
        table.get_mut(slot).map(|c| &mut c.transport)
    {
        *last_sequence = if cached { Some(sequence) } else { None };
    }
}
