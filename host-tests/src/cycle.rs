//! What the Class 1 cycle benchmarks (`io_cycle`, `io_runtime`) share: the generic profile's
//! exclusive owner opened on a virtual scanner, and its O->T datagram.

use std::net::SocketAddrV4;

use enip_profiles::generic::Generic;
use enip_stack::originator;
use enip_stack::virtual_scanner::{VirtualScanner, SCANNER_IP};
use enip_stack::wire::forward_open::Triad;

use crate::scanner::{generic_forward_open, OWNER_O_T, OWNER_PATH};

/// The connection's RPI, both directions.
pub const RPI_US: u64 = 1_000;

/// A scanner holding the generic profile's exclusive owner (150 -> 100, config 151) at
/// [`RPI_US`], and the connection's O->T ID.
pub fn exclusive_owner() -> (VirtualScanner<Generic>, u32) {
    let mut scanner = VirtualScanner::new(Generic::new());
    let triad = Triad {
        connection_serial: 1,
        vendor_id: 0xF00D,
        originator_serial: 1,
    };
    let opened = scanner.forward_open(&generic_forward_open(
        triad,
        0x5C00_0000,
        &OWNER_PATH,
        OWNER_O_T,
        2,
        RPI_US as u32,
    ));
    assert_eq!(opened.general, 0, "Forward_Open refused");
    (scanner, opened.o_t_id)
}

/// Where the scanner sends O->T data from.
pub fn scanner_address() -> SocketAddrV4 {
    SocketAddrV4::new(SCANNER_IP, 2222)
}

/// The O->T datagram of connection `o_t` (run, 32 bytes of outputs) in `buf`; returns its
/// length. Built once: a cycle only patches its two sequence numbers (bytes 10..14 and
/// 18..20), so a count is the adapter's work, not the originator's.
pub fn o_t_datagram(buf: &mut [u8], o_t: u32) -> usize {
    originator::io_datagram(buf, o_t, 0, 0, Some(true), &[0x5A; 32]).expect("datagram")
}

/// The cycle count a driver program's first argument names (a million without one).
pub fn cycles_from_args() -> u64 {
    std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(1_000_000)
}
