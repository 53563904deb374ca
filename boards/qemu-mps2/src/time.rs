//! The embassy-time driver of the machine: two CMSDK APB timers clocked at the system clock
//! (25 MHz, 20 MHz on mps2-an505), giving a 1 MHz time base (one tick = 25 or 20 timer
//! counts).
//!
//! - Timer 0 counts down from `PERIOD_COUNTS` - 1 forever: a period is exactly 2^27 µs
//!   (134.2 s), so the time is the period count shifted left plus a 32-bit division of the
//!   counts into the period (a multiplication: no 64-bit division on every `now`). Its wrap
//!   interrupt counts periods, which extends it to 64 bits.
//! - Timer 1 is the alarm: loaded with the counts until the earliest timer of the queue or
//!   the link task's deadline, it interrupts once and is stopped.
//!
//! The link task's deadline has a slot of its own beside the queue ([`LinkSlot`], the
//! task's `enip_firmware::link::LinkAlarm`): asking for it finds no queue entry, and the
//! alarm firing for it walks the queue only if the queue has a timer due too.

use core::cell::{Cell, RefCell};
use core::task::Waker;

use critical_section::{CriticalSection, Mutex};
use embassy_time_driver::Driver;
use embassy_time_queue_utils::Queue;
use enip_firmware::link::{KeptWaker, LinkAlarm};

use crate::irq::{self, Irq};
use crate::mmio::Block;

/// Timer counts per microsecond (the timers run at the system clock).
const COUNTS_PER_US: u64 = crate::machine::COUNTS_PER_US as u64;
/// Microseconds of one period of the free-running timer, as a power of two.
const PERIOD_US_LOG2: u32 = 27;
/// Timer counts of one period: 2^27 µs (fits in the 32-bit counter up to 31 MHz).
const PERIOD_COUNTS: u32 = (COUNTS_PER_US << PERIOD_US_LOG2) as u32;
/// The longest alarm in µs the 32-bit counter holds; a later deadline fires this early,
/// and the queue re-arms for the rest.
const MAX_ALARM_US: u32 = u32::MAX / COUNTS_PER_US as u32;

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
const CLOCK: Block = Block::at(crate::machine::THIS.timer0.0);
/// The alarm timer.
const ALARM: Block = Block::at(crate::machine::THIS.timer1.0);

/// The time driver: wrap count, timer queue, the link task's slot and the tick the alarm is
/// armed for, shared with the interrupt handlers.
struct Mps2Time {
    periods: Mutex<Cell<u64>>,
    queue: Mutex<RefCell<Queue>>,
    /// The queue's earliest expiry as last learned, or an earlier tick (`u64::MAX`: none):
    /// an alarm before it leaves the queue alone.
    queue_next: Mutex<Cell<u64>>,
    /// The link task's deadline (`u64::MAX`: none).
    link_at: Mutex<Cell<u64>>,
    /// The link task's waker, kept across its wake-ups.
    link_waker: Mutex<KeptWaker>,
    /// The alarm fires at this tick (`u64::MAX`: not armed); a timer due later needs no
    /// re-arming, as the queue is walked again when the alarm fires.
    armed: Mutex<Cell<u64>>,
}

embassy_time_driver::time_driver_impl!(static DRIVER: Mps2Time = Mps2Time {
    periods: Mutex::new(Cell::new(0)),
    queue: Mutex::new(RefCell::new(Queue::new())),
    queue_next: Mutex::new(Cell::new(u64::MAX)),
    link_at: Mutex::new(Cell::new(u64::MAX)),
    link_waker: Mutex::new(KeptWaker::new()),
    armed: Mutex::new(Cell::new(u64::MAX)),
});

/// The link task's alarm: a slot of the time driver beside its queue, holding the one
/// deadline last asked.
#[derive(Debug, Clone, Copy, Default)]
pub struct LinkSlot;

impl LinkAlarm for LinkSlot {
    fn wake_at(&self, at: u64, waker: &Waker) {
        critical_section::with(|cs| {
            DRIVER.link_waker.borrow(cs).register(waker);
            DRIVER.link_at.borrow(cs).set(at);
            DRIVER.arm_earlier(cs, at);
        })
    }

    fn keeps_deadline(&self) -> bool {
        true
    }
}

