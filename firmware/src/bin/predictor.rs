//! The product: cam-timing and jump predictor. At boot, builds the prediction table of
//! the chip's scene (camsim-core's model in f32, configured by the `camsim-chip` crate) and
//! checks its interpolation against direct simulations; then reads the cam speed once per
//! revolution, predicts the contact-force margin, the speed margin to jump onset and the
//! follower timing errors, drives the alarm pin with hysteresis; when the speed source
//! ends (the QEMU board's scripted profile), prints this image's own memory and boot cost
//! (the `product ...` line) and exits with success.
//!
//! Only the chip's model is linked here; the instruction probes (per RHS, per revolution,
//! the 22-state comparison model, libm costs) are the `budget` binary.
//!
//! Lines starting with `parity ` carry every compared value as raw f32 bits; the host
//! regenerates them with `camsim predict --f32` and checks them bit for bit
//! (`camsim predict --f32 --check-log`).

#![no_std]
#![no_main]

use camsim_chip::{chip_alarm, CHIP_CHECK_RPM};
use camsim_core::{JumpAlarm, SpeedPrediction, SpeedSource, SteadyState};
use camsim_firmware::board::qemu::{FakeIndexPulse, LedAlarmPin, ScriptedSpeed};
use camsim_firmware::memory::{paint_stack, MemoryReport};
use camsim_firmware::timing::InstrCounter;
use camsim_firmware::workload::Predictor;
use camsim_firmware::{exit_failure, exit_success};
use cortex_m_rt::entry;
use embedded_hal::digital::{InputPin, OutputPin};

/// Polls of the index input before a missing pulse is reported.
const INDEX_POLLS: u32 = 100_000;
/// Clock the boot time is stated at (Hz): a typical Cortex-M4F (e.g. STM32F4) at full speed.
const STATED_CLOCK_HZ: u64 = 168_000_000;

/// What the predictor loop saw.
#[derive(Clone, Copy, Debug, Default, defmt::Format)]
struct LoopSummary {
    samples: u32,
    alarm_samples: u32,
    missed_index: u32,
    max_rpm: f32,
    /// Instructions of the slowest loop iteration (prediction + alarm, logging excluded).
    max_predict_instr: u64,
}

/// Waits for a rising edge of the index pulse; false if none came within the poll budget.
fn wait_index<I: InputPin>(index: &mut I) -> Result<bool, I::Error> {
    let mut was_high = index.is_high()?;
    for _ in 0..INDEX_POLLS {
        let high = index.is_high()?;
        if high && !was_high {
            return Ok(true);
        }
        was_high = high;
    }
    Ok(false)
}

/// A short name of a core error for the log (core::fmt would cost ~20 KB of flash).
fn error_name(e: &camsim_core::Error) -> &'static str {
    use camsim_core::Error as E;
    match e {
        E::InvalidParameter { field, .. } => field,
        E::Capacity { what, .. } => what,
        E::StepSizeUnderflow { .. } => "step size underflow",
        E::NonFinite { .. } => "non-finite state",
        E::StepBudgetExceeded { .. } => "step budget exceeded",
        E::NoConvergence { what, .. } => what,
        _ => "other error",
    }
}

/// Raw bits of the six timing errors.
fn timing_bits(t: &[f32; 6]) -> [u32; 6] {
    t.map(f32::to_bits)
}

/// Logs one row of the boot table (readable and as parity bits).
fn log_table_row(i: usize, rpm: f32, s: &SteadyState<f32>) {
    let t = &s.timing_deg;
    defmt::info!(
        "table rpm={=f32} min_force_lb={=f32} jumped={=bool} timing_deg rise10/50/90={=f32} {=f32} {=f32} return10/50/90={=f32} {=f32} {=f32}",
        rpm, s.min_contact_force, s.jumped, t[0], t[1], t[2], t[3], t[4], t[5]
    );
    let b = timing_bits(t);
    defmt::info!(
        "parity table i={=usize} rpm={=u32:#010x} force={=u32:#010x} jumped={=bool} timing={=u32:#010x},{=u32:#010x},{=u32:#010x},{=u32:#010x},{=u32:#010x},{=u32:#010x}",
        i, rpm.to_bits(), s.min_contact_force.to_bits(), s.jumped, b[0], b[1], b[2], b[3], b[4], b[5]
    );
}

