//! What the W5500-EVB-Pico can sustain of Class 1, from arithmetic (no board here to measure
//! on), and the RPI floor that holds Forward_Opens to it ([`rpi_floor_us`], applied through
//! `enip_firmware::RpiFloor`).
//!
//! Every frame crosses the SPI bus between the RP2040 and the W5500, one at a time (the
//! W5500 driver's runner task moves them). Per frame, embassy-net-wiznet 0.3's MACRAW driver
//! makes these SPI transactions (3 bytes of address and control each, then the data, framed
//! by the chip select):
//!
//! - receive: the received size twice (2 bytes each, until two reads agree), clear the
//!   interrupt (1), the read pointer (2), the frame's length header (2), the frame, the new
//!   read pointer (2), the RECV command (1): 8 transactions, 36 bytes besides the frame;
//! - send: the free size (2), the write pointer (2), the frame, the new write pointer (2),
//!   the SEND command (1): 5 transactions, 22 bytes besides the frame.
//!
//! A Class 1 frame is the connection size (data, 2-byte sequence count, 4-byte run/idle
//! header where used) behind 60 bytes of headers (Ethernet 14, IPv4 20, UDP 8, Common Packet
//! Format 18: item count, sequenced address item, connected data item header), at least 60
//! bytes (the W5500 hands over and takes frames without the FCS).
//!
//! Figures: SPI clock [`SPI_HZ`] (50 MHz asked as embassy's W5500-EVB-Pico examples do; the
//! RP2040's SPI divides the 125 MHz peripheral clock by an even prescaler and a post-divider,
//! so 31.25 MHz, inside the W5500's guaranteed 33.3 MHz); [`CLOCKS_PER_BYTE`] clocks a byte;
//! [`TRANSACTION_US`] of processor time per transaction and [`CYCLE_CPU_US`] per Class 1
//! cycle are estimates, stated with their reasoning below. One Class 1 cycle of a connection
//! (one O->T frame in, one T->O frame out) of io-block's sizes (8 and 4 bytes: 68- and
//! 64-byte frames) then takes 61 us on the wire, 195 us in the driver's transactions and
//! 100 us in the link task and the adapter: 356 us, so about 2 800 cycles a second with
//! nothing else running. The floor keeps [`MAX_CONNECTIONS`] connections of a request's
//! sizes within [`CLASS1_SHARE_PERCENT`] % of the board's time (the rest for explicit
//! messaging, ARP, LLDP, the link poll and bursts), rounded up to a whole millisecond:
//! 8 ms for io-block's connections, 14 ms for 500 bytes each way. It is conservative for
//! fewer connections (one alone could run at about 1 ms).

use enip_stack::config::MAX_CONNECTIONS;
use enip_stack::device::OpenRequest;

/// SPI clock to the W5500, Hz: 125 MHz / 2 / 2.
pub const SPI_HZ: u32 = 31_250_000;
/// SPI clocks a byte takes: 8, and (assumed) 2 between bytes, where the RP2040's PL022 in
/// mode 0 pulses its frame signal.
pub const CLOCKS_PER_BYTE: u32 = 10;
/// Processor time per SPI transaction, us (estimate): three DMA transfers, each started,
/// awaited through the DMA interrupt and the executor (about 600 cycles of the 125 MHz
/// Cortex-M0+), and the chip select.
pub const TRANSACTION_US: u32 = 15;
/// Processor time of the link task and the adapter per Class 1 cycle, us (estimate): the
/// emulated Cortex-M4 runs 3 824 instructions a cycle (README, bench); Thumb-1 code takes
/// about 1.5 times as many (counted in the two images' code: 1.46 times the NUCLEO's
/// instructions for the stack's functions, 1.55 for the firmware's), at about 2 cycles each
/// from the XIP cache at 125 MHz: 92 us.
pub const CYCLE_CPU_US: u32 = 100;
/// Share of the board's time Class 1 may take at the floor, percent.
pub const CLASS1_SHARE_PERCENT: u32 = 50;

/// Bytes of headers before a Class 1 connection's data in an Ethernet frame.
const HEADERS: u32 = 14 + 20 + 8 + 18;
/// The shortest Ethernet frame, without its FCS.
const MIN_FRAME: u32 = 60;
/// SPI transactions and bytes besides the frame, to receive one frame.
const RX_TRANSACTIONS: u32 = 8;
const RX_BYTES: u32 = 36;
/// SPI transactions and bytes besides the frame, to send one frame.
const TX_TRANSACTIONS: u32 = 5;
const TX_BYTES: u32 = 22;

/// Bytes of the Ethernet frame of a Class 1 connection of `size` bytes.
const fn frame(size: u16) -> u32 {
    let bytes = HEADERS + size as u32;
    if bytes < MIN_FRAME {
        MIN_FRAME
    } else {
        bytes
    }
}

/// Nanoseconds of one Class 1 cycle of a connection of sizes `o_t` and `t_o`: one frame of
/// each across the SPI bus, and the processor's share.
pub const fn cycle_ns(o_t: u16, t_o: u16) -> u32 {
    let bytes = RX_BYTES + frame(o_t) + TX_BYTES + frame(t_o);
    let wire = (bytes as u64 * CLOCKS_PER_BYTE as u64 * 1_000_000_000 / SPI_HZ as u64) as u32;
    let software = (RX_TRANSACTIONS + TX_TRANSACTIONS) * TRANSACTION_US + CYCLE_CPU_US;
    wire + software * 1_000
}

/// The RPI floor, us, of connections of sizes `o_t` and `t_o`: [`MAX_CONNECTIONS`] of them
/// within [`CLASS1_SHARE_PERCENT`] % of the time, rounded up to a whole millisecond.
pub const fn floor_us(o_t: u16, t_o: u16) -> u32 {
    let busy_ns = MAX_CONNECTIONS as u32 * cycle_ns(o_t, t_o);
    let rpi_us = busy_ns / 10 / CLASS1_SHARE_PERCENT;
    rpi_us.div_ceil(1_000) * 1_000
}

/// The RPI floor of a Forward_Open, us, from its connection sizes.
pub fn rpi_floor_us(request: &OpenRequest<'_>) -> u32 {
    floor_us(request.o_t.params.size, request.t_o.params.size)
}

// The figures the module documentation and the README give.
const _: () = assert!(cycle_ns(8, 4) == 355_800);
const _: () = assert!(floor_us(8, 4) == 8_000);
const _: () = assert!(floor_us(506, 502) == 14_000);
