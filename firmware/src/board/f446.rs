//! Nucleo-F446RE (STM32F446RE, Cortex-M4F at 180 MHz) through `stm32f4xx-hal`.
//!
//! - **Index pulse -> TIM2 input capture, channel 1 on PA0** (AF1; Arduino header A0,
//!   CN8 pin 1, also CN7 pin 28). TIM2 is one of the F446's two 32-bit timers; it counts
//!   at [`TICK_HZ`] = 1 MHz (its 90 MHz APB1 timer clock divided by 90; the clock comes
//!   from the ST-LINK's 8 MHz crystal, see the binary) and latches the
//!   count on the **falling** edge: an NPN (sinking) inductive sensor pulls the line to
//!   ground when the cam's target passes. The input filter (fDTS/32, N = 8: 2.8 µs at
//!   90 MHz) drops ringing shorter than that; longer bounces reach the core's state
//!   machine ([`camsim_core::IndexPulse`]), which rejects them. PA0 gets the internal
//!   pull-up (about 40 kΩ); wire an external 4.7 kΩ to 3.3 V for a sensor cable.
//! - **Jump alarm -> PA5** (the board's green LED LD2, a stand-in for a relay driver or
//!   PLC input). [`crate::monitor::FailSafeOutput`]: **LOW = alarm asserted = the safe state**, HIGH =
//!   the predictor vouches for the speed and its margin. A de-energised output, a reset
//!   (pins float as inputs; a pull-down on the driver), a lost supply, a broken wire
//!   and a halted program (the independent watchdog resets it) all read as the alarm, so
//!   the alarm output fails safe. LED lit = running and safe; LED dark = alarm.
//! - [`drive_alarm_safe_from_fault`]: the one register write the HardFault and default
//!   handlers make to put PA5 low without owning the pin.

use camsim_core::{CaptureEvent, CaptureTimer};
use stm32f4xx_hal::gpio::{Output, PA0, PA5};
use stm32f4xx_hal::pac::{GPIOA, TIM2};
use stm32f4xx_hal::rcc::Rcc;
use stm32f4xx_hal::timer::{
    CaptureChannel, CaptureFilter, CaptureHzManager, CapturePolarity, Flag, Timer,
};
use stm32f4xx_hal::{ClearFlags, ReadFlags};

/// Tick rate of the index capture (TIM2 after its prescaler), Hz.
pub const TICK_HZ: u32 = 1_000_000;

/// TIM2 in input-capture mode on PA0 (channel 1), free-running over all 32 bits.
pub struct IndexCapture {
    timer: CaptureHzManager<TIM2>,
    channel: CaptureChannel<TIM2, 0>,
}

impl IndexCapture {
    /// Configures TIM2 at [`TICK_HZ`], channel 1 on PA0 (pull-up, falling edge, filtered).
    /// Panics (in the HAL) if TIM2's clock is not a multiple of [`TICK_HZ`]: a clock
    /// configuration error found at the first boot.
    pub fn new(tim2: TIM2, pa0: PA0, rcc: &mut Rcc) -> Self {
        use stm32f4xx_hal::prelude::*;
        let (timer, (ch1, ..)) = Timer::new(tim2, rcc).capture_hz(TICK_HZ.Hz());
        let mut channel = ch1.with(pa0.into_alternate::<1>().internal_pull_up(true));
        channel.set_filter(CaptureFilter::FdtsDiv32N8);
        channel.set_polarity(CapturePolarity::ActiveLow);
        channel.enable();
        Self { timer, channel }
    }
}

/// The board's side of the speed monitor (`camsim_chip::ChipMonitor`): the same trait the
/// QEMU board's scripted pulse train implements.
impl CaptureTimer for IndexCapture {
    /// The counter's actual tick rate, Hz (TIM2's clock over its prescaler).
    fn tick_hz(&self) -> u32 {
        self.timer.get_timer_clock()
    }

    /// The pending capture, if any. Reading the capture register clears its flag; the
    /// overcapture flag is checked after that read, so a capture lost at any moment is
    /// reported, never a period that silently spans two edges.
    fn poll_capture(&mut self) -> Option<CaptureEvent> {
        if !self.timer.flags().contains(Flag::C1) {
            return None;
        }
        let count = self.channel.get_capture();
        if self.timer.flags().contains(Flag::C1Overcapture) {
            self.timer.clear_flags(Flag::C1Overcapture);
            return Some(CaptureEvent::Overrun(count));
        }
        Some(CaptureEvent::Edge(count))
    }

    /// The counter now (for timeouts).
    fn now(&mut self) -> u32 {
        // SAFETY: TIM2's CNT register, a plain 32-bit read without side effects; `self`
        // owns TIM2 (through the HAL's capture manager), nothing else writes it.
        unsafe { (*TIM2::ptr()).cnt().read().bits() }
    }
}

/// The alarm pin of this board: PA5 (LD2), push-pull.
pub type AlarmPin = PA5<Output>;

/// Drives PA5 low (alarm asserted) without owning it: for the fault handlers.
pub fn drive_alarm_safe_from_fault() {
    // SAFETY: GPIOA's BSRR is write-only; writing BR5 (bit 21) resets PA5's output
    // atomically and touches no other pin or register, so it cannot race the owner of
    // PA5. If GPIOA is not clocked yet (a fault before setup) the write is ignored and the
    // pin is still a floating input after reset, which the driver's pull-down reads as
    // the alarm.
    unsafe { (*GPIOA::ptr()).bsrr().write(|w| w.br(5).set_bit()) };
}
