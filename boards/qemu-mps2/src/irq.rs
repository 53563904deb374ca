//! The machine's interrupt lines, and the one handler that serves them.
//!
//! cortex-m-rt points every external interrupt vector at `DefaultHandler`, which receives
//! the interrupt number: it dispatches to the driver that owns the line.

use cortex_m::interrupt::InterruptNumber;
use cortex_m::peripheral::NVIC;

use crate::machine::THIS;

/// External interrupts of the machine that the board uses (their numbers are the
/// machine's, [`crate::machine::THIS`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Irq {
    /// CMSDK APB timer 0 (the free-running clock).
    Timer0,
    /// CMSDK APB timer 1 (the alarm).
    Timer1,
    /// LAN9118 Ethernet controller.
    Ethernet,
}

// SAFETY: the numbers are valid external interrupts of the machine (the mps2 machines have
// 32, mps2-an505 has 32 + 92).
unsafe impl InterruptNumber for Irq {
    fn number(self) -> u16 {
        match self {
            Irq::Timer0 => THIS.timer0.1,
            Irq::Timer1 => THIS.timer1.1,
            Irq::Ethernet => THIS.lan9118.1,
        }
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
    let line = u16::try_from(irqn).ok();
    if line == Some(THIS.timer0.1) {
        crate::time::on_wrap_interrupt()
    } else if line == Some(THIS.timer1.1) {
        crate::time::on_alarm_interrupt()
    } else if line == Some(THIS.lan9118.1) {
        crate::lan9118::on_interrupt()
    } else {
        panic!("unexpected exception or interrupt {irqn}")
    }
}
