//! The budget probes: instructions per right-hand-side evaluation and per simulated
//! revolution (800 rpm, the chip's solver settings) of the chip's model (the
//! quasi-static-rod scene, 10 states) and, for comparison, of the full 22-state model (the
//! reference design only: not beside a scene compiled in, for the flash);
//! the real-time factor (simulated time over CPU time at 168 MHz, one instruction a
//! cycle); what the elementary functions cost; and
//! this image's own memory. Prints the `budget ...` line that scripts/firmware-ci.sh reads
//! and exits with success.
//!
//! Not the QEMU demonstration image (that is `predictor`): this image links both models, so its flash and
//! stack are those of the probes, not of what a board runs.

#![no_std]
#![no_main]

use camsim_chip::{
    realtime_factor, BudgetLine, ChipScene, MemoryFields, CHIP_CLOCK_HZ, CHIP_GRID, CHIP_GRID_RPM,
    CHIP_STATES,
};
use camsim_core::{LiftProfile, Real, Scene};
use camsim_firmware::memory::{paint_stack, MemoryReport};
use camsim_firmware::timing::InstrCounter;
use camsim_firmware::workload;
use camsim_firmware::{exit_failure, exit_success};
use cortex_m_rt::entry;

/// Measures instructions per RHS and per revolution (at [`workload::NOMINAL_RPM`]) of
/// scene `S`'s model (`N = S::N`) with the roller on `profile`. The revolution is the
/// integration and its sampling; building the model (validating the design, once per
/// speed) is timed apart (`model_build_instr`).
fn measure_model<S: Scene, const N: usize, P: LiftProfile<f32> + Copy>(
    counter: &InstrCounter,
    name: &str,
    profile: P,
) -> Option<(u64, u64)> {
    let (model, y) = workload::rhs_probe::<S, N, P>(profile)?;
    let (checksum, rhs_instr) =
        counter.measure(|| workload::evaluate_rhs(&model, &y, workload::RHS_REPS));
    let per_rhs = rhs_instr / u64::from(workload::RHS_REPS);
    let (model, build_instr) =
        counter.measure(|| workload::revolution_model::<S, N, P>(profile, workload::NOMINAL_RPM));
    let model = model?;
    let (rev, rev_instr) = counter.measure(|| workload::simulate_revolution(&model));
    let rev = rev?;
    defmt::info!(
        "model {=str} states={=usize} instr_per_rhs={=u64} instr_per_rev={=u64} rev_rhs_evals={=u32} rev_steps={=u32} instr_per_rev_per_eval={=u64} model_build_instr={=u64} rhs_checksum={=f32} load_in={=f32} load_in_per_s={=f32} load_bits={=u32:#010x}",
        name, N, per_rhs, rev_instr, rev.rhs_evals, rev.steps,
        rev_instr / u64::from(rev.rhs_evals.max(1)), build_instr, checksum, rev.load_in, rev.load_in_per_s, rev.load_in.to_bits()
    );
    Some((per_rhs, rev_instr))
}

/// One revolution of the chip's model at `rpm` (the table's top speed): its instructions,
/// evaluations and real-time factor (simulated time 60/rpm s over the instructions at
/// 168 MHz).
fn measure_at_speed<P: LiftProfile<f32> + Copy>(counter: &InstrCounter, rpm: f32, profile: P) {
    let model = workload::revolution_model::<ChipScene, CHIP_STATES, P>(profile, rpm);
    let (rev, rev_instr) =
        counter.measure(|| model.as_ref().and_then(workload::simulate_revolution));
    let Some(rev) = rev else {
        defmt::error!("chip model at {=f32} rpm failed", rpm);
        exit_failure()
    };
    let factor = CHIP_CLOCK_HZ as f32 * 60.0 / rpm / rev_instr.max(1) as f32;
    defmt::info!(
        "model chip at rpm={=f32} instr_per_rev={=u64} rev_rhs_evals={=u32} rev_steps={=u32} instr_per_rev_per_eval={=u64} realtime_factor={=f32}",
        rpm, rev_instr, rev.rhs_evals, rev.steps, rev_instr / u64::from(rev.rhs_evals.max(1)), factor
    );
}

