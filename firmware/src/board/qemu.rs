//! QEMU `mps2-an386` (ARM MPS2 board, AN386 Cortex-M4 FPGA image).
//!
//! Memory map used (checked with QEMU 7.2 `info mtree`): code SSRAM at 0x0000_0000,
//! data SSRAM at 0x2000_0000, FPGA IO block at 0x4002_8000 (`LED0` at offset 0).

use core::convert::Infallible;
use core::sync::atomic::{AtomicBool, Ordering};

use embedded_hal::digital::{ErrorType, InputPin, OutputPin, StatefulOutputPin};

/// Scripted cam speed: the profile shared with the host (`camsim predict`), defined in
/// the `camsim-chip` crate so both run the same samples.
pub use camsim_chip::ScriptedProfile as ScriptedSpeed;

/// Fake index pulse: each read alternates low/high, so a wait for the next rising
/// edge always finds one (one "revolution" per speed sample).
#[derive(Clone, Debug, Default)]
pub struct FakeIndexPulse {
    level: bool,
}

impl ErrorType for FakeIndexPulse {
    type Error = Infallible;
}

impl InputPin for FakeIndexPulse {
    fn is_high(&mut self) -> Result<bool, Self::Error> {
        self.level = !self.level;
        Ok(self.level)
    }

    fn is_low(&mut self) -> Result<bool, Self::Error> {
        self.is_high().map(|h| !h)
    }
}

/// FPGA IO `LED0` register of the MPS2 (bit 0 = user LED 0).
const FPGAIO_LED0: usize = 0x4002_8000;

static LED_TAKEN: AtomicBool = AtomicBool::new(false);

/// The jump alarm on the MPS2's user LED 0 (FPGA IO `LED0` bit 0); logs every transition.
#[derive(Debug)]
pub struct LedAlarmPin {
    transitions: u32,
}

impl LedAlarmPin {
    /// The pin, once (`None` if already taken), switched off.
    pub fn take() -> Option<Self> {
        if LED_TAKEN.swap(true, Ordering::AcqRel) {
            return None;
        }
        let mut pin = Self { transitions: 0 };
        pin.write(false);
        Some(pin)
    }

    /// Times the output changed level.
    pub fn transitions(&self) -> u32 {
        self.transitions
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

    fn set(&mut self, on: bool) {
        if self.read() != on {
            self.transitions += 1;
            defmt::info!(
                "alarm pin -> {=str}",
                if on {
                    "HIGH (jump alarm on)"
                } else {
                    "LOW (jump alarm off)"
                }
            );
        }
        self.write(on);
    }
}

impl ErrorType for LedAlarmPin {
    type Error = Infallible;
}

impl OutputPin for LedAlarmPin {
    fn set_low(&mut self) -> Result<(), Self::Error> {
        self.set(false);
        Ok(())
    }

    fn set_high(&mut self) -> Result<(), Self::Error> {
        self.set(true);
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
