//! `timer_baseline SECONDS`: the host's own scheduling floor for a 1 ms period. A plain
//! thread sleeps to absolute 1 ms deadlines and records when it wakes; the intervals'
//! percentiles are what no program on this machine can beat, so `cargo xtask bench` prints
//! them beside the board's T->O intervals.

use std::thread;
use std::time::{Duration, Instant};

use host_tests::scanner::stats::quantile;

fn main() {
    let seconds: u64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(10);
    let period = Duration::from_millis(1);
    let start = Instant::now();
    let ticks = seconds * 1000;
    let mut wakes = Vec::with_capacity(ticks as usize);
    for k in 1..=ticks {
        let at = start + period * k as u32;
        if let Some(wait) = at.checked_duration_since(Instant::now()) {
            thread::sleep(wait);
        }
        wakes.push(start.elapsed().as_micros() as u64);
    }
    let mut intervals: Vec<u64> = wakes.windows(2).map(|w| w[1] - w[0]).collect();
    intervals.sort_unstable();
    println!(
        "{{\"period_us\":1000,\"seconds\":{seconds},\"p50_us\":{},\"p99_us\":{},\"max_us\":{}}}",
        quantile(&intervals, 0.5),
        quantile(&intervals, 0.99),
        intervals.last().copied().unwrap_or(0)
    );
}
