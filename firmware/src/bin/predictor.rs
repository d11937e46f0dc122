//! Cam-timing and jump predictor: at boot, builds the prediction table of the chip's
//! scene (camsim-core's model in f32, configured by the `camsim-chip` crate) and checks its
//! interpolation against direct simulations; then reads the cam speed once per
//! revolution, predicts the contact-force margin, the speed margin to jump onset and the
//! follower timing errors, drives the alarm pin with hysteresis; finally measures and
//! prints the budget line and exits (status 0) through semihosting.
//!
//! Lines starting with `parity ` carry every compared value as raw f32 bits; the host
//! regenerates them with `camsim predict --f32` and checks them bit for bit
//! (`camsim predict --f32 --check-log`).

#![no_std]
#![no_main]

use camsim_chip::{chip_alarm, ChipScene, CHIP_CHECK_RPM, CHIP_STATES};
use camsim_core::{
    JumpAlarm, Real, RegulatedFull, Scene, SpeedPrediction, SpeedSource, SteadyState,
};
use camsim_firmware::board::qemu::{FakeIndexPulse, LedAlarmPin, ScriptedSpeed};
use camsim_firmware::memory::{paint_stack, stack_peak_bytes, Sections};
use camsim_firmware::timing::{on_systick_wrap, InstrCounter};
use camsim_firmware::workload::{self, Predictor};
use camsim_firmware::{exit_failure, exit_success};
use cortex_m_rt::{entry, exception, ExceptionFrame};
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

/// Measures instructions per RHS and per revolution of scene `S`'s model (`N = S::N`).
fn measure_model<S: Scene, const N: usize>(
    counter: &InstrCounter,
    name: &str,
) -> Option<(u64, u64)> {
    let (model, y) = workload::rhs_probe::<S, N>()?;
    let (checksum, rhs_instr) =
        counter.measure(|| workload::evaluate_rhs(&model, &y, workload::RHS_REPS));
    let per_rhs = rhs_instr / u64::from(workload::RHS_REPS);
    let (rev, rev_instr) = counter.measure(|| workload::simulate_revolution::<S, N>());
    let rev = rev?;
    defmt::info!(
        "model {=str} states={=usize} instr_per_rhs={=u64} instr_per_rev={=u64} rev_rhs_evals={=u32} rev_steps={=u32} instr_per_rev_per_eval={=u64} rhs_checksum={=f32} load_in={=f32} load_in_per_s={=f32} load_bits={=u32:#010x}",
        name, N, per_rhs, rev_instr, rev.rhs_evals, rev.steps,
        rev_instr / u64::from(rev.rhs_evals.max(1)), checksum, rev.load_in, rev.load_in_per_s, rev.load_in.to_bits()
    );
    Some((per_rhs, rev_instr))
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

    // Instructions per right-hand-side evaluation and per simulated revolution (800 rpm):
    // the full 22-state model for comparison, then the chip's model (the budget line).
    if measure_model::<RegulatedFull, { RegulatedFull::N }>(&counter, "full").is_none() {
        defmt::error!("full model measurement failed");
        exit_failure()
    }
    let Some((instr_per_rhs, rev_instr)) =
        measure_model::<ChipScene, CHIP_STATES>(&counter, "chip")
    else {
        defmt::error!("chip model measurement failed");
        exit_failure()
    };

    // What the elementary functions cost (libm in software; f32 trig computes in f64).
    let x = core::hint::black_box(0.7f32);
    let (_, sc) = counter.measure(|| {
        (0..100).fold(0.0f32, |a, i| {
            let (s, c) = core::hint::black_box(x + i as f32 * 1e-3).sin_cos();
            a + s + c
        })
    });
    let (_, at) = counter.measure(|| {
        (0..100).fold(0.0f32, |a, i| {
            a + core::hint::black_box(x + i as f32 * 1e-3).atan2(1.3)
        })
    });
    let (_, sq) = counter.measure(|| {
        (0..100).fold(0.0f32, |a, i| {
            a + core::hint::black_box(x + i as f32 * 1e-3).sqrt()
        })
    });
    let (_, dv) = counter.measure(|| {
        (0..100).fold(0.0f32, |a, i| {
            a + 1.0 / core::hint::black_box(x + i as f32 * 1e-3)
        })
    });
    defmt::info!(
        "math instr_per_call sin_cos={=u64} atan2={=u64} sqrt={=u64} loop_with_divide={=u64}",
        sc / 100,
        at / 100,
        sq / 100,
        dv / 100
    );

    // Memory: static sections from the linker, stack from the paint.
    let sections = Sections::get();
    let flash_bytes = sections.flash_bytes();
    let ram_static_bytes = sections.ram_static_bytes();
    let stack_peak = stack_peak_bytes();
    defmt::info!(
        "sections text_end={=u32:#x} rodata={=u32:#x}..{=u32:#x} data={=u32:#x}..{=u32:#x} bss={=u32:#x}..{=u32:#x} uninit={=u32:#x}..{=u32:#x} stack={=u32:#x}..{=u32:#x}",
        sections.etext,
        sections.srodata,
        sections.erodata,
        sections.sdata,
        sections.edata,
        sections.sbss,
        sections.ebss,
        sections.suninit,
        sections.euninit,
        sections.stack_end,
        sections.stack_start
    );
    if stack_peak >= sections.stack_room_bytes() {
        defmt::error!(
            "stack overflowed its {=u32} bytes",
            sections.stack_room_bytes()
        );
        exit_failure()
    }
    defmt::info!(
        "budget flash_bytes={=u32} ram_static_bytes={=u32} stack_peak_bytes={=u32} ram_bytes={=u32} instr_per_rhs={=u64} instr_per_rev={=u64}",
        flash_bytes,
        ram_static_bytes,
        stack_peak,
        ram_static_bytes + stack_peak,
        instr_per_rhs,
        rev_instr
    );
    exit_success()
}

#[exception]
fn SysTick() {
    on_systick_wrap();
}

#[exception]
unsafe fn HardFault(ef: &ExceptionFrame) -> ! {
    defmt::error!("HardFault at pc={=u32:#010x}", ef.pc());
    exit_failure()
}
