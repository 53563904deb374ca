//! The machine's interrupt lines, and the one handler that serves them.
//!
//! cortex-m-rt points every external interrupt vector at `DefaultHandler`, which receives
//! the interrupt number: it dispatches to the driver that owns the line.

use cortex_m::interrupt::InterruptNumber;
use cortex_m::peripheral::NVIC;

/// External interrupts of mps2-an386 that the board uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Irq {
    /// CMSDK APB timer 0 (the free-running clock).
    Timer0 = 8,
    /// CMSDK APB timer 1 (the alarm).
    Timer1 = 9,
    /// LAN9118 Ethernet controller.
    Ethernet = 13,
}

// SAFETY: the numbers are valid external interrupts of the machine (it has 32).
unsafe impl InterruptNumber for Irq {
    fn number(self) -> u16 {
        self as u16
    }
}

/// Enables `irq` in the NVIC.
pub fn enable(irq: Irq) {
    // SAFETY: every handler is ready before its line is unmasked, and none relies on a
    // critical section being established by masking.
    unsafe { NVIC::unmask(irq) }
}

#[cortex_m_rt::exception]
unsafe fn DefaultHandler(irqn: i16) {
    match irqn {
        n if n == Irq::Timer0 as i16 => crate::time::on_wrap_interrupt(),
        n if n == Irq::Timer1 as i16 => crate::time::on_alarm_interrupt(),
        n if n == Irq::Ethernet as i16 => crate::lan9118::on_interrupt(),
        n => panic!("unexpected exception or interrupt {n}"),
    }
}
