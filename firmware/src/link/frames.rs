//! [`LinkFrames`]: the frames the link task and the embassy-net stack hand each other (every
//! frame that is not Class 1 I/O), the wake-ups between them, and the link state.
//!
//! Not `embassy-net-driver-channel`: its `Device` reports fixed, MTU-only `Capabilities`, so
//! the board driver's checksum offload and burst size, which [`super::NetDriver`] passes on
//! to embassy-net, would be lost (and its state wants a `&'static mut`, this a `const` value).

use core::cell::{Cell, RefCell};
use core::task::Waker;

use embassy_net_driver::LinkState;
use embassy_sync::waitqueue::WakerRegistration;

use super::KeptWaker;

/// The largest Ethernet frame without its CRC: 1 500 bytes of payload and the header.
pub const FRAME_LEN: usize = 1514;
/// Received frames waiting for the network stack.
pub const RX_FRAMES: usize = 2;
/// Frames of the network stack waiting for the link task to send them.
pub const TX_FRAMES: usize = 2;

/// One frame and its length.
pub(crate) struct Frame {
    len: usize,
    data: [u8; FRAME_LEN],
}

impl Frame {
    const fn empty() -> RefCell<Frame> {
        RefCell::new(Frame {
            len: 0,
            data: [0; FRAME_LEN],
        })
    }

    /// Room for a frame of `len` bytes (at most [`FRAME_LEN`]), now its bytes.
    pub fn fill(&mut self, len: usize) -> &mut [u8] {
        self.len = len.min(FRAME_LEN);
        self.bytes()
    }

    /// The frame's bytes.
    pub fn bytes(&mut self) -> &mut [u8] {
        self.data.get_mut(..self.len).unwrap_or(&mut [])
    }
}

/// A queue of `N` frames in place: the oldest at `head`, `len` of them.
pub(crate) struct Queue<const N: usize> {
    frames: [RefCell<Frame>; N],
    head: Cell<usize>,
    len: Cell<usize>,
}

impl<const N: usize> Queue<N> {
    const fn new() -> Self {
        Queue {
            frames: [const { Frame::empty() }; N],
            head: Cell::new(0),
            len: Cell::new(0),
        }
    }

    /// True if no frame is waiting.
    pub fn is_empty(&self) -> bool {
        self.len.get() == 0
    }

    /// True if no room is left.
    pub fn is_full(&self) -> bool {
        self.len.get() >= N
    }

    /// Appends a frame written by `write` into room for `len` bytes; gives `write` back if
    /// the queue is full.
    pub fn push<R, W: FnOnce(&mut [u8]) -> R>(&self, len: usize, write: W) -> Result<R, W> {
        let at = self.head.get().wrapping_add(self.len.get()).checked_rem(N);
        let frame = at.and_then(|at| self.frames.get(at));
        let Some(frame) = frame.filter(|_| !self.is_full()) else {
            return Err(write);
        };
        let r = write(frame.borrow_mut().fill(len));
        self.len.set(self.len.get().saturating_add(1));
        Ok(r)
    }

    /// Hands the oldest frame to `read`, then removes it; gives `read` back if the queue is
    /// empty. The frame is borrowed only during `read`, which may push to another queue.
    pub fn pop<R, F: FnOnce(&mut [u8]) -> R>(&self, read: F) -> Result<R, F> {
        let at = self.head.get();
        let Some(frame) = self.frames.get(at).filter(|_| !self.is_empty()) else {
            return Err(read);
        };
        let r = read(frame.borrow_mut().bytes());
        self.head
            .set(at.wrapping_add(1).checked_rem(N).unwrap_or(0));
        self.len.set(self.len.get().saturating_sub(1));
        Ok(r)
    }

    /// Removes the frame pushed last.
    pub fn drop_last(&self) {
        self.len.set(self.len.get().saturating_sub(1));
    }
}

