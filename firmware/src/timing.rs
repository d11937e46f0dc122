//! Instruction counting with SysTick under QEMU's `-icount shift=0`.
//!
//! With `-icount shift=0` QEMU advances its virtual clock by exactly 1 ns per
//! guest instruction, whatever the instruction, so SysTick (clocked from the
//! core clock) counts ticks in proportion to EXECUTED INSTRUCTIONS, not cycles.
//! On mps2-an386 the core clock is 25 MHz, i.e. about 40 instructions per tick;
//! [`InstrCounter::calibrate`] measures the ratio against a loop of known
//! instruction count instead of assuming it. On real silicon the same code
//! counts core cycles (the calibration then gives cycles per loop instruction).
//!
//! The 24-bit counter wraps every 2^24 ticks; the SysTick exception counts the
//! wraps (the crate's `SysTick` handler in `lib.rs` calls [`on_systick_wrap`]), so
//! spans of any length are measured.

use core::sync::atomic::{AtomicU32, Ordering};
use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::{SCB, SYST};

const RELOAD: u32 = 0x00FF_FFFF;

static WRAPS: AtomicU32 = AtomicU32::new(0);

/// Call from the `SysTick` exception handler: counts one counter wrap.
pub fn on_systick_wrap() {
    WRAPS.fetch_add(1, Ordering::Relaxed);
}

/// Iterations of the calibration loop (two instructions each).
pub const CALIBRATION_ITERS: u32 = 5_000_000;

/// Runs exactly `2 * n` instructions (`subs` + `bne` per iteration) for `n >= 1`.
#[inline(never)]
pub fn known_loop(n: u32) {
    // SAFETY: pure register arithmetic on its own operand; no memory, no stack.
    unsafe {
        core::arch::asm!(
            "2:",
            "subs {n}, {n}, #1",
            "bne 2b",
            n = inout(reg) n.max(1) => _,
            options(nomem, nostack),
        );
    }
}

/// A free-running 64-bit tick count built on SysTick, with its calibration.
pub struct InstrCounter {
    _syst: SYST,
    /// Ticks measured for the calibration span (see [`Self::calibrate`]).
    cal_ticks: u64,
    /// Instructions in the calibration span.
    cal_instr: u64,
}

impl InstrCounter {
    /// Starts SysTick from the core clock with the largest reload and its wrap interrupt.
    pub fn start(mut syst: SYST) -> Self {
        syst.disable_counter();
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(RELOAD);
        syst.clear_current();
        syst.enable_interrupt();
        syst.enable_counter();
        Self {
            _syst: syst,
            cal_ticks: 0,
            cal_instr: 0,
        }
    }

    /// Ticks since [`Self::start`].
    #[inline(never)]
    pub fn now(&self) -> u64 {
        loop {
            let w1 = WRAPS.load(Ordering::Acquire);
            let cvr = SYST::get_current();
            let pending = SCB::is_pendst_pending();
            let w2 = WRAPS.load(Ordering::Acquire);
            if w1 == w2 {
                let mut wraps = u64::from(w1);
                // The counter reached 0 (a wrap) but the exception has not run yet.
                if pending && (cvr == 0 || cvr > RELOAD / 2) {
                    wraps += 1;
                }
                let period = u64::from(RELOAD) + 1;
                // The count runs RELOAD, ..., 1, 0 and the wrap is counted on reaching
                // 0, so 0 is the last tick of the period that `wraps` already closed.
                // (Right after `start` the counter also reads 0 until its first load:
                // that is time 0.)
                if cvr == 0 {
                    return (wraps * period).saturating_sub(1);
                }
                return wraps * period + u64::from(RELOAD - cvr);
            }
        }
    }

    /// Measures ticks per instruction: runs [`known_loop`] with N and 2N iterations and
    /// takes the difference, which cancels the call and timer-read overhead exactly.
    pub fn calibrate(&mut self) {
        let n = CALIBRATION_ITERS;
        let t0 = self.now();
        known_loop(n);
        let t1 = self.now();
        known_loop(2 * n);
        let t2 = self.now();
        let single = t1 - t0;
        let double = t2 - t1;
        self.cal_ticks = double.saturating_sub(single);
        self.cal_instr = 2 * u64::from(n);
        defmt::info!(
            "calibration: {=u64} instructions = {=u64} ticks ({=u64} ticks for {=u64}, {=u64} for {=u64})",
            self.cal_instr,
            self.cal_ticks,
            single,
            2 * u64::from(n),
            double,
            4 * u64::from(n)
        );
    }

    /// Converts a tick span into instructions, rounded (0 before calibration).
    pub fn ticks_to_instr(&self, ticks: u64) -> u64 {
        if self.cal_ticks == 0 {
            return 0;
        }
        (ticks * self.cal_instr + self.cal_ticks / 2) / self.cal_ticks
    }

    /// Runs `f` and returns its result with the instructions it took.
    pub fn measure<R>(&self, f: impl FnOnce() -> R) -> (R, u64) {
        let t0 = self.now();
        let r = f();
        let t1 = self.now();
        (r, self.ticks_to_instr(t1 - t0))
    }
}
