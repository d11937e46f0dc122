//! The QEMU demonstration image: cam-timing and jump predictor. At boot, with the alarm asserted, builds
//! the prediction table of the chip's scene (camsim-core's model in f32, configured by
//! the `camsim-chip` crate) and checks its interpolation against direct simulations;
//! then runs the chip's speed monitor (`camsim_chip::ChipMonitor`, the board's too) on
//! the QEMU board's index pulses: the scripted machine (`camsim_chip::CHIP_SCRIPT`, with
//! its faults) through the same `CaptureTimer` trait and `IndexPulse` code the board's
//! TIM2 capture feeds. Each reading gives a prediction and the alarm state (LED0, LOW =
//! asserted, the safe state) or a fault that asserts the alarm. When the script ends it
//! prints this image's own memory and boot cost (the `product ...` line) and exits with
//! success.
//!
//! Only the chip's model is linked here; the instruction probes (per RHS, per revolution,
//! the 22-state comparison model, libm costs) are the `budget` binary.
//!
//! Lines starting with `parity ` carry every compared value as raw f32 bits; the host
//! regenerates them with `camsim predict --f32` (the same script, monitor and table) and
//! checks them bit for bit (`camsim predict --f32 --check-log`). Lines starting with
//! `reaction ` state, for each reading that does not vouch for the speed, the alarm
//! state and the level read back from LED0 (scripts/firmware-ci.sh checks them).

#![no_std]
#![no_main]

use camsim_chip::{
    chip_solver_settings, ChipMonitor, ChipStep, MemoryFields, ParityLine, ProductLine,
    ReactionLine, ScriptedPulseTrain, CHIP_CHECK_RPM, CHIP_CLOCK_HZ,
};
use camsim_core::{CaptureTimer, SpeedPrediction, SteadyState};
use camsim_firmware::board::qemu::{alarm_output, boot_or_stop, stop_safe, AlarmOutput, ALARM_PIN};
use camsim_firmware::memory::{paint_stack, MemoryReport};
use camsim_firmware::monitor::{error_name, log_alarm_change, log_config, log_fault, Counts};
use camsim_firmware::timing::InstrCounter;
use camsim_firmware::workload::Predictor;
use camsim_firmware::{exit_failure, exit_success};
use cortex_m_rt::entry;

/// Clock the boot time is stated at (Hz): a typical Cortex-M4F (e.g. STM32F4) at full speed.
const STATED_CLOCK_HZ: u64 = CHIP_CLOCK_HZ;

/// Logs one row of the boot table (readable and as parity bits).
fn log_table_row(i: usize, rpm: f32, s: &SteadyState<f32>) {
    let t = &s.timing_deg;
    defmt::info!(
        "table rpm={=f32} min_force_lb={=f32} jumped={=bool} timing_deg rise10/50/90={=f32} {=f32} {=f32} return10/50/90={=f32} {=f32} {=f32}",
        rpm, s.min_contact_force, s.jumped, t[0], t[1], t[2], t[3], t[4], t[5]
    );
    defmt::info!("{}", ParityLine::table(i as u32, rpm, s));
}

/// Logs a prediction at a vouched speed (readable and as parity bits).
fn log_sample(i: u32, p: &SpeedPrediction<f32>, alarm: bool) {
    let t = &p.timing_deg;
    defmt::info!(
        "sample rpm={=f32} force_margin_lb={=f32} speed_margin_rpm={=f32} in_grid={=bool} alarm={=bool} timing_deg rise10/50/90={=f32} {=f32} {=f32} return10/50/90={=f32} {=f32} {=f32}",
        p.rpm, p.force_margin_lb, p.speed_margin_rpm, p.in_grid, alarm, t[0], t[1], t[2], t[3], t[4], t[5]
    );
    defmt::info!("{}", ParityLine::sample(i, p, alarm));
}

/// Logs a reading that does not vouch for the speed: why (a warning), the parity line,
/// and the reaction: the alarm state and LED0's level read back.
fn log_non_vouched(i: u32, monitor: &ChipMonitor<f32>, step: &ChipStep<f32>, led0_low: bool) {
    log_fault(monitor, &step.reading);
    defmt::info!("{}", ParityLine::reading(i, &step.reading, step.alarm));
    let reaction = ReactionLine {
        kind: step.reading.kind(),
        asserted: step.alarm,
        pin: ALARM_PIN,
        low: led0_low,
    };
    defmt::info!("{}", reaction);
}

