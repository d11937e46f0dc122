//! QEMU `mps2-an386` (ARM MPS2 board, AN386 Cortex-M4 FPGA image): the HAL glue of the
//! QEMU board, as `f446` is the Nucleo's. The index pulses come from the scripted machine
//! ([`ScriptedPulseTrain`], a [`camsim_core::CaptureTimer`] like the board's TIM2
//! capture), the alarm goes to the FPGA IO's `LED0` with the board's fail-safe polarity
//! (LOW = asserted), and the QEMU demonstration image's boot ([`boot_or_stop`]) stops with the alarm
//! asserted on any failure.
//!
//! Memory map used (checked with QEMU 7.2 `info mtree`): code SSRAM at 0x0000_0000,
//! data SSRAM at 0x2000_0000, FPGA IO block at 0x4002_8000 (`LED0` at offset 0).

use core::convert::Infallible;
use core::sync::atomic::{AtomicBool, Ordering};

use camsim_core::SolverSettings;
use embedded_hal::digital::{ErrorType, OutputPin, StatefulOutputPin};

use crate::monitor::{error_name, FailSafeOutput};
use crate::timing::InstrCounter;
use crate::workload::{Predictor, PROFILE_KNOTS, PROFILE_NAME, SCENE_NAME};

/// The scripted machine's index pulses (`camsim_chip::CHIP_SCRIPT`): the QEMU board's
/// [`camsim_core::CaptureTimer`], in place of the board's TIM2 capture; the host's
/// `camsim predict` feeds the same train to the same monitor.
pub use camsim_chip::ScriptedPulseTrain;

/// The name of the alarm output in the log.
pub const ALARM_PIN: &str = "LED0";

/// FPGA IO `LED0` register of the MPS2 (bit 0 = user LED 0).
const FPGAIO_LED0: usize = 0x4002_8000;

static LED_TAKEN: AtomicBool = AtomicBool::new(false);

/// The jump alarm on the MPS2's user LED 0 (FPGA IO `LED0` bit 0), a plain output pin:
/// wrap it in [`FailSafeOutput`] (LOW = alarm asserted, the safe state, as on the board).
#[derive(Debug)]
pub struct LedAlarmPin {
    _private: (),
}

impl LedAlarmPin {
    /// The pin, once (`None` if already taken), driven LOW (the safe state).
    pub fn take() -> Option<Self> {
        if LED_TAKEN.swap(true, Ordering::AcqRel) {
            return None;
        }
        let mut pin = Self { _private: () };
        pin.write(false);
        Some(pin)
    }

    fn read(&self) -> bool {
        // SAFETY: FPGAIO_LED0 is the 32-bit, word-aligned LED0 register of the
        // MPS2 FPGA IO block (present on QEMU's mps2-an386 and the real AN386);
        // reads have no side effects.
        unsafe { core::ptr::read_volatile(FPGAIO_LED0 as *const u32) & 1 == 1 }
    }

    fn write(&mut self, on: bool) {
        // SAFETY: same register as in `read`; this struct is its only owner
        // (`take` hands it out once), so the read-modify-write is not racy.
        unsafe {
            let p = FPGAIO_LED0 as *mut u32;
            let v = core::ptr::read_volatile(p);
            core::ptr::write_volatile(p, (v & !1) | u32::from(on));
        }
    }
}

impl ErrorType for LedAlarmPin {
    type Error = Infallible;
}

impl OutputPin for LedAlarmPin {
    fn set_low(&mut self) -> Result<(), Self::Error> {
        self.write(false);
        Ok(())
    }

    fn set_high(&mut self) -> Result<(), Self::Error> {
        self.write(true);
        Ok(())
    }
}

impl StatefulOutputPin for LedAlarmPin {
    fn is_set_high(&mut self) -> Result<bool, Self::Error> {
        Ok(self.read())
    }

    fn is_set_low(&mut self) -> Result<bool, Self::Error> {
        Ok(!self.read())
    }
}

/// The alarm output of this board: [`LedAlarmPin`] with the fail-safe polarity.
pub type AlarmOutput = FailSafeOutput<LedAlarmPin>;

/// Takes LED0 as the alarm output, asserted (LOW); `None` if already taken.
pub fn alarm_output() -> Option<AlarmOutput> {
    let Ok(out) = FailSafeOutput::new(LedAlarmPin::take()?);
    Some(out)
}

/// Stops with the alarm in its safe state: asserts it, reads LED0 back, logs why, then the
/// failure exit (semihosting exit 1 under QEMU).
pub fn stop_safe(out: &mut AlarmOutput, why: &str) -> ! {
    let Ok(_) = out.set_asserted(true);
    let Ok(low) = out.reads_low();
    defmt::error!(
        "alarm asserted ({=str} low: {=bool}), stopped: {=str}",
        ALARM_PIN,
        low,
        why
    );
    crate::exit_failure()
}

/// The QEMU demonstration image's boot: builds the prediction table of the compiled-in scene with the
/// solver `settings` (the QEMU demonstration image passes `camsim_chip::chip_solver_settings()`) while the
/// alarm stays asserted; returns it with the instructions it took. A failure is logged
/// (`boot: table build failed: <error>`) and stops the firmware with the alarm asserted
/// ([`stop_safe`]).
pub fn boot_or_stop(
    counter: &InstrCounter,
    out: &mut AlarmOutput,
    settings: &SolverSettings<f32>,
) -> (Predictor, u64) {
    defmt::info!(
        "scene={=str} profile={=str} profile_knots={=usize}; alarm asserted ({=str} low): booting, building the prediction table",
        SCENE_NAME,
        PROFILE_NAME,
        PROFILE_KNOTS,
        ALARM_PIN
    );
    let (predictor, instr) = counter.measure(|| Predictor::boot_with(settings));
    match predictor {
        Ok(p) => (p, instr),
        Err(e) => {
            defmt::error!("boot: table build failed: {=str}", error_name(&e));
            stop_safe(out, "boot failed")
        }
    }
}
