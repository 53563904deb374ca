//! `request_rate`: back-to-back Get_Attribute_Single requests (Identity vendor ID) on N
//! sessions at once, one thread each, for a while; prints the requests answered as JSON.

use std::net::Ipv4Addr;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use host_tests::scanner::Session;

/// Identity object, instance 1, attribute 1 (vendor ID).
const VENDOR: [SegmentRepr<'static>; 3] = [
    SegmentRepr::Logical(LogicalType::Class, 1),
    SegmentRepr::Logical(LogicalType::Instance, 1),
    SegmentRepr::Logical(LogicalType::Attribute, 1),
];

fn parse() -> Result<(Ipv4Addr, usize, u64), String> {
    let (mut target, mut sessions, mut seconds) = (Ipv4Addr::new(198, 18, 0, 2), 1, 5);
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let value = it.next().ok_or_else(|| format!("{flag} needs a value"))?;
        let bad = |e: &dyn std::fmt::Display| format!("{flag}: {e}");
        match flag.as_str() {
            "--target" => target = value.parse().map_err(|e| bad(&e))?,
            "--sessions" => sessions = value.parse().map_err(|e| bad(&e))?,
            "--seconds" => seconds = value.parse().map_err(|e| bad(&e))?,
            _ => {
                return Err("usage: request_rate [--target IP] [--sessions N] [--seconds S]".into())
            }
        }
    }
    Ok((target, sessions, seconds))
}

/// Requests answered on one session until `end`.
fn hammer(target: Ipv4Addr, end: Instant) -> Result<u64, String> {
    let mut s = Session::connect(target, Duration::from_secs(3)).map_err(|e| e.to_string())?;
    let mut done = 0u64;
    while Instant::now() < end {
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
    let (target, sessions, seconds) = match parse() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("request_rate: {e}");
            return ExitCode::from(2);
        }
    };
    let start = Instant::now();
    let end = start + Duration::from_secs(seconds);
    let counts: Vec<Result<u64, String>> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..sessions)
            .map(|_| s.spawn(move || hammer(target, end)))
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
            "seconds": elapsed,
            "requests": total,
            "per_second": (total as f64 / elapsed).round(),
        })
    );
    ExitCode::SUCCESS
}
