//! `scanner`: opens N connections on the generic profile at a given RPI, exchanges I/O for a
//! while (or until the file `--stop-file` names exists), closes them, and prints
//! per-connection interval statistics (and JSON with --json).

use std::net::Ipv4Addr;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use host_tests::scanner::{exchange_until, open_generic_triggered, Session};
use host_tests::stop_file::StopFile;

struct Args {
    target: Ipv4Addr,
    connections: usize,
    rpi_us: u32,
    seconds: u64,
    multiplier: u8,
    /// Transport class and trigger byte of the Forward_Opens (0x01: cyclic).
    transport: u8,
    json: Option<String>,
    /// The run ends early once this file exists.
    stop_file: Option<PathBuf>,
}

fn parse() -> Result<Args, String> {
    let mut a = Args {
        target: Ipv4Addr::new(198, 18, 0, 2),
        connections: 1,
        rpi_us: 10_000,
        seconds: 5,
        multiplier: 2,
        transport: 0x01,
        json: None,
        stop_file: None,
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or_else(|| format!("{flag} needs a value"));
        match flag.as_str() {
            "--target" => a.target = value()?.parse().map_err(|e| format!("--target: {e}"))?,
            "--connections" => a.connections = value()?.parse().map_err(|e| format!("--connections: {e}"))?,
            "--rpi-us" => a.rpi_us = value()?.parse().map_err(|e| format!("--rpi-us: {e}"))?,
            "--seconds" => a.seconds = value()?.parse().map_err(|e| format!("--seconds: {e}"))?,
            "--multiplier" => a.multiplier = value()?.parse().map_err(|e| format!("--multiplier: {e}"))?,
            "--trigger" => {
                a.transport = match value()?.as_str() {
                    "cyclic" => 0x01,
                    "cos" => 0x11,
                    "app" => 0x21,
                    other => return Err(format!("--trigger: {other} is not cyclic, cos or app")),
                }
            }
            "--json" => a.json = Some(value()?),
            "--stop-file" => a.stop_file = Some(value()?.into()),
            "-h" | "--help" => {
                return Err("usage: scanner [--target IP] [--connections N] [--rpi-us US] [--seconds S] [--multiplier CODE] [--trigger cyclic|cos|app] [--json PATH] [--stop-file PATH]".into())
            }
            other => return Err(format!("unknown argument {other}")),
        }
    }
    Ok(a)
}

fn run(a: &Args) -> Result<(), String> {
    let mut session =
        Session::connect(a.target, Duration::from_secs(3)).map_err(|e| format!("connect: {e}"))?;
    let opened = open_generic_triggered(
        &mut session,
        a.connections,
        a.rpi_us,
        a.multiplier,
        a.transport,
    )
    .map_err(|e| e.to_string())?;
    eprintln!(
        "scanner: {} connections open at {} us",
        opened.len(),
        a.rpi_us
    );
    let duration = Duration::from_secs(a.seconds);
    let record = exchange_until(
        a.target,
        &opened,
        Duration::from_micros(u64::from(a.rpi_us)),
        duration,
        |k| [k as u8; 32],
        StopFile::new(a.stop_file.clone()),
    )
    .map_err(|e| format!("exchange: {e}"))?;
    for c in &opened {
        let r = session
            .forward_close(c.triad)
            .map_err(|e| format!("forward close: {e}"))?;
        if r.general != 0 {
            eprintln!(
                "scanner: Forward_Close of {:#x} answered {:#x}",
                c.t_o_id, r.general
            );
        }
    }
    let end = record.ended_us;
    let quiet = 16 * u64::from(a.rpi_us) * (4u64 << a.multiplier);
    let summary = record.summary(end, quiet);
    println!(
        "{:>10} {:>9} {:>6} {:>8} {:>8} {:>8}",
        "T->O id", "received", "lost", "p50 us", "p99 us", "max us"
    );
    for c in &summary.connections {
        println!(
            "{:>#10x} {:>9} {:>6} {:>8} {:>8} {:>8}",
            c.t_o_id, c.received, c.lost, c.p50_us, c.p99_us, c.max_us
        );
    }
    println!(
        "sent {} O->T datagrams; connections without traffic at the end: {}",
        record.sent, summary.timeouts
    );
    if let Some(path) = &a.json {
        let conns: Vec<_> = summary
            .connections
            .iter()
            .map(|c| serde_json::json!({"t_o_id": c.t_o_id, "received": c.received, "lost": c.lost, "p50_us": c.p50_us, "p99_us": c.p99_us, "max_us": c.max_us}))
            .collect();
        let worst = |f: fn(&host_tests::scanner::ConnectionStats) -> u64| {
            summary.connections.iter().map(f).max().unwrap_or(0)
        };
        let doc = serde_json::json!({"worst_p99_us": worst(|c| c.p99_us), "worst_max_us": worst(|c| c.max_us), "total_lost": summary.connections.iter().map(|c| c.lost).sum::<u64>(), "rpi_us": a.rpi_us, "seconds": a.seconds, "connections": conns, "timeouts": summary.timeouts, "sent": record.sent, "expected_per_connection": end / u64::from(a.rpi_us)});
        std::fs::write(path, doc.to_string()).map_err(|e| format!("{path}: {e}"))?;
    }
    Ok(())
}

fn main() -> ExitCode {
    match parse().and_then(|a| run(&a)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("scanner: {e}");
            ExitCode::FAILURE
        }
    }
}
