//! [`NetDriver`]: the embassy-net driver the network stack gets instead of the board's. Its
//! frames are the ones the link task passed on (everything but Class 1 I/O), its sends go to
//! the link task, which owns the board's driver.

use core::task::Context;

use embassy_net_driver::{
    Capabilities, Checksum, Driver, HardwareAddress, LinkState, RxToken, TxToken,
};

use super::frames::LinkFrames;
use super::stack_sums::LinkChecksums;

/// The network stack's side of [`LinkFrames`], with the board driver's address and
/// capabilities.
pub struct NetDriver<'a> {
    frames: &'a LinkFrames,
    capabilities: Capabilities,
    address: HardwareAddress,
}

impl<'a> NetDriver<'a> {
    /// The driver for `embassy_net::new`, passing frames through `frames` to the link task
    /// that owns `board` (whose address and capabilities it reports).
    pub fn new(frames: &'a LinkFrames, board: &impl Driver) -> Self {
        NetDriver {
            frames,
            capabilities: board.capabilities(),
            address: board.hardware_address(),
        }
    }

    /// Like [`Self::new`], but the stack is told the hardware does its checksums: the link
    /// task verifies and fills those `board` leaves to software in its place, 16 bytes a
    /// step rather than smoltcp's 2, once run with the proof returned here
    /// ([`super::run_with_link_checksums`], `link/stack_sums.rs`). About 400 bytes of
    /// flash more: for a board that has them to spare.
    pub fn with_link_checksums(
        frames: &'a LinkFrames,
        board: &impl Driver,
    ) -> (Self, LinkChecksums) {
        let mut driver = Self::new(frames, board);
        let sums = &mut driver.capabilities.checksum;
        sums.ipv4 = Checksum::None;
        sums.udp = Checksum::None;
        sums.tcp = Checksum::None;
        sums.icmpv4 = Checksum::None;
        (driver, LinkChecksums(()))
    }
}

impl Driver for NetDriver<'_> {
    type RxToken<'a>
        = Received<'a>
    where
        Self: 'a;
    type TxToken<'a>
        = Send<'a>
    where
        Self: 'a;

    fn receive(&mut self, cx: &mut Context<'_>) -> Option<(Received<'_>, Send<'_>)> {
        let f = self.frames;
        if f.rx.is_empty() || f.tx.is_full() {
            f.register_stack(cx.waker());
            return None;
        }
        Some((Received { frames: f }, Send { frames: f }))
    }

    fn transmit(&mut self, cx: &mut Context<'_>) -> Option<Send<'_>> {
        let f = self.frames;
        if f.tx.is_full() {
            f.register_stack(cx.waker());
            return None;
        }
        Some(Send { frames: f })
    }

    fn link_state(&mut self, cx: &mut Context<'_>) -> LinkState {
        self.frames.register_stack(cx.waker());
        self.frames.link_state()
    }

    fn capabilities(&self) -> Capabilities {
        self.capabilities.clone()
    }

    fn hardware_address(&self) -> HardwareAddress {
        self.address
    }
}

/// The oldest frame the link task passed on.
pub struct Received<'a> {
    frames: &'a LinkFrames,
}

impl RxToken for Received<'_> {
    fn consume<R, F: FnOnce(&mut [u8]) -> R>(self, f: F) -> R {
        let r = self.frames.rx.pop(f);
        self.frames.stack_took();
        // The token exists only while a frame waits, and nothing else takes it meanwhile:
        // the empty frame is never handed over.
        r.unwrap_or_else(|f| f(&mut []))
    }
}

/// Room for one frame to send.
pub struct Send<'a> {
    frames: &'a LinkFrames,
}

impl TxToken for Send<'_> {
    fn consume<R, F: FnOnce(&mut [u8]) -> R>(self, len: usize, f: F) -> R {
        let r = self.frames.tx.push(len, f);
        self.frames.wake_link();
        // Room was there when the token was made, and only this token fills it (the stack
        // holds one token at a time): the empty buffer is never handed over.
        r.unwrap_or_else(|f| f(&mut []))
    }
}
