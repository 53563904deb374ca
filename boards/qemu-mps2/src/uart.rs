//! Logs over CMSDK APB UART0 (0x4000_4000; 0x5020_0000 on mps2-an505), which QEMU connects
//! to its first serial port
//! (standard output with `-nographic`), through the `log` facade.

use core::fmt::Write;

use log::{LevelFilter, Log, Metadata, Record};

use crate::mmio::Block;

const UART0: Block = Block::at(crate::machine::THIS.uart0);
const DATA: usize = 0x00;
const STATE: usize = 0x04;
const CTRL: usize = 0x08;
const BAUDDIV: usize = 0x10;
/// STATE: the transmit buffer is full.
const TX_FULL: u32 = 1 << 0;
/// CTRL: transmitter enabled.
const TX_EN: u32 = 1 << 0;
/// The system clock / 115200 baud.
const DIVISOR: u32 = crate::machine::THIS.clock_hz / 115_200;
/// How long to wait for room in the transmit buffer before dropping a byte.
const TX_SPINS: u32 = 100_000;

/// Writes bytes to UART0, waiting (bounded) for room before each.
struct Uart;

impl Write for Uart {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        for b in s.bytes() {
            let mut spins = 0;
            while UART0.read(STATE) & TX_FULL != 0 && spins < TX_SPINS {
                spins += 1;
            }
            UART0.write(DATA, u32::from(b));
        }
        Ok(())
    }
}

/// The `log` implementation: one line per record, with the uptime in seconds.
struct UartLogger;

impl Log for UartLogger {
    fn enabled(&self, metadata: &Metadata<'_>) -> bool {
        metadata.level() <= log::max_level()
    }

    fn log(&self, record: &Record<'_>) {
        if !self.enabled(record.metadata()) {
            return;
        }
        let us = embassy_time::Instant::now().as_micros();
        critical_section::with(|_| {
            let _ = writeln!(
                Uart,
                "[{:>5}.{:06} {:<5}] {}",
                us / 1_000_000,
                us % 1_000_000,
                record.level(),
                record.args()
            );
        });
    }

    fn flush(&self) {}
}

static LOGGER: UartLogger = UartLogger;

/// Enables the transmitter and installs the logger at `level`.
pub fn init(level: LevelFilter) {
    UART0.write(BAUDDIV, DIVISOR);
    UART0.write(CTRL, TX_EN);
    // Cannot fail: this is the only logger, installed once.
    let _ = log::set_logger(&LOGGER);
    log::set_max_level(level);
}

/// Writes one line straight to the UART, without the logger (which may be what failed): a
/// panic, a fault or the watchdog's report.
pub fn report(line: core::fmt::Arguments<'_>) {
    critical_section::with(|_| {
        let _ = writeln!(Uart, "{line}");
    });
}
