//! LAN9118 registers (SMSC datasheet, "System Control and Status Registers"): the direct
//! ones, and the MAC and PHY registers reached through them.

use crate::mmio::Block;

/// The controller, at the machine's address.
pub const LAN: Block = Block::at(crate::machine::THIS.lan9118.0);

/// Receive data FIFO port, the first of eight aliases (0x00-0x1C): reading any pops the
/// next word, so one `ldm` reads eight.
pub const RX_DATA: usize = 0x00;
/// Transmit data FIFO port, the first of eight aliases (0x20-0x3C): writing any pushes a
/// word, so one `stm` writes eight.
pub const TX_DATA: usize = 0x20;
/// Receive status FIFO port (pops one status).
pub const RX_STATUS: usize = 0x40;
/// Interrupt configuration.
pub const IRQ_CFG: usize = 0x54;
/// Interrupt status (write 1 to clear).
pub const INT_STS: usize = 0x58;
/// Interrupt enables.
pub const INT_EN: usize = 0x5C;
/// Reads as [`BYTE_TEST_VALUE`].
pub const BYTE_TEST: usize = 0x64;
/// FIFO levels that raise interrupts.
pub const FIFO_INT: usize = 0x68;
/// Transmit configuration.
pub const TX_CFG: usize = 0x70;
/// Hardware configuration.
pub const HW_CFG: usize = 0x74;
/// Receive FIFO fill levels.
pub const RX_FIFO_INF: usize = 0x7C;
/// Transmit FIFO free space.
pub const TX_FIFO_INF: usize = 0x80;
/// Power management (bit 0: ready).
pub const PMT_CTRL: usize = 0x84;
/// Free-running 25 MHz counter.
pub const FREE_RUN: usize = 0x9C;
/// MAC CSR command.
const MAC_CSR_CMD: usize = 0xA4;
/// MAC CSR data.
const MAC_CSR_DATA: usize = 0xA8;

/// What [`BYTE_TEST`] reads on a present, correctly wired controller.
pub const BYTE_TEST_VALUE: u32 = 0x8765_4321;
/// HW_CFG: soft reset (self-clearing).
pub const HW_CFG_SRST: u32 = 1 << 0;
/// PMT_CTRL: the controller is ready after reset.
pub const PMT_READY: u32 = 1 << 0;
/// IRQ_CFG: interrupt output enabled, active high, push-pull.
pub const IRQ_CFG_ENABLED_HIGH: u32 = (1 << 8) | (1 << 4) | (1 << 0);
/// TX_CFG: transmitter on, status FIFO may overrun (statuses are not read).
pub const TX_CFG_ON: u32 = (1 << 1) | (1 << 2);

/// INT_STS/INT_EN: receive status FIFO above its level (a frame arrived).
pub const INT_RSFL: u32 = 1 << 3;
/// INT_STS/INT_EN: transmit data FIFO has room above its level.
pub const INT_TDFA: u32 = 1 << 9;
/// INT_STS/INT_EN: PHY interrupt (link change).
pub const INT_PHY: u32 = 1 << 18;

/// FIFO_INT: "TX data available" level, in 64-byte units (room for one full frame).
pub const FIFO_INT_TX_ROOM: u32 = 24 << 24;
/// RX status word: frame length in bytes, CRC included (bits 29:16).
pub fn rx_status_len(status: u32) -> usize {
    ((status >> 16) & 0x3FFF) as usize
}
/// RX status word: error summary.
pub const RX_STATUS_ERROR: u32 = 1 << 15;
/// RX_FIFO_INF: statuses waiting (bits 23:16).
pub fn rx_statuses(inf: u32) -> u32 {
    (inf >> 16) & 0xFF
}
/// TX_FIFO_INF: free bytes in the data FIFO (bits 15:0).
pub fn tx_free(inf: u32) -> usize {
    (inf & 0xFFFF) as usize
}
/// TX command A: first and last segment of a frame of `len` bytes.
pub fn tx_command_a(len: usize) -> u32 {
    (1 << 13) | (1 << 12) | (len as u32 & 0x7FF)
}
/// TX command B: frame of `len` bytes (also its tag).
pub fn tx_command_b(len: usize) -> u32 {
    ((len as u32 & 0xFFFF) << 16) | (len as u32 & 0x7FF)
}

/// MAC control register.
pub const MAC_CR: u32 = 1;
/// MAC address, bytes 4-5.
pub const MAC_ADDRH: u32 = 2;
/// MAC address, bytes 0-3.
pub const MAC_ADDRL: u32 = 3;
/// MII access (PHY register select).
const MAC_MII_ACC: u32 = 6;
/// MII data.
const MAC_MII_DATA: u32 = 7;
/// MAC_CR: receive and transmit on, full duplex, all multicast accepted (IGMP groups).
pub const MAC_CR_RUN: u32 = (1 << 2) | (1 << 3) | (1 << 19) | (1 << 20);

/// Address of the internal PHY.
const PHY_ADDRESS: u32 = 1;
/// PHY basic control.
pub const PHY_BMCR: u32 = 0;
/// PHY basic status.
pub const PHY_BMSR: u32 = 1;
/// PHY interrupt source (read clears).
pub const PHY_INT_SOURCE: u32 = 29;
/// PHY interrupt mask.
pub const PHY_INT_MASK: u32 = 30;
/// BMCR: auto-negotiation enabled and restarted.
pub const BMCR_AUTONEG: u32 = (1 << 12) | (1 << 9);
/// BMSR: link up.
pub const BMSR_LINK: u32 = 1 << 2;
/// PHY interrupts for link changes: link down, auto-negotiation complete, energy on.
pub const PHY_LINK_EVENTS: u32 = (1 << 4) | (1 << 6) | (1 << 7);

/// Polls of a busy flag before giving up (the controller answers in microseconds).
const BUSY_SPINS: u32 = 10_000;
/// Busy flag of MAC_CSR_CMD and of MII_ACC.
const BUSY: u32 = 1 << 31;
const MII_BUSY: u32 = 1 << 0;

fn wait_not_busy(read: impl Fn() -> u32, busy: u32) {
    let mut spins = 0;
    while read() & busy != 0 && spins < BUSY_SPINS {
        spins += 1;
    }
}

/// Reads MAC register `reg`.
pub fn mac_read(reg: u32) -> u32 {
    LAN.write(MAC_CSR_CMD, BUSY | (1 << 30) | reg);
    wait_not_busy(|| LAN.read(MAC_CSR_CMD), BUSY);
    LAN.read(MAC_CSR_DATA)
}

/// Writes `value` to MAC register `reg`.
pub fn mac_write(reg: u32, value: u32) {
    LAN.write(MAC_CSR_DATA, value);
    LAN.write(MAC_CSR_CMD, BUSY | reg);
    wait_not_busy(|| LAN.read(MAC_CSR_CMD), BUSY);
}

/// Reads PHY register `reg`.
pub fn phy_read(reg: u32) -> u32 {
    mac_write(MAC_MII_ACC, (PHY_ADDRESS << 11) | (reg << 6) | MII_BUSY);
    wait_not_busy(|| mac_read(MAC_MII_ACC), MII_BUSY);
    mac_read(MAC_MII_DATA) & 0xFFFF
}

/// Writes `value` to PHY register `reg`.
pub fn phy_write(reg: u32, value: u32) {
    mac_write(MAC_MII_DATA, value);
    mac_write(
        MAC_MII_ACC,
        (PHY_ADDRESS << 11) | (reg << 6) | (1 << 1) | MII_BUSY,
    );
    wait_not_busy(|| mac_read(MAC_MII_ACC), MII_BUSY);
}
