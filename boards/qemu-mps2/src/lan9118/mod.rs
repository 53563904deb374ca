//! A LAN9118 Ethernet driver for embassy-net, interrupt-driven.
//!
//! The controller keeps received frames in its own FIFO and announces each with an entry in
//! the receive status FIFO; the "RX status FIFO level" interrupt (level 0) fires for every
//! frame. The interrupt handler acknowledges and wakes the network runner, which then pops
//! frames in [`Driver::receive`]. Transmission writes a frame straight into the transmit
//! FIFO; when it lacks room, the "TX data available" interrupt wakes the runner. Link
//! changes come from the PHY interrupt.

mod regs;

use core::sync::atomic::{AtomicBool, Ordering};
use core::task::{Context, Waker};

use embassy_net_driver::{Capabilities, Driver, HardwareAddress, LinkState, RxToken, TxToken};
use embassy_sync::waitqueue::AtomicWaker;

use crate::irq::{self, Irq};
use regs::*;

/// Largest Ethernet frame handled (no VLAN tag), without the CRC.
const MTU: usize = 1514;
/// Receive buffer: a frame with its CRC, rounded up to whole FIFO words.
const RX_BUF: usize = (MTU + 4 + 3) & !3;
/// Transmit FIFO room needed for one frame: two command words and the data words.
const TX_ROOM: usize = 8 + TX_BUF;
/// Transmit buffer: a frame rounded up to whole FIFO words (the bytes past its end in the
/// last word are sent to the controller, which leaves them out).
const TX_BUF: usize = (MTU + 3) & !3;
/// Polls of PMT_CTRL after a soft reset before giving up.
const RESET_SPINS: u32 = 100_000;
/// The address used when the controller's EEPROM holds none (locally administered).
const FALLBACK_MAC: [u8; 6] = [0x02, 0x45, 0x4E, 0x49, 0x50, 0x02];

/// The runner waiting for a received frame or transmit room.
static WAKER: AtomicWaker = AtomicWaker::new();
/// The PHY reported a link event not yet read.
static LINK_EVENT: AtomicBool = AtomicBool::new(true);

/// Why the controller could not be brought up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Error {
    /// BYTE_TEST did not read back its fixed value: no controller at the address.
    NotFound,
    /// The controller did not come out of its soft reset.
    ResetTimeout,
}

/// The LAN9118 of the machine, with one frame buffer in each direction. Both buffers start
/// word-aligned (`RX_BUF` is a multiple of 4), as the link task's frame queues do: the
/// copies between them run a word at a time.
#[repr(C, align(4))]
pub struct Lan9118 {
    rx: [u8; RX_BUF],
    tx: [u8; TX_BUF],
    mac: [u8; 6],
    link_up: bool,
    /// The waker last registered in [`WAKER`]: [`AtomicWaker::wake`] keeps it, so the same
    /// task's waker is not registered again (a critical section saved per call).
    registered: Option<Waker>,
}

impl Lan9118 {
    /// Resets the controller, reads its MAC address (QEMU loads the `-nic` one), starts
    /// reception and transmission, and enables its interrupt.
    pub fn new() -> Result<Self, Error> {
        if LAN.read(BYTE_TEST) != BYTE_TEST_VALUE {
            return Err(Error::NotFound);
        }
        LAN.write(HW_CFG, HW_CFG_SRST);
        let mut spins = 0;
        while LAN.read(PMT_CTRL) & PMT_READY == 0 || LAN.read(HW_CFG) & HW_CFG_SRST != 0 {
            spins += 1;
            if spins > RESET_SPINS {
                return Err(Error::ResetTimeout);
            }
        }
        let mac = read_mac().unwrap_or_else(|| {
            write_mac(FALLBACK_MAC);
            FALLBACK_MAC
        });
        phy_write(PHY_INT_MASK, PHY_LINK_EVENTS);
        phy_write(PHY_BMCR, BMCR_AUTONEG);
        LAN.write(FIFO_INT, FIFO_INT_TX_ROOM);
        LAN.write(INT_STS, u32::MAX);
        LAN.write(INT_EN, INT_RSFL | INT_PHY);
        LAN.write(IRQ_CFG, IRQ_CFG_ENABLED_HIGH);
        LAN.write(TX_CFG, TX_CFG_ON);
        mac_write(MAC_CR, MAC_CR_RUN);
        irq::enable(Irq::Ethernet);
        Ok(Lan9118 {
            mac,
            link_up: false,
            registered: None,
            rx: [0; RX_BUF],
            tx: [0; TX_BUF],
        })
    }

