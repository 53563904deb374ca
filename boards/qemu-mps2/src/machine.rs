//! The QEMU machines the board runs on, and the one this image is built for: the addresses,
//! interrupt lines and clock that differ between them (from QEMU's `hw/arm/mps2.c` and
//! `hw/arm/mps2-tz.c`). Everything else (the CMSDK timers, UART and watchdog, the LAN9118)
//! is the same device on each. The build script chooses with the cargo features `an385`,
//! `an386` (the default), `an500` and `an505`, and links with that machine's memory map.

/// One machine's differences.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Machine {
    /// QEMU's name for it (`-M`).
    pub name: &'static str,
    /// Its core.
    pub core: &'static str,
    /// The system clock of the timers, UART and watchdog, in Hz.
    pub clock_hz: u32,
    /// CMSDK APB UART0 (QEMU's first serial port).
    pub uart0: usize,
    /// CMSDK APB timer 0 (the free-running clock) and its interrupt.
    pub timer0: (usize, u16),
    /// CMSDK APB timer 1 (the alarm) and its interrupt.
    pub timer1: (usize, u16),
    /// The CMSDK APB watchdog whose first expiry is the NMI.
    pub watchdog: usize,
    /// The LAN9118 and its interrupt.
    pub lan9118: (usize, u16),
    /// True if the core's MPU is the ARMv8-M one (base/limit regions, no "no access").
    pub armv8m_mpu: bool,
}

/// Cortex-M3, AN385: the AN386 memory map and devices.
pub const AN385: Machine = Machine {
    name: "mps2-an385",
    core: "Cortex-M3",
    ..AN386
};

/// Cortex-M4 with FPU, AN386: code in ZBT SSRAM1 at 0, data in SSRAM2/3 at 0x2000_0000.
pub const AN386: Machine = Machine {
    name: "mps2-an386",
    core: "Cortex-M4",
    clock_hz: 25_000_000,
    uart0: 0x4000_4000,
    timer0: (0x4000_0000, 8),
    timer1: (0x4000_1000, 9),
    watchdog: 0x4000_8000,
    lan9118: (0x4020_0000, 13),
    armv8m_mpu: false,
};

/// Cortex-M7 with FPU, AN500: the AN386 map, but the LAN9118 at 0xA000_0000.
pub const AN500: Machine = Machine {
    name: "mps2-an500",
    core: "Cortex-M7",
    lan9118: (0xA000_0000, 13),
    ..AN386
};

/// Cortex-M33 with FPU, AN505 (the IoTKit subsystem, TrustZone): the core starts and stays
/// in the Secure state, so every device is reached through its Secure alias (address bit 28
/// set); code in SSRAM1 at 0x1000_0000, data in SSRAM2/3 at 0x3800_0000. The IoTKit's own
/// interrupts come first: the FPGA's expansion interrupts (the LAN9118's is 16) start at 32.
pub const AN505: Machine = Machine {
    name: "mps2-an505",
    core: "Cortex-M33",
    clock_hz: 20_000_000,
    uart0: 0x5020_0000,
    timer0: (0x5000_0000, 3),
    timer1: (0x5000_1000, 4),
    watchdog: 0x5008_1000,
    lan9118: (0x5200_0000, 32 + 16),
    armv8m_mpu: true,
};

/// The machine this image is built for.
#[cfg(mps2_machine = "an385")]
pub const THIS: Machine = AN385;
/// The machine this image is built for.
#[cfg(mps2_machine = "an386")]
pub const THIS: Machine = AN386;
/// The machine this image is built for.
#[cfg(mps2_machine = "an500")]
pub const THIS: Machine = AN500;
/// The machine this image is built for.
#[cfg(mps2_machine = "an505")]
pub const THIS: Machine = AN505;

/// The clock in counts per microsecond.
pub const COUNTS_PER_US: u32 = THIS.clock_hz / 1_000_000;