/// Logs one prediction (readable and as parity bits).
fn log_sample(i: u32, p: &SpeedPrediction<f32>, alarm: bool) {
    let t = &p.timing_deg;
    defmt::info!(
        "sample rpm={=f32} force_margin_lb={=f32} speed_margin_rpm={=f32} in_grid={=bool} alarm={=bool} timing_deg rise10/50/90={=f32} {=f32} {=f32} return10/50/90={=f32} {=f32} {=f32}",
        p.rpm, p.force_margin_lb, p.speed_margin_rpm, p.in_grid, alarm, t[0], t[1], t[2], t[3], t[4], t[5]
    );
    let b = timing_bits(t);
    defmt::info!(
        "parity sample i={=u32} rpm={=u32:#010x} force={=u32:#010x} speed={=u32:#010x} alarm={=bool} timing={=u32:#010x},{=u32:#010x},{=u32:#010x},{=u32:#010x},{=u32:#010x},{=u32:#010x}",
        i, p.rpm.to_bits(), p.force_margin_lb.to_bits(), p.speed_margin_rpm.to_bits(), alarm, b[0], b[1], b[2], b[3], b[4], b[5]
    );
}

/// The predictor loop: one speed sample per revolution -> prediction -> hysteresis -> pin.
fn run_predictor<S, I, P>(
    counter: &InstrCounter,
    source: &mut S,
    index: &mut I,
    alarm_pin: &mut P,
    predictor: &Predictor,
    alarm: &mut JumpAlarm<f32>,
) -> LoopSummary
where
    S: SpeedSource<f32>,
    I: InputPin,
    P: OutputPin,
{
    let mut summary = LoopSummary::default();
    loop {
        match wait_index(index) {
            Ok(true) => {}
            Ok(false) => summary.missed_index += 1,
            Err(_) => {
                defmt::warn!("index pulse input failed");
                summary.missed_index += 1;
            }
        }
        let Some(rpm) = source.next_rpm() else { break };
        let ((p, on), instr) = counter.measure(|| {
            let p = predictor.predict(rpm);
            let on = alarm.update(p.speed_margin_rpm);
            (p, on)
        });
        if alarm_pin.set_state(on.into()).is_err() {
            defmt::error!("alarm pin write failed");
        }
        log_sample(summary.samples, &p, on);
        summary.samples += 1;
        summary.alarm_samples += u32::from(on);
        summary.max_predict_instr = summary.max_predict_instr.max(instr);
        if rpm > summary.max_rpm {
            summary.max_rpm = rpm;
        }
    }
    summary
}