    /// The controller's MAC address.
    pub fn mac(&self) -> [u8; 6] {
        self.mac
    }

    /// A free-running 25 MHz count since reset (some entropy for seeds).
    pub fn free_running_count() -> u32 {
        LAN.read(FREE_RUN)
    }

    /// Pops the next good frame into `rx`; its length without the CRC.
    fn pop_frame(&mut self) -> Option<usize> {
        // Bounded by the frames waiting now; bad or oversized ones are drained and skipped.
        for _ in 0..rx_statuses(LAN.read(RX_FIFO_INF)) {
            let status = LAN.read(RX_STATUS);
            let len = rx_status_len(status);
            let words = len.div_ceil(4);
            if status & RX_STATUS_ERROR != 0 || len <= 4 || len > RX_BUF {
                for _ in 0..words {
                    LAN.read(RX_DATA);
                }
                continue;
            }
            // Whole bursts of eight words through the port's aliases, then the rest a word
            // at a time.
            let whole = &mut self.rx[..words * 4];
            let read = LAN.read_bursts(RX_DATA, whole);
            for word in whole[read..].as_chunks_mut::<4>().0 {
                *word = LAN.read(RX_DATA).to_le_bytes();
            }
            return Some(len - 4);
        }
        None
    }

    /// True if the transmit FIFO has room for a full frame; otherwise asks for the
    /// interrupt that says when it has.
    fn tx_ready(&self) -> bool {
        if tx_free(LAN.read(TX_FIFO_INF)) >= TX_ROOM {
            return true;
        }
        critical_section::with(|_| LAN.write(INT_EN, LAN.read(INT_EN) | INT_TDFA));
        // Room may have appeared before the interrupt was enabled.
        tx_free(LAN.read(TX_FIFO_INF)) >= TX_ROOM
    }
}

/// True if the receive status FIFO announces a frame.
fn frame_waiting() -> bool {
    rx_statuses(LAN.read(RX_FIFO_INF)) > 0
}

fn read_mac() -> Option<[u8; 6]> {
    let low = mac_read(MAC_ADDRL).to_le_bytes();
    let high = mac_read(MAC_ADDRH).to_le_bytes();
    let mac = [low[0], low[1], low[2], low[3], high[0], high[1]];
    let usable = mac != [0; 6] && mac != [0xFF; 6] && mac[0] & 1 == 0;
    usable.then_some(mac)
}

fn write_mac(mac: [u8; 6]) {
    mac_write(
        MAC_ADDRL,
        u32::from_le_bytes([mac[0], mac[1], mac[2], mac[3]]),
    );
    mac_write(MAC_ADDRH, u32::from_le_bytes([mac[4], mac[5], 0, 0]));
}

/// The controller's interrupt: acknowledge what fired and wake the runner.
pub fn on_interrupt() {
    let enabled = LAN.read(INT_EN);
    let fired = LAN.read(INT_STS) & enabled;
    LAN.write(INT_STS, fired);
    // Level-type sources stay masked until the runner has served them.
    LAN.write(INT_EN, enabled & !(fired & (INT_TDFA | INT_PHY)));
    if fired & INT_PHY != 0 {
        LINK_EVENT.store(true, Ordering::Release);
    }
    WAKER.wake();
}

impl Lan9118 {
    /// Registers `waker` for the next interrupt, unless it is registered already (inline:
    /// the usual case is two comparisons).
    #[inline(always)]
    fn register(&mut self, waker: &Waker) {
        if !self.registered.as_ref().is_some_and(|w| w.will_wake(waker)) {
            self.register_anew(waker);
        }
    }