/// Instructions per call of the elementary functions an RHS uses (mean of 100 calls,
/// loop overhead included); libm's f32 functions run in software on the M4F.
fn measure_math(counter: &InstrCounter) {
    use core::hint::black_box;
    let x = black_box(0.7f32);
    // Every result goes through `black_box`: a pure call whose result is unused is
    // otherwise removed (which made `sqrt` look like 9 instructions).
    let (_, sc) = counter.measure(|| {
        black_box((0..100).fold(0.0f32, |a, i| {
            let (s, c) = black_box(x + i as f32 * 1e-3).sin_cos();
            a + s + c
        }))
    });
    let (_, at) = counter.measure(|| {
        black_box((0..100).fold(0.0f32, |a, i| a + black_box(x + i as f32 * 1e-3).atan2(1.3)))
    });
    let (_, sq) = counter.measure(|| {
        black_box((0..100).fold(0.0f32, |a, i| a + black_box(x + i as f32 * 1e-3).sqrt()))
    });
    let (_, dv) = counter.measure(|| {
        black_box((0..100).fold(0.0f32, |a, i| a + 1.0 / black_box(x + i as f32 * 1e-3)))
    });
    defmt::info!(
        "math instr_per_call sin_cos={=u64} atan2={=u64} sqrt={=u64} loop_with_divide={=u64}",
        sc / 100,
        at / 100,
        sq / 100,
        dv / 100
    );
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
    defmt::info!("scene={=str}", workload::SCENE_NAME);

    // The full 22-state model for comparison (closed-form lift), then the chip's model on
    // its lift table (the budget line) at 800 rpm and at the table's top speed. (A second
    // chip model on the closed-form lift does not fit the flash beside both.) With a scene
    // compiled in, the chip's model alone: its design decoder (postcard) and the lift table
    // in flash leave no room for the full model in the 128 KiB budget (docs/FIRMWARE.md).
    #[cfg(not(camsim_scene))]
    if measure_model::<camsim_core::RegulatedFull, { camsim_core::RegulatedFull::N }, _>(
        &counter,
        "full",
        camsim_core::TheoreticalLift,
    )
    .is_none()
    {
        defmt::error!("full model measurement failed");
        exit_failure()
    }
    let table = workload::chip_table();
    defmt::info!(
        "lift table knots={=usize} max_interval_deg={=f32} bytes={=usize}",
        table.knots(),
        table.max_interval().to_degrees(),
        workload::FlashTable::bytes()
    );
    let Some((instr_per_rhs, rev_instr)) =
        measure_model::<ChipScene, CHIP_STATES, _>(&counter, "chip", table)
    else {
        defmt::error!("chip model measurement failed");
        exit_failure()
    };
    let top = CHIP_GRID_RPM[CHIP_GRID - 1] as f32;
    measure_at_speed(&counter, top, table);
    measure_math(&counter);

    // Memory of THIS image (both models and the probes), for the llvm-size cross-check.
    let mem = MemoryReport::measure();
    if mem.stack_overflowed() {
        exit_failure()
    }
    // Real time at 800 rpm is 60/800 s a revolution; at 168 MHz and one instruction a
    // cycle a revolution's instructions take rev_instr / 168e6 s (camsim_chip::realtime_factor).
    let line = BudgetLine {
        memory: MemoryFields {
            flash_bytes: mem.flash_bytes,
            ram_static_bytes: mem.ram_static_bytes,
            stack_peak_bytes: mem.stack_peak_bytes,
            ram_bytes: mem.ram_bytes(),
        },
        instr_per_rhs,
        instr_per_rev: rev_instr,
        realtime_factor: realtime_factor(rev_instr),
    };
    defmt::info!("{}", line);
    exit_success()
}
