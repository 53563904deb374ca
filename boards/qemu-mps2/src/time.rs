//! The embassy-time driver of the machine: two CMSDK APB timers clocked at 25 MHz, giving
//! a 1 MHz time base (one tick = 25 timer counts).
//!
//! - Timer 0 counts down from `u32::MAX` forever; its wrap interrupt (every 171.8 s) counts
//!   periods, which extends it to 64 bits.
//! - Timer 1 is the alarm: loaded with the counts until the earliest timer of the queue, it
//!   interrupts once and is stopped.

use core::cell::{Cell, RefCell};
use core::task::Waker;

use critical_section::{CriticalSection, Mutex};
use embassy_time_driver::Driver;
use embassy_time_queue_utils::Queue;

use crate::irq::{self, Irq};
use crate::mmio::Block;

/// Timer counts per microsecond (the timers run at the 25 MHz system clock).
const COUNTS_PER_US: u64 = 25;

/// CMSDK APB timer registers.
mod reg {
    pub const CTRL: usize = 0x00;
    pub const VALUE: usize = 0x04;
    pub const RELOAD: usize = 0x08;
    pub const INTSTATUS: usize = 0x0C;
    /// CTRL: count.
    pub const EN: u32 = 1 << 0;
    /// CTRL: interrupt when the count reaches zero.
    pub const IRQEN: u32 = 1 << 3;
    /// INTSTATUS: the count reached zero (write 1 to clear).
    pub const IRQ: u32 = 1 << 0;
}

/// The free-running timer.
const CLOCK: Block = Block::at(0x4000_0000);
/// The alarm timer.
const ALARM: Block = Block::at(0x4000_1000);

/// The time driver: wrap count and timer queue, shared with the interrupt handlers.
struct Mps2Time {
    periods: Mutex<Cell<u64>>,
    queue: Mutex<RefCell<Queue>>,
}

embassy_time_driver::time_driver_impl!(static DRIVER: Mps2Time = Mps2Time {
    periods: Mutex::new(Cell::new(0)),
    queue: Mutex::new(RefCell::new(Queue::new())),
});

/// Starts the clock and enables both timer interrupts; call once, first thing in `main`.
pub fn init() {
    ALARM.write(reg::CTRL, 0);
    ALARM.write(reg::INTSTATUS, reg::IRQ);
    CLOCK.write(reg::CTRL, 0);
    CLOCK.write(reg::INTSTATUS, reg::IRQ);
    CLOCK.write(reg::RELOAD, u32::MAX);
    CLOCK.write(reg::CTRL, reg::EN | reg::IRQEN);
    irq::enable(Irq::Timer0);
    irq::enable(Irq::Timer1);
}

impl Mps2Time {
    /// Timer counts since [`init`], in a critical section so a pending wrap is seen.
    fn counts(&self, cs: CriticalSection<'_>) -> u64 {
        let periods = self.periods.borrow(cs).get();
        let value = CLOCK.read(reg::VALUE);
        // A wrap the handler has not counted yet: re-read, the value is after it.
        let (periods, value) = if CLOCK.read(reg::INTSTATUS) & reg::IRQ != 0 {
            (periods + 1, CLOCK.read(reg::VALUE))
        } else {
            (periods, value)
        };
        (periods << 32) + u64::from(u32::MAX - value)
    }

    fn now_in(&self, cs: CriticalSection<'_>) -> u64 {
        self.counts(cs) / COUNTS_PER_US
    }

    /// Arms the alarm for tick `at`; false if `at` is already due (nothing armed).
    fn arm(&self, cs: CriticalSection<'_>, at: u64) -> bool {
        ALARM.write(reg::CTRL, 0);
        ALARM.write(reg::INTSTATUS, reg::IRQ);
        if at == u64::MAX {
            return true;
        }
        let now = self.now_in(cs);
        if at <= now {
            return false;
        }
        // A far deadline fires early, and the queue re-arms for the rest.
        let counts = (at - now)
            .saturating_mul(COUNTS_PER_US)
            .min(u64::from(u32::MAX));
        ALARM.write(reg::RELOAD, counts as u32);
        ALARM.write(reg::CTRL, reg::EN | reg::IRQEN);
        true
    }

    /// Wakes every expired timer and arms the alarm for the next one.
    fn dispatch(&self, cs: CriticalSection<'_>) {
        let mut queue = self.queue.borrow_ref_mut(cs);
        // Bounded: each round wakes the timers that expired, and time moves forward.
        let mut next = queue.next_expiration(self.now_in(cs));
        while !self.arm(cs, next) {
            next = queue.next_expiration(self.now_in(cs));
        }
    }
}

impl Driver for Mps2Time {
    fn now(&self) -> u64 {
        critical_section::with(|cs| self.now_in(cs))
    }

    fn schedule_wake(&self, at: u64, waker: &Waker) {
        critical_section::with(|cs| {
            let changed = self.queue.borrow_ref_mut(cs).schedule_wake(at, waker);
            if changed {
                self.dispatch(cs);
            }
        })
    }
}

/// Timer 0 wrapped: one more period of 2^32 counts.
pub fn on_wrap_interrupt() {
    critical_section::with(|cs| {
        if CLOCK.read(reg::INTSTATUS) & reg::IRQ != 0 {
            CLOCK.write(reg::INTSTATUS, reg::IRQ);
            let periods = DRIVER.periods.borrow(cs);
            periods.set(periods.get() + 1);
        }
    })
}

/// Timer 1 fired: wake what is due and re-arm.
pub fn on_alarm_interrupt() {
    critical_section::with(|cs| DRIVER.dispatch(cs))
}
