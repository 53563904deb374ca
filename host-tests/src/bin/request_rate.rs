//! `request_rate`: Get_Attribute_Single requests (Identity vendor ID) on N sessions at once,
//! one thread each, for a while: back to back, or paced to a total rate (`--rate`, requests
//! per second over all sessions), ending early once the file `--stop-file` names exists;
//! prints the requests answered as JSON.

use std::net::Ipv4Addr;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use host_tests::scanner::Session;
use host_tests::stop_file::StopFile;

/// Identity object, instance 1, attribute 1 (vendor ID).
const VENDOR: [SegmentRepr<'static>; 3] = [
    SegmentRepr::Logical(LogicalType::Class, 1),
    SegmentRepr::Logical(LogicalType::Instance, 1),
    SegmentRepr::Logical(LogicalType::Attribute, 1),
];

/// What to run: the target, sessions, seconds, the total rate (0: back to back) and the
/// file that ends the run early.
struct Args {
    target: Ipv4Addr,
    sessions: usize,
    seconds: u64,
    rate: u32,
    stop_file: Option<PathBuf>,
}

fn parse() -> Result<Args, String> {
    let (mut target, mut sessions, mut seconds) = (Ipv4Addr::new(198, 18, 0, 2), 1, 5);
    let (mut rate, mut stop_file) = (0, None);
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let value = it.next().ok_or_else(|| format!("{flag} needs a value"))?;
        let bad = |e: &dyn std::fmt::Display| format!("{flag}: {e}");
        match flag.as_str() {
            "--target" => target = value.parse().map_err(|e| bad(&e))?,
            "--sessions" => sessions = value.parse().map_err(|e| bad(&e))?,
            "--seconds" => seconds = value.parse().map_err(|e| bad(&e))?,
            "--rate" => rate = value.parse().map_err(|e| bad(&e))?,
            "--stop-file" => stop_file = Some(value.into()),
            _ => {
                return Err(
                    "usage: request_rate [--target IP] [--sessions N] [--seconds S] \
                     [--rate R] [--stop-file PATH]"
                        .into(),
                )
            }
        }
    }
    Ok(Args {
        target,
        sessions,
        seconds,
        rate,
        stop_file,
    })
}

/// Requests answered on one session until `end` (or `stop`), one every `period` from
/// `first` (none: back to back). A session that falls behind by a period starts counting
/// anew from now (no burst to catch up).
fn hammer(
    target: Ipv4Addr,
    end: Instant,
    pace: Option<(Instant, Duration)>,
    mut stop: StopFile,
) -> Result<u64, String> {
    let mut s = Session::connect(target, Duration::from_secs(3)).map_err(|e| e.to_string())?;
    let mut done = 0u64;
    let mut next = pace.map(|(first, _)| first);
    while Instant::now() < end && !stop.asked() {
        if let (Some(at), Some((_, period))) = (next.as_mut(), pace) {
            let now = Instant::now();
            match at.checked_duration_since(now) {
                Some(wait) => std::thread::sleep(wait),
                None if now.duration_since(*at) > period => *at = now,
                None => {}
            }
            *at += period;
        }
        let r = s
            .request(0x0E, &VENDOR, &[])
            .map_err(|e| format!("request: {e}"))?;
        if r.general != 0 {
            return Err(format!("general status {:#x}", r.general));
        }
        done += 1;
    }
    Ok(done)
}

fn main() -> ExitCode {
    let Args {
        target,
        sessions,
        seconds,
        rate,
        stop_file,
    } = match parse() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("request_rate: {e}");
            return ExitCode::from(2);
        }
    };
    let start = Instant::now();
    let end = start + Duration::from_secs(seconds);
    // Each session sends every `sessions / rate` seconds, the sessions staggered evenly.
    let period = (rate > 0).then(|| Duration::from_secs_f64(sessions as f64 / f64::from(rate)));
    let counts: Vec<Result<u64, String>> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..sessions)
            .map(|i| {
                let pace = period.map(|p| (start + p.mul_f64(i as f64 / sessions as f64), p));
                let stop = StopFile::new(stop_file.clone());
                s.spawn(move || hammer(target, end, pace, stop))
            })
            .collect();
        workers
            .into_iter()
            .map(|w| w.join().unwrap_or_else(|_| Err("worker panicked".into())))
            .collect()
    });
    let elapsed = start.elapsed().as_secs_f64();
    let mut total = 0;
    for c in counts {
        match c {
            Ok(n) => total += n,
            Err(e) => {
                eprintln!("request_rate: {e}");
                return ExitCode::FAILURE;
            }
        }
    }
    println!(
        "{}",
        serde_json::json!({
            "sessions": sessions,
            "rate": rate,
            "seconds": elapsed,
            "requests": total,
            "per_second": (total as f64 / elapsed).round(),
        })
    );
    ExitCode::SUCCESS
}
