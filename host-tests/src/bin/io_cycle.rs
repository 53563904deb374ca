//! `io_cycle N`: drives the sans-IO adapter with the generic profile through N Class 1
//! cycles (consume one O->T datagram, produce one T->O datagram) after opening one
//! exclusive-owner connection. Run under callgrind by `cargo xtask bench` for instruction
//! counts (two runs of different N, so set-up cancels out), and natively for time per cycle.

use std::hint::black_box;
use std::time::Instant as WallClock;

use enip_stack::Instant;
use host_tests::cycle::{cycles_from_args, exclusive_owner, o_t_datagram, scanner_address, RPI_US};

fn main() {
    let cycles = cycles_from_args();
    let (mut scanner, o_t) = exclusive_owner();
    let adapter = scanner.adapter_mut();
    let scanner = scanner_address();
    // The O->T datagram is built once; each cycle only patches its two sequence numbers, so
    // the count is the adapter's work, not the originator's.
    let mut rx = [0u8; 64];
    let n = o_t_datagram(&mut rx, o_t);
    let mut tx = [0u8; 128];
    let mut produced = 0u64;
    let started = WallClock::now();
    for k in 1..=cycles {
        let now = Instant(k * RPI_US);
        rx[10..14].copy_from_slice(&(k as u32).to_le_bytes());
        rx[18..20].copy_from_slice(&(k as u16).to_le_bytes());
        let _ = black_box(adapter.io_receive(scanner, black_box(&rx[..n]), now));
        while let Some((_, len)) = adapter.poll_io(now, &mut tx) {
            black_box(&tx[..len]);
            produced += 1;
        }
    }
    let elapsed = started.elapsed();
    assert!(produced >= cycles, "every cycle produces");
    println!(
        "{{\"cycles\":{cycles},\"produced\":{produced},\"ns_per_cycle\":{:.1}}}",
        elapsed.as_nanos() as f64 / cycles as f64
    );
}