#[entry]
fn main() -> ! {
    // First: paint the free stack so the peak can be read back at the end.
    paint_stack();

    let Some(cp) = cortex_m::Peripherals::take() else {
        defmt::error!("core peripherals already taken");
        exit_failure()
    };
    let mut counter = InstrCounter::start(cp.SYST);
    counter.calibrate();

    // Boot: the prediction table over the scene's speed grid.
    defmt::info!("scene={=str}", camsim_firmware::workload::SCENE_NAME);
    let (predictor, boot_instr) = counter.measure(Predictor::boot);
    let predictor = match predictor {
        Ok(p) => p,
        Err(e) => {
            defmt::error!("boot: table build failed: {=str}", error_name(&e));
            exit_failure()
        }
    };
    let boot_ms = boot_instr * 1000 / STATED_CLOCK_HZ;
    defmt::info!(
        "boot_instr={=u64} (~{=u64} ms at {=u64} MHz assuming ~1 instruction per cycle; a real M4F needs more cycles than instructions)",
        boot_instr, boot_ms, STATED_CLOCK_HZ / 1_000_000
    );
    let table = &predictor.table;
    for (i, (rpm, s)) in table.rpm.iter().zip(table.at.iter()).enumerate() {
        log_table_row(i, *rpm, s);
    }
    match table.jump_rpm {
        Some(j) => {
            defmt::info!("jump_onset_rpm={=f32}", j);
            defmt::info!("parity jump rpm={=u32:#010x}", j.to_bits());
        }
        None => {
            defmt::info!("jump_onset_rpm=none (no jump up to the search limit)");
            defmt::info!("parity jump rpm=none");
        }
    }

    // How accurate the interpolation is: direct simulations between grid points.
    let ((), check_instr) = counter.measure(|| {
        for rpm in CHIP_CHECK_RPM.map(|r| r as f32) {
            let p = predictor.predict(rpm);
            match predictor.direct(rpm) {
                Ok(d) => {
                    let df = (p.force_margin_lb - d.min_contact_force).abs();
                    let mut dt = 0.0f32;
                    for (a, b) in p.timing_deg.iter().zip(d.timing_deg.iter()) {
                        dt = dt.max((*a - *b).abs());
                    }
                    defmt::info!(
                        "interp_check rpm={=f32} interp_force_lb={=f32} direct_force_lb={=f32} abs_err_force_lb={=f32} max_abs_err_timing_deg={=f32} direct_jumped={=bool}",
                        rpm, p.force_margin_lb, d.min_contact_force, df, dt, d.jumped
                    );
                    let b = timing_bits(&d.timing_deg);
                    defmt::info!(
                        "parity check rpm={=u32:#010x} force={=u32:#010x} jumped={=bool} timing={=u32:#010x},{=u32:#010x},{=u32:#010x},{=u32:#010x},{=u32:#010x},{=u32:#010x}",
                        rpm.to_bits(), d.min_contact_force.to_bits(), d.jumped, b[0], b[1], b[2], b[3], b[4], b[5]
                    );
                }
                Err(e) => defmt::error!("interp_check rpm={=f32} failed: {=str}", rpm, error_name(&e)),
            }
        }
    });
    defmt::info!("interp_check_instr={=u64}", check_instr);

    // Predictor loop on the scripted speed profile.
    let Some(mut pin) = LedAlarmPin::take() else {
        defmt::error!("alarm pin already taken");
        exit_failure()
    };
    let mut alarm = match chip_alarm::<f32>() {
        Ok(a) => a,
        Err(_) => {
            defmt::error!("invalid alarm thresholds");
            exit_failure()
        }
    };
    let mut speed = ScriptedSpeed::new();
    let mut index = FakeIndexPulse::default();
    let summary = run_predictor(
        &counter, &mut speed, &mut index, &mut pin, &predictor, &mut alarm,
    );
    defmt::info!(
        "predictor samples={=u32} alarm_samples={=u32} alarm_transitions={=u32} missed_index={=u32} max_rpm={=f32} max_instr_per_prediction={=u64}",
        summary.samples,
        summary.alarm_samples,
        pin.transitions(),
        summary.missed_index,
        summary.max_rpm,
        summary.max_predict_instr
    );

    // Memory of this image: static sections from the linker, stack from the paint.
    let mem = MemoryReport::measure();
    if mem.stack_overflowed() {
        exit_failure()
    }
    defmt::info!(
        "product flash_bytes={=u32} ram_static_bytes={=u32} stack_peak_bytes={=u32} ram_bytes={=u32} boot_instr={=u64} max_instr_per_prediction={=u64}",
        mem.flash_bytes,
        mem.ram_static_bytes,
        mem.stack_peak_bytes,
        mem.ram_bytes(),
        boot_instr,
        summary.max_predict_instr
    );
    exit_success()
}