/// Starts the clock and enables both timer interrupts; call once, first thing in `main`.
pub fn init() {
    ALARM.write(reg::CTRL, 0);
    ALARM.write(reg::INTSTATUS, reg::IRQ);
    CLOCK.write(reg::CTRL, 0);
    CLOCK.write(reg::INTSTATUS, reg::IRQ);
    CLOCK.write(reg::RELOAD, PERIOD_COUNTS - 1);
    CLOCK.write(reg::VALUE, PERIOD_COUNTS - 1);
    CLOCK.write(reg::CTRL, reg::EN | reg::IRQEN);
    irq::enable(Irq::Timer0);
    irq::enable(Irq::Timer1);
}

impl Mps2Time {
    /// Microseconds since [`init`], in a critical section so a pending wrap is seen.
    fn now_in(&self, cs: CriticalSection<'_>) -> u64 {
        let periods = self.periods.borrow(cs).get();
        let value = CLOCK.read(reg::VALUE);
        // A wrap the handler has not counted yet: re-read, the value is after it.
        let (periods, value) = if CLOCK.read(reg::INTSTATUS) & reg::IRQ != 0 {
            (periods + 1, CLOCK.read(reg::VALUE))
        } else {
            (periods, value)
        };
        let into_period = (PERIOD_COUNTS - 1).saturating_sub(value) / COUNTS_PER_US as u32;
        (periods << PERIOD_US_LOG2) + u64::from(into_period)
    }

    /// Arms the alarm for tick `at`; false if `at` is already due (nothing armed).
    fn arm(&self, cs: CriticalSection<'_>, at: u64) -> bool {
        self.arm_from(cs, at, || self.now_in(cs))
    }

    /// [`Self::arm`] with the time read by `now` (once, after the alarm is stopped: it is
    /// counted from then).
    fn arm_from(&self, cs: CriticalSection<'_>, at: u64, now: impl FnOnce() -> u64) -> bool {
        ALARM.write(reg::CTRL, 0);
        ALARM.write(reg::INTSTATUS, reg::IRQ);
        let armed = self.armed.borrow(cs);
        armed.set(u64::MAX);
        if at == u64::MAX {
            return true;
        }
        let now = now();
        if at <= now {
            return false;
        }
        // 32-bit arithmetic: the delay clamped to what the counter holds.
        let us = (at - now).min(u64::from(MAX_ALARM_US)) as u32;
        ALARM.write(reg::RELOAD, us * COUNTS_PER_US as u32);
        ALARM.write(reg::CTRL, reg::EN | reg::IRQEN);
        armed.set(now + u64::from(us));
        true
    }

    /// Wakes every expired timer and arms the alarm for the next one.
    fn dispatch(&self, cs: CriticalSection<'_>) {
        // Bounded: each round wakes the timers that expired, and time moves forward.
        let mut next = self.expire(cs, self.now_in(cs));
        while !self.arm(cs, next) {
            next = self.expire(cs, self.now_in(cs));
        }
    }

    /// Wakes the link task if its deadline has come at `now`, and the queue's timers that
    /// expired if one may have; returns the earliest deadline left.
    fn expire(&self, cs: CriticalSection<'_>, now: u64) -> u64 {
        let link_at = self.link_at.borrow(cs);
        if link_at.get() <= now {
            link_at.set(u64::MAX);
            self.link_waker.borrow(cs).wake();
        }
        let queue_next = self.queue_next.borrow(cs);
        if queue_next.get() <= now {
            queue_next.set(self.queue.borrow_ref_mut(cs).next_expiration(now));
        }
        link_at.get().min(queue_next.get())
    }

    /// Arms the alarm for `at` if it comes before the one armed (then `at` is the earliest
    /// deadline: every other is due at `armed` or later, so no walk is needed), unless the
    /// alarm is due already or so is `at` (then [`Self::dispatch`] wakes what expired). One
    /// look at the clock serves both.
    fn arm_earlier(&self, cs: CriticalSection<'_>, at: u64) {
        let armed = self.armed.borrow(cs).get();
        if at < armed {
            let now = self.now_in(cs);
            if armed <= now || !self.arm_from(cs, at, || now) {
                self.dispatch(cs);
            }
        }
    }
}

impl Driver for Mps2Time {
    fn now(&self) -> u64 {
        critical_section::with(|cs| self.now_in(cs))
    }

    fn schedule_wake(&self, at: u64, waker: &Waker) {
        critical_section::with(|cs| {
            if self.queue.borrow_ref_mut(cs).schedule_wake(at, waker) {
                let queue_next = self.queue_next.borrow(cs);
                queue_next.set(queue_next.get().min(at));
                self.arm_earlier(cs, at);
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