    /// [`Self::register`]'s rare case, out of line.
    #[inline(never)]
    fn register_anew(&mut self, waker: &Waker) {
        WAKER.register(waker);
        self.registered = Some(waker.clone());
    }
}

impl Driver for Lan9118 {
    type RxToken<'a> = Rx<'a>;
    type TxToken<'a> = Tx<'a>;

    fn receive(&mut self, cx: &mut Context<'_>) -> Option<(Rx<'_>, Tx<'_>)> {
        // Whether a frame waits is one register read, the common answer "no" no more. The
        // waker is registered only when there is nothing to return, before looking again:
        // a frame (or transmit room) that comes in between still wakes the task.
        if !frame_waiting() {
            self.register(cx.waker());
            if !frame_waiting() {
                return None;
            }
        }
        let len = match self.tx_ready().then(|| self.pop_frame()).flatten() {
            Some(len) => len,
            None => {
                self.register(cx.waker());
                self.tx_ready().then(|| self.pop_frame()).flatten()?
            }
        };
        Some((
            Rx {
                frame: &mut self.rx[..len],
            },
            Tx { buf: &mut self.tx },
        ))
    }

    fn transmit(&mut self, cx: &mut Context<'_>) -> Option<Tx<'_>> {
        if !self.tx_ready() {
            self.register(cx.waker());
            if !self.tx_ready() {
                return None;
            }
        }
        Some(Tx { buf: &mut self.tx })
    }

    fn link_state(&mut self, cx: &mut Context<'_>) -> LinkState {
        self.register(cx.waker());
        if LINK_EVENT.swap(false, Ordering::Acquire) {
            phy_read(PHY_INT_SOURCE);
            self.link_up = phy_read(PHY_BMSR) & BMSR_LINK != 0;
            critical_section::with(|_| LAN.write(INT_EN, LAN.read(INT_EN) | INT_PHY));
        }
        if self.link_up {
            LinkState::Up
        } else {
            LinkState::Down
        }
    }

    fn capabilities(&self) -> Capabilities {
        let mut caps = Capabilities::default();
        caps.max_transmission_unit = MTU;
        caps
    }

    fn hardware_address(&self) -> HardwareAddress {
        HardwareAddress::Ethernet(self.mac)
    }
}

/// A received frame, already out of the controller.
pub struct Rx<'a> {
    frame: &'a mut [u8],
}

impl RxToken for Rx<'_> {
    fn consume<R, F: FnOnce(&mut [u8]) -> R>(self, f: F) -> R {
        f(self.frame)
    }
}

/// Room for one frame, written into the transmit FIFO when consumed.
pub struct Tx<'a> {
    buf: &'a mut [u8; TX_BUF],
}

impl TxToken for Tx<'_> {
    fn consume<R, F: FnOnce(&mut [u8]) -> R>(self, len: usize, f: F) -> R {
        let len = len.min(MTU);
        let result = f(&mut self.buf[..len]);
        push_frame(self.buf, len);
        result
    }
}

/// Writes the first `len` bytes of `buf` into the transmit FIFO behind its two command
/// words: the frame is handed to the controller. Never inlined: `cargo xtask bench --qemu`
/// takes its entry as the moment a T->O frame reaches the driver.
#[inline(never)]
fn push_frame(buf: &[u8; TX_BUF], len: usize) {
    LAN.write(TX_DATA, tx_command_a(len));
    LAN.write(TX_DATA, tx_command_b(len));
    // Whole words (the last one's bytes past `len` are left out by the controller): bursts
    // of eight through the port's aliases, then the rest a word at a time.
    let words = &buf[..len.div_ceil(4) * 4];
    let written = LAN.write_bursts(TX_DATA, words);
    for word in words[written..].as_chunks::<4>().0 {
        LAN.write(TX_DATA, u32::from_le_bytes(*word));
    }
}
