//! `io_cycle N`: drives the sans-IO adapter with the generic profile through N Class 1
//! cycles (consume one O->T datagram, produce one T->O datagram) after opening one
//! exclusive-owner connection. Run under callgrind by `cargo xtask bench` for instruction
//! counts (two runs of different N, so set-up cancels out), and natively for time per cycle.

use std::hint::black_box;
use std::net::SocketAddrV4;
use std::time::Instant as WallClock;

use enip_firmware::profiles::generic::Generic;
use enip_stack::originator;
use enip_stack::virtual_scanner::{VirtualScanner, SCANNER_IP};
use enip_stack::wire::forward_open::{ForwardOpen, NetworkParams, Triad};
use enip_stack::Instant;

const RPI_US: u64 = 1_000;

/// The generic profile's exclusive owner (150 -> 100, config 151).
fn exclusive_owner(path: &[u8]) -> ForwardOpen<'_> {
    ForwardOpen {
        large: false,
        priority_tick: 0x0A,
        timeout_ticks: 0x0E,
        o_t_connection_id: 0,
        t_o_connection_id: 0x5C00_0000,
        triad: Triad {
            connection_serial: 1,
            vendor_id: 0xF00D,
            originator_serial: 1,
        },
        timeout_multiplier: 2,
        o_t_rpi: RPI_US as u32,
        o_t_params: NetworkParams::from_u16(0x4800 | 38),
        t_o_rpi: RPI_US as u32,
        t_o_params: NetworkParams::from_u16(0x4800 | 34),
        transport: 0x01,
        path,
    }
}

fn main() {
    let cycles: u64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(1_000_000);
    let mut scanner = VirtualScanner::new(Generic::new());
    let path = [0x20, 0x04, 0x24, 151, 0x2C, 150, 0x2C, 100];
    let opened = scanner.forward_open(&exclusive_owner(&path));
    assert_eq!(opened.general, 0, "Forward_Open refused");
    let o_t = opened.o_t_id;
    let adapter = scanner.adapter_mut();
    let scanner = SocketAddrV4::new(SCANNER_IP, 2222);
    // The O->T datagram is built once; each cycle only patches its two sequence numbers, so
    // the count is the adapter's work, not the originator's.
    let mut rx = [0u8; 64];
    let n = originator::io_datagram(&mut rx, o_t, 0, 0, Some(true), &[0x5A; 32]).expect("datagram");
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
