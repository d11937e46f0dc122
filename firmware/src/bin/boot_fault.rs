//! The QEMU demonstration image's boot with a solver failure provoked: the same boot as `predictor`
//! (`board::qemu::boot_or_stop`: alarm asserted first, then the prediction table) with an
//! impossible step budget (one step per revolution), so the table build fails with
//! `StepBudgetExceeded`. The QEMU demonstration image's failure path must then report the error and stop
//! with the alarm in its safe state (LED0 low, read back) and a failure exit (QEMU exit
//! status 1); scripts/firmware-ci.sh checks all three. Not a demonstration image: a test of the
//! QEMU demonstration image's boot-failure path, with that image's own code.

#![no_std]
#![no_main]

use camsim_chip::chip_solver_settings;
use camsim_core::SolverSettings;
use camsim_firmware::board::qemu::{alarm_output, boot_or_stop, stop_safe};
use camsim_firmware::exit_failure;
use camsim_firmware::timing::InstrCounter;
use cortex_m_rt::entry;

/// The impossible step budget: one step per revolution.
const STEPS_PER_REV: u32 = 1;

#[entry]
fn main() -> ! {
    let Some(mut out) = alarm_output() else {
        defmt::error!("alarm pin already taken");
        exit_failure()
    };
    let Some(cp) = cortex_m::Peripherals::take() else {
        stop_safe(&mut out, "core peripherals already taken")
    };
    let counter = InstrCounter::start(cp.SYST);
    let settings = SolverSettings {
        max_steps_per_rev: STEPS_PER_REV,
        ..chip_solver_settings()
    };
    defmt::info!(
        "boot_fault: the QEMU demonstration image's boot with an impossible solver budget (max_steps_per_rev={=u32})",
        STEPS_PER_REV
    );
    let _ = boot_or_stop(&counter, &mut out, &settings);
    defmt::error!("boot_fault: the boot did not fail");
    exit_failure()
}
