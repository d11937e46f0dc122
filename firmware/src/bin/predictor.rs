//! Cam-timing and jump predictor: reads the cam speed once per revolution, predicts
//! the margin to jump onset, drives the alarm pin with hysteresis, then measures and
//! prints the firmware's budget line and exits (status 0) through semihosting.

#![no_std]
#![no_main]

use camsim_core::{JumpAlarm, SpeedSource};
use camsim_firmware::board::qemu::{FakeIndexPulse, LedAlarmPin, ScriptedSpeed};
use camsim_firmware::memory::{paint_stack, stack_peak_bytes, Sections};
use camsim_firmware::timing::{on_systick_wrap, InstrCounter};
use camsim_firmware::workload::{self, JumpPredictor};
use camsim_firmware::{exit_failure, exit_success};
use cortex_m_rt::{entry, exception, ExceptionFrame};
use embedded_hal::digital::{InputPin, OutputPin};

/// Alarm turns on at this margin to jump onset (rpm) or less.
const ALARM_ON_MARGIN_RPM: f32 = 100.0;
/// An active alarm turns off once the margin exceeds this (rpm).
const ALARM_OFF_MARGIN_RPM: f32 = 150.0;
/// Polls of the index input before a missing pulse is reported.
const INDEX_POLLS: u32 = 100_000;

/// What the predictor loop saw.
#[derive(Clone, Copy, Debug, Default, defmt::Format)]
struct LoopSummary {
    samples: u32,
    alarm_samples: u32,
    missed_index: u32,
    max_rpm: f32,
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

/// The predictor loop: one speed sample per revolution -> margin -> hysteresis -> pin.
fn run_predictor<S, I, P>(
    source: &mut S,
    index: &mut I,
    alarm_pin: &mut P,
    predictor: &mut JumpPredictor,
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
        let margin = predictor.margin_rpm(rpm);
        let on = alarm.update(margin);
        if alarm_pin.set_state(on.into()).is_err() {
            defmt::error!("alarm pin write failed");
        }
        summary.samples += 1;
        summary.alarm_samples += u32::from(on);
        if rpm > summary.max_rpm {
            summary.max_rpm = rpm;
        }
        defmt::debug!("rpm={=f32} margin={=f32} alarm={=bool}", rpm, margin, on);
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

    // Predictor loop on the scripted speed profile.
    let Some(mut pin) = LedAlarmPin::take() else {
        defmt::error!("alarm pin already taken");
        exit_failure()
    };
    let mut alarm = match JumpAlarm::new(ALARM_ON_MARGIN_RPM, ALARM_OFF_MARGIN_RPM) {
        Ok(a) => a,
        Err(_) => {
            defmt::error!("invalid alarm thresholds");
            exit_failure()
        }
    };
    let mut predictor = JumpPredictor::new();
    let mut speed = ScriptedSpeed::new();
    let mut index = FakeIndexPulse::default();
    let summary = run_predictor(&mut speed, &mut index, &mut pin, &mut predictor, &mut alarm);
    defmt::info!(
        "predictor samples={=u32} alarm_samples={=u32} alarm_transitions={=u32} missed_index={=u32} max_rpm={=f32} onset_rpm={=f32}",
        summary.samples,
        summary.alarm_samples,
        pin.transitions(),
        summary.missed_index,
        summary.max_rpm,
        predictor.onset_rpm()
    );

    // Instructions per right-hand-side evaluation and per simulated revolution.
    let (checksum, rhs_instr) = counter.measure(|| workload::evaluate_rhs(workload::RHS_REPS));
    let instr_per_rhs = rhs_instr / u64::from(workload::RHS_REPS);
    let (rev, rev_instr) = counter.measure(workload::simulate_revolution);
    defmt::info!(
        "workload rhs_checksum={=f32} rev_steps={=u32} rev_rhs_evals={=u32} follower_in={=f32} follower_in_per_s={=f32} follower_bits={=u32:#010x}",
        checksum,
        rev.steps,
        rev.rhs_evals,
        rev.follower_in,
        rev.follower_in_per_s,
        rev.follower_in.to_bits()
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