/// The frames between the link task and the network stack; create one with
/// [`LinkFrames::new`] in a `static` cell and give it to [`super::NetDriver::new`] and
/// [`super::run`].
pub struct LinkFrames {
    /// Received frames for the network stack.
    pub(crate) rx: Queue<RX_FRAMES>,
    /// The network stack's frames to send.
    pub(crate) tx: Queue<TX_FRAMES>,
    /// Wakes the network stack's runner: a frame came, room to send appeared in a queue the
    /// runner had found full, the link state changed.
    stack: RefCell<WakerRegistration>,
    /// Wakes the link task: the stack queued a frame, or took one from a full queue.
    link: KeptWaker,
    link_state: Cell<LinkState>,
}

impl LinkFrames {
    /// Empty queues, link down (a `const fn`, so a board can place them in `.bss`).
    pub const fn new() -> Self {
        LinkFrames {
            rx: Queue::new(),
            tx: Queue::new(),
            stack: RefCell::new(WakerRegistration::new()),
            link: KeptWaker::new(),
            link_state: Cell::new(LinkState::Down),
        }
    }

    /// The stack's runner waits for [`Self::wake_stack`].
    pub(crate) fn register_stack(&self, waker: &Waker) {
        self.stack.borrow_mut().register(waker);
    }

    /// Wakes the stack's runner.
    pub(crate) fn wake_stack(&self) {
        self.stack.borrow_mut().wake();
    }

    /// The link task waits for [`Self::wake_link`] (registered once: it is kept).
    pub(crate) fn register_link(&self, waker: &Waker) {
        self.link.register(waker);
    }

    /// The stack took a received frame: wakes the link task if the queue had been full (one
    /// slot free now), the only time the link task waits for the stack to take one
    /// (`Pump::receive`); a queue with room left never stopped it. Out of line: the stack
    /// inlines its receive tokens at each of their uses.
    #[inline(never)]
    pub(crate) fn stack_took(&self) {
        if self.rx.len.get() == RX_FRAMES.saturating_sub(1) {
            self.wake_link();
        }
    }

    /// Wakes the link task.
    pub(crate) fn wake_link(&self) {
        self.link.wake();
    }

    /// The link state the driver last reported.
    pub(crate) fn link_state(&self) -> LinkState {
        self.link_state.get()
    }

    /// Records the driver's link state; wakes the stack's runner when it changed.
    pub(crate) fn set_link_state(&self, state: LinkState) {
        if self.link_state.replace(state) != state {
            self.wake_stack();
        }
    }
}

impl Default for LinkFrames {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::vec;

    #[test]
    fn queue_is_first_in_first_out_and_bounded() {
        let q: Queue<2> = Queue::new();
        assert!(q.pop(|f| f.len()).is_err());
        assert!(q.push(3, |f| f.copy_from_slice(&[1, 2, 3])).is_ok());
        assert!(q.push(2, |f| f.copy_from_slice(&[4, 5])).is_ok());
        assert!(q.is_full());
        assert!(q.push(1, |_| ()).is_err());
        assert_eq!(q.pop(|f| f.to_vec()).ok(), Some(vec![1, 2, 3]));
        assert_eq!(q.push(FRAME_LEN + 10, |f| f.len()).ok(), Some(FRAME_LEN));
        assert_eq!(q.pop(|f| f.to_vec()).ok(), Some(vec![4, 5]));
        assert_eq!(q.pop(|f| f.len()).ok(), Some(FRAME_LEN));
        assert!(q.is_empty());
    }

    #[test]
    fn the_frame_pushed_last_can_be_dropped() {
        let q: Queue<2> = Queue::new();
        assert!(q.push(1, |f| f.copy_from_slice(&[1])).is_ok());
        assert!(q.push(1, |f| f.copy_from_slice(&[2])).is_ok());
        q.drop_last();
        assert!(q.push(1, |f| f.copy_from_slice(&[3])).is_ok());
        assert_eq!(q.pop(|f| f.to_vec()).ok(), Some(vec![1]));
        assert_eq!(q.pop(|f| f.to_vec()).ok(), Some(vec![3]));
        assert!(q.is_empty());
    }
}
