//! The emulated board's latencies and explicit path for `cargo xtask bench --qemu`, counted
//! from the same execution trace as its Class 1 cycle ([`crate::bench_qemu`]):
//!
//! - O->T to the device: instructions from the wake-up that finds an O->T datagram (the
//!   first instruction outside the executor's idle loop, i.e. the interrupt's entry) to the
//!   call of the device's `write_assembly`, 1 connection at 10 ms;
//! - input change to the driver: from the call of `write_assembly` in which the generic
//!   profile marks its input changed (it echoes new outputs) to the T->O frame handed to the
//!   LAN9118 driver (`push_frame`) in the same wake-up, on a change-of-state and on an
//!   application-triggered connection (inhibit time 0, the scanner's data new at every
//!   datagram);
//! - one explicit request: whole-firmware instructions per Get_Attribute_Single (UCMM) on one
//!   session, smoltcp's TCP included (`request_rate`), by part.
//!
//! Microseconds are an estimate for the NUCLEO-F767ZI's 216 MHz at one instruction per clock,
//! labelled as such: the M7 is dual-issue but waits on flash and memory.

use serde_json::{json, Value};

use crate::bench_qemu::{print_cost, traced_runs, Load, M4};
use crate::bench_qemu_trace::{median, Cost, Symbols};
use crate::bench_scale::Scale;
use crate::util::Result;
use std::path::Path;

/// The NUCLEO-F767ZI's core clock, MHz, for the estimates.
const NUCLEO_MHZ: f64 = 216.0;
/// The latency runs' RPI, µs.
const LATENCY_RPI_US: u32 = 10_000;

/// The latency figures: O->T to `write_assembly` from `cyclic` (the 1-connection runs), and
/// input change to the driver from change-of-state and application-triggered runs.
pub fn latency(
    elf: &Path,
    symbols: &Symbols,
    dir: &Path,
    scale: Scale,
    cyclic: &[Cost],
) -> Result<Value> {
    let to_device = figure(cyclic.iter().map(|c| median(&c.to_device)));
    println!("  O->T frame -> write_assembly: {}", line(&to_device));
    let mut out = json!({
        "note": "instructions of the emulated Cortex-M4, median of the runs' medians; us: an estimate at 216 MHz (NUCLEO-F767ZI), one instruction per clock",
        "o_t_to_write_assembly": to_device,
    });
    for (trigger, key) in [
        ("cos", "change_of_state_to_driver"),
        ("app", "application_triggered_to_driver"),
    ] {
        let load = Load::Class1 {
            connections: 1,
            rpi_us: LATENCY_RPI_US,
            trigger,
        };
        let runs = traced_runs(M4, elf, symbols, dir, load, scale, false)?;
        print_cost(&load.title(), &runs[runs.len() / 2]);
        let to_driver = figure(runs.iter().map(|c| median(&c.to_driver)));
        println!(
            "  input change -> T->O frame to the driver: {}",
            line(&to_driver)
        );
        out[key] = to_driver;
        out[format!("{key}_o_t_to_write_assembly")] =
            figure(runs.iter().map(|c| median(&c.to_device)));
    }
    Ok(out)
}

/// Instructions per Get_Attribute_Single on one session, whole firmware, by part (one run if
/// `once`).
pub fn explicit(
    elf: &Path,
    symbols: &Symbols,
    dir: &Path,
    scale: Scale,
    once: bool,
) -> Result<Value> {
    let runs = traced_runs(M4, elf, symbols, dir, Load::Requests, scale, once)?;
    let median = &runs[runs.len() / 2];
    print_cost(&Load::Requests.title(), median);
    let all: Vec<f64> = runs.iter().map(|c| c.per_cycle(c.total())).collect();
    println!("  runs: {all:?}");
    let mut out = median.to_json(0, 0);
    out["instructions_per_request"] = median.per_cycle(median.total()).into();
    out["runs"] = all.into();
    Ok(out)
}

/// The median of per-run figures, with the estimate in µs and the runs.
fn figure(runs: impl Iterator<Item = u64>) -> Value {
    let mut all: Vec<u64> = runs.collect();
    all.sort_unstable();
    let instructions = median(&all);
    json!({
        "instructions": instructions,
        "us_at_216_mhz_estimate": (instructions as f64 / NUCLEO_MHZ * 100.0).round() / 100.0,
        "runs": all,
    })
}

/// One printed line of a [`figure`].
fn line(figure: &Value) -> String {
    format!(
        "{} instructions (runs {}), about {} us at 216 MHz (estimate)",
        figure["instructions"], figure["runs"], figure["us_at_216_mhz_estimate"]
    )
}
