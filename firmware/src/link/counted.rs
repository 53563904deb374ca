//! [`Counted`]: the board's driver as the link task uses it, counting every frame it receives
//! and sends for the Ethernet Link object (attributes 4 and 5). Counting at the driver catches
//! every frame whoever in the link task reads or writes it (Class 1, the network stack's, ARP,
//! the layer-2 services). Each frame costs a few additions and no lock: the link task hands
//! the counts to the adapter ([`Counted::hand_over`]) only at the end of a wake-up that leaves a
//! frame for the network stack. Any request that reads them comes in such a frame, so it
//! finds every frame up to its own counted, and a Class 1 cycle (its frames never go to the
//! network stack) pays nothing more.

use core::cell::RefCell;
use core::task::Context;

use embassy_net_driver::{Capabilities, Driver, HardwareAddress, LinkState, RxToken, TxToken};
use enip_stack::objects::LinkCounters;

/// A driver whose frames are counted. It borrows the board's driver rather than owning it:
/// moved into the link task's future beside the task's own argument, a driver holding its
/// buffers (the LAN9118's) would take their room twice.
pub(crate) struct Counted<'d, D> {
    inner: &'d mut D,
    mac: [u8; 6],
    counts: RefCell<LinkCounters>,
}

impl<'d, D: Driver> Counted<'d, D> {
    /// Counts the frames of `inner`, the station `mac`.
    pub fn new(inner: &'d mut D, mac: [u8; 6]) -> Self {
        Counted {
            inner,
            mac,
            counts: RefCell::new(LinkCounters::new()),
        }
    }

    /// Hands what was counted since the last call to `f`, where it lies (not copied out),
    /// and counts anew from zero.
    pub fn hand_over(&self, f: impl FnOnce(&LinkCounters)) {
        let mut counts = self.counts.borrow_mut();
        f(&counts);
        *counts = LinkCounters::new();
    }
}

impl<D: Driver> Driver for Counted<'_, D> {
    type RxToken<'a>
        = Rx<'a, D::RxToken<'a>>
    where
        Self: 'a;
    type TxToken<'a>
        = Tx<'a, D::TxToken<'a>>
    where
        Self: 'a;

    fn receive(&mut self, cx: &mut Context<'_>) -> Option<(Self::RxToken<'_>, Self::TxToken<'_>)> {
        let Counted { inner, mac, counts } = self;
        let (rx, tx) = inner.receive(cx)?;
        Some((Rx { rx, mac, counts }, Tx { tx, counts }))
    }

    fn transmit(&mut self, cx: &mut Context<'_>) -> Option<Self::TxToken<'_>> {
        let Counted { inner, counts, .. } = self;
        inner.transmit(cx).map(|tx| Tx { tx, counts })
    }

    fn link_state(&mut self, cx: &mut Context<'_>) -> LinkState {
        self.inner.link_state(cx)
    }

    fn capabilities(&self) -> Capabilities {
        self.inner.capabilities()
    }

    fn hardware_address(&self) -> HardwareAddress {
        self.inner.hardware_address()
    }
}

/// A received frame, counted once read (after its O->T data reached the device: counting is
/// not on the way there).
pub(crate) struct Rx<'a, T> {
    rx: T,
    mac: &'a [u8; 6],
    counts: &'a RefCell<LinkCounters>,
}

impl<T: RxToken> RxToken for Rx<'_, T> {
    fn consume<R, F: FnOnce(&mut [u8]) -> R>(self, f: F) -> R {
        let Rx { rx, mac, counts } = self;
        rx.consume(|frame| {
            let r = f(frame);
            counts.borrow_mut().received(frame, mac);
            r
        })
    }
}

/// Room for a frame to send, counted once written.
pub(crate) struct Tx<'a, T> {
    tx: T,
    counts: &'a RefCell<LinkCounters>,
}

impl<T: TxToken> TxToken for Tx<'_, T> {
    fn consume<R, F: FnOnce(&mut [u8]) -> R>(self, len: usize, f: F) -> R {
        let Tx { tx, counts } = self;
        tx.consume(len, |frame| {
            let r = f(frame);
            counts.borrow_mut().sent(frame);
            r
        })
    }
}