/// Logs the boot table (a row per grid speed) and its jump onset.
fn log_table(predictor: &Predictor) {
    let table = &predictor.table;
    for (i, (rpm, s)) in table.rpm.iter().zip(table.at.iter()).enumerate() {
        log_table_row(i, *rpm, s);
    }
    match table.jump_rpm {
        Some(j) => {
            defmt::info!("jump_onset_rpm={=f32}", j);
            defmt::info!("{}", ParityLine::jump(Some(j)));
        }
        None => {
            defmt::info!("jump_onset_rpm=none (no jump up to the search limit)");
            defmt::info!("{}", ParityLine::jump(None));
        }
    }
}

/// How accurate the interpolation is: direct simulations between grid points, logged
/// with their instruction count.
fn check_interpolation(predictor: &Predictor, counter: &InstrCounter) {
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
                    defmt::info!("{}", ParityLine::check(rpm, &d));
                }
                Err(e) => defmt::error!("interp_check rpm={=f32} failed: {=str}", rpm, error_name(&e)),
            }
        }
    });
    defmt::info!("interp_check_instr={=u64}", check_instr);
}

/// The speed monitor on the scripted machine's index pulses (its faults included): each
/// reading logged with its reaction on `out`, then the summary line. Returns the most
/// instructions a reading took.
fn run_monitor(predictor: &Predictor, counter: &InstrCounter, out: &mut AlarmOutput) -> u64 {
    let mut train = ScriptedPulseTrain::chip();
    let mut monitor = match ChipMonitor::<f32>::new(train.tick_hz()) {
        Ok(m) => m,
        Err(e) => {
            defmt::error!("speed monitor configuration: {=str}", error_name(&e));
            stop_safe(out, "invalid speed monitor configuration")
        }
    };
    log_config(&monitor);
    let mut counts = Counts::default();
    let mut max_rpm = 0.0f32;
    let mut max_instr = 0u64;
    while !train.finished() {
        let (step, instr) = counter.measure(|| monitor.step(&predictor.table, &mut train));
        let Some(step) = step else { continue };
        max_instr = max_instr.max(instr);
        let i = counts.total();
        counts.add(&step.reading);
        // LED0 writes cannot fail (Infallible).
        let Ok(changed) = out.set_asserted(step.alarm);
        match &step.prediction {
            Some(p) => {
                log_sample(i, p, step.alarm);
                max_rpm = max_rpm.max(p.rpm);
            }
            None => {
                let Ok(low) = out.reads_low();
                log_non_vouched(i, &monitor, &step, low);
            }
        }
        if changed {
            log_alarm_change(ALARM_PIN, &step);
        }
    }
    let Ok(low) = out.reads_low();
    defmt::info!(
        "predictor readings={=u32} counts={} alarm_transitions={=u32} max_vouched_rpm={=f32} max_instr_per_reading={=u64} script_ticks={=u64} alarm_at_end={=str} ({=str} {=str})",
        counts.total(),
        counts,
        out.transitions(),
        max_rpm,
        max_instr,
        train.elapsed_ticks(),
        if out.is_asserted() { "asserted" } else { "released" },
        ALARM_PIN,
        if low { "low" } else { "high" }
    );
    max_instr
}

#[entry]
fn main() -> ! {
    // First: paint the free stack so the peak can be read back at the end.
    paint_stack();

    // The alarm output before anything else, asserted (LED0 low, the safe state).
    let Some(mut out) = alarm_output() else {
        defmt::error!("alarm pin already taken");
        exit_failure()
    };
    let Some(cp) = cortex_m::Peripherals::take() else {
        stop_safe(&mut out, "core peripherals already taken")
    };
    let mut counter = InstrCounter::start(cp.SYST);
    counter.calibrate();

    // Boot: the prediction table over the scene's speed grid (the alarm stays asserted).
    let (predictor, boot_instr) = boot_or_stop(&counter, &mut out, &chip_solver_settings());
    let boot_ms = boot_instr * 1000 / STATED_CLOCK_HZ;
    defmt::info!(
        "boot_instr={=u64} (~{=u64} ms at {=u64} MHz assuming ~1 instruction per cycle; a real M4F needs more cycles than instructions)",
        boot_instr, boot_ms, STATED_CLOCK_HZ / 1_000_000
    );
    log_table(&predictor);

    check_interpolation(&predictor, &counter);

    let max_instr = run_monitor(&predictor, &counter, &mut out);

    // Memory of this image: static sections from the linker, stack from the paint.
    let mem = MemoryReport::measure();
    if mem.stack_overflowed() {
        stop_safe(&mut out, "stack overflow")
    }
    let line = ProductLine {
        memory: MemoryFields {
            flash_bytes: mem.flash_bytes,
            ram_static_bytes: mem.ram_static_bytes,
            stack_peak_bytes: mem.stack_peak_bytes,
            ram_bytes: mem.ram_bytes(),
        },
        boot_instr,
        max_instr_per_reading: max_instr,
    };
    defmt::info!("{}", line);
    exit_success()
}
