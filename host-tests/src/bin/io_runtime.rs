//! `io_runtime N`: drives the sans-IO adapter with the generic profile through N Class 1
//! cycles the way the firmware's link task (`enip_firmware::link`) does, each entry point
//! called out of line: an O->T datagram wakes it (the interface addresses, `io_receive`,
//! then `io_due` finding nothing due with the watchdog count read around it, and
//! `io_deadline`), and the production deadline wakes it (the same, with `write_io` into the
//! transmit buffer). Run under callgrind like `io_cycle` (two runs of different N) for the
//! stack's instructions per cycle inside a running adapter.

use std::hint::black_box;

use enip_profiles::generic::Generic;
use enip_stack::{Adapter, Instant};
use host_tests::cycle::{cycles_from_args, exclusive_owner, o_t_datagram, scanner_address, RPI_US};

/// The queries the link task makes on every wake-up besides `io_due`: the interface
/// addresses, the watchdog count (read around each `io_due`) and the next deadline.
#[inline(never)]
fn queries(a: &mut Adapter<Generic>) {
    black_box(a.network().ip);
    black_box(a.connections().timeouts());
    black_box(a.io_deadline());
}

/// One O->T datagram handed to the adapter.
#[inline(never)]
fn receive(a: &mut Adapter<Generic>, rx: &[u8], now: Instant) {
    let _ = black_box(a.io_receive(scanner_address(), black_box(rx), now));
}

/// Every T->O datagram due at `now`, each built into the transmit buffer `tx`; how many.
#[inline(never)]
fn produce(a: &mut Adapter<Generic>, now: Instant, tx: &mut [u8]) -> u64 {
    let mut n = 0;
    while let Some(due) = a.io_due(now) {
        let len = a.write_io(due, now, tx.get_mut(..due.max_len));
        black_box(&tx[..len]);
        n += 1;
    }
    n
}

fn main() {
    let cycles = cycles_from_args();
    let (mut scanner, o_t) = exclusive_owner();
    let adapter = scanner.adapter_mut();
    let mut rx = [0u8; 64];
    let n = o_t_datagram(&mut rx, o_t);
    let mut tx = [0u8; 128];
    let mut produced = 0u64;
    for k in 1..=cycles {
        // The O->T datagram arrives half-way between two productions.
        let received = Instant(k * RPI_US - RPI_US / 2);
        rx[10..14].copy_from_slice(&(k as u32).to_le_bytes());
        rx[18..20].copy_from_slice(&(k as u16).to_le_bytes());
        receive(adapter, &rx[..n], received);
        produced += produce(adapter, received, &mut tx);
        queries(adapter);
        let due = Instant(k * RPI_US);
        produced += produce(adapter, due, &mut tx);
        queries(adapter);
    }
    assert!(produced >= cycles, "every cycle produces");
    println!("{{\"cycles\":{cycles},\"produced\":{produced}}}");
}
