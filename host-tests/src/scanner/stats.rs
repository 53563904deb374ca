//! Interval statistics of received T->O packets.

/// What one connection's received packets show.
#[derive(Debug, Clone, PartialEq)]
pub struct ConnectionStats {
    /// T->O connection ID.
    pub t_o_id: u32,
    /// Packets received.
    pub received: usize,
    /// Packets missing from the 32-bit sequence numbers.
    pub lost: u64,
    /// Median interval, microseconds.
    pub p50_us: u64,
    /// 99th percentile interval, microseconds.
    pub p99_us: u64,
    /// Largest interval, microseconds.
    pub max_us: u64,
}

/// Totals over all connections.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// Per connection.
    pub connections: Vec<ConnectionStats>,
    /// Connections the adapter closed (no packets in the last part of the run).
    pub timeouts: usize,
}

/// The `q`-quantile (0..=1) of sorted `values`.
pub fn quantile(sorted: &[u64], q: f64) -> u64 {
    if sorted.is_empty() {
        return 0;
    }
    let i = ((sorted.len() - 1) as f64 * q).round() as usize;
    sorted[i.min(sorted.len() - 1)]
}

/// Statistics of one connection's packets: (arrival in microseconds, sequence number).
pub fn connection_stats(t_o_id: u32, packets: &[(u64, u32)]) -> ConnectionStats {
    let mut intervals: Vec<u64> = packets
        .windows(2)
        .map(|w| w[1].0.saturating_sub(w[0].0))
        .collect();
    intervals.sort_unstable();
    let lost = packets
        .windows(2)
        .map(|w| u64::from(w[1].1.wrapping_sub(w[0].1).saturating_sub(1)))
        .sum();
    ConnectionStats {
        t_o_id,
        received: packets.len(),
        lost,
        p50_us: quantile(&intervals, 0.5),
        p99_us: quantile(&intervals, 0.99),
        max_us: intervals.last().copied().unwrap_or(0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stats_of_a_steady_stream_with_one_gap() {
        let packets: Vec<(u64, u32)> = (0..100u32)
            .filter(|&i| i != 50)
            .map(|i| (u64::from(i) * 1000, i))
            .collect();
        let s = connection_stats(7, &packets);
        assert_eq!(
            (s.received, s.lost, s.p50_us, s.max_us),
            (99, 1, 1000, 2000)
        );
    }
}
