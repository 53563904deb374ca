//! An in-memory Ethernet segment with two ports: frames queued per receiving port.

use super::*;
use embassy_net::driver::{self, Capabilities, HardwareAddress, LinkState};

/// Frames a port may have waiting before the wire drops more, as a busy PHY would.
const QUEUE_LIMIT: usize = 64;

#[derive(Default)]
struct Segment {
    /// Frames waiting to be received by port 0 and port 1.
    queues: [VecDeque<Vec<u8>>; 2],
    /// The receiving runner of each port, woken when a frame arrives for it.
    wakers: [Option<Waker>; 2],
}

/// One end of the segment, usable as an embassy-net driver.
pub struct Port {
    segment: Rc<RefCell<Segment>>,
    side: usize,
    mac: [u8; 6],
}

thread_local! {
    /// The segment [`pair`] made last on this thread (each test runs on its own).
    static LAST: RefCell<Option<Rc<RefCell<Segment>>>> = const { RefCell::new(None) };
}

/// Queues `frame` for port 0 of the segment made last on this thread, as if another
/// station on the wire had sent it.
pub fn inject_to_port_0(frame: Vec<u8>) {
    LAST.with_borrow(|last| {
        let segment = last.as_ref().expect("a segment");
        let mut seg = segment.borrow_mut();
        seg.queues[0].push_back(frame);
        if let Some(w) = seg.wakers[0].take() {
            w.wake();
        }
    });
}

/// A fresh segment's two ports, with these MAC addresses.
pub fn pair(mac0: [u8; 6], mac1: [u8; 6]) -> (Port, Port) {
    let segment = Rc::new(RefCell::new(Segment::default()));
    LAST.with_borrow_mut(|last| *last = Some(segment.clone()));
    let port = |side, mac| Port {
        segment: segment.clone(),
        side,
        mac,
    };
    (port(0, mac0), port(1, mac1))
}

pub struct RxToken(Vec<u8>);

pub struct TxToken {
    segment: Rc<RefCell<Segment>>,
    to: usize,
}

impl driver::Driver for Port {
    type RxToken<'a> = RxToken;
    type TxToken<'a> = TxToken;

    fn receive(&mut self, cx: &mut Context) -> Option<(RxToken, TxToken)> {
        let mut seg = self.segment.borrow_mut();
        match seg.queues[self.side].pop_front() {
            Some(frame) => {
                drop(seg);
                Some((RxToken(frame), self.tx()))
            }
            None => {
                seg.wakers[self.side] = Some(cx.waker().clone());
                None
            }
        }
    }

    fn transmit(&mut self, _cx: &mut Context) -> Option<TxToken> {
        Some(self.tx())
    }

    fn link_state(&mut self, _cx: &mut Context) -> LinkState {
        LinkState::Up
    }

    fn capabilities(&self) -> Capabilities {
        let mut caps = Capabilities::default();
        caps.max_transmission_unit = 1514;
        caps
    }

    fn hardware_address(&self) -> HardwareAddress {
        HardwareAddress::Ethernet(self.mac)
    }
}

impl Port {
    fn tx(&self) -> TxToken {
        TxToken {
            segment: self.segment.clone(),
            to: 1 - self.side,
        }
    }
}

impl driver::RxToken for RxToken {
    fn consume<R, F: FnOnce(&mut [u8]) -> R>(mut self, f: F) -> R {
        f(&mut self.0)
    }
}

impl driver::TxToken for TxToken {
    fn consume<R, F: FnOnce(&mut [u8]) -> R>(self, len: usize, f: F) -> R {
        let mut frame = vec![0; len];
        let r = f(&mut frame);
        let mut seg = self.segment.borrow_mut();
        if seg.queues[self.to].len() < QUEUE_LIMIT {
            seg.queues[self.to].push_back(frame);
        }
        if let Some(w) = seg.wakers[self.to].take() {
            w.wake();
        }
        r
    }
}
