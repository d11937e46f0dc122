//! The chip's predictor run on the host: the boot-time table, the interpolation checks
//! and the scripted machine's readings, in `T` (`f32` as the chip computes, or `f64`),
//! for the reference design or a scene file's, on the theoretical cam or a measured
//! profile's deviation knots ([`ProfileKnots`], read as the firmware's build script reads
//! `CAMSIM_PROFILE`).

use anyhow::{bail, Result};

use camsim_chip::{
    chip_design, chip_design_from, ChipConfig, ChipDeviation, ChipMonitor, ChipStep, ChipTable,
    ScriptedPulseTrain, CHIP_CHECK_RPM, CHIP_GRID, CHIP_PROFILE_MAX_KNOTS, CHIP_TICK_HZ,
};
use camsim_core::{Design, LiftProfile, Real, SpeedPrediction, SteadyState, TheoreticalLift};

/// A measured profile's deviation knots as the chip carries them, in `f64` before the
/// narrowing (`camsim_scene_file::measured::Measured::deviation_knots`).
#[derive(Clone, Debug, PartialEq)]
pub struct ProfileKnots {
    /// Knots, rad: one revolution, the closing knot included.
    pub knots_rad: Vec<f64>,
    /// Deviation at the knots, in (the last repeats the first).
    pub values_in: Vec<f64>,
}

impl ProfileKnots {
    /// Reads a measured file as the firmware's build script does (`CAMSIM_PROFILE`): at
    /// most [`CHIP_PROFILE_MAX_KNOTS`] − 1 rows, the deviation on `design` (the scene's,
    /// in f64), at most [`CHIP_PROFILE_MAX_KNOTS`] knots.
    pub fn load(path: &std::path::Path, design: &Design<f64>) -> Result<Self> {
        let m = camsim_scene_file::measured::load_limited(path, CHIP_PROFILE_MAX_KNOTS - 1)
            .map_err(anyhow::Error::msg)?;
        let (knots_rad, values_in) = m
            .deviation_knots(design)
            .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        if knots_rad.len() > CHIP_PROFILE_MAX_KNOTS {
            bail!(
                "{}: the deviation has {} knots, more than the chip's {CHIP_PROFILE_MAX_KNOTS} (a radius profile's envelope has 8 a row)",
                path.display(),
                knots_rad.len()
            );
        }
        Ok(Self {
            knots_rad,
            values_in,
        })
    }
}

/// One direct simulation between grid points against the interpolated prediction.
#[derive(Clone, Copy, Debug)]
pub struct InterpCheck<T> {
    /// Speed, rpm.
    pub rpm: T,
    /// The table's interpolated prediction.
    pub interpolated: SpeedPrediction<T>,
    /// The model run directly at this speed.
    pub direct: SteadyState<T>,
}

/// Everything the predictor computes for the chip's scene.
#[derive(Clone, Debug)]
pub struct Prediction<T> {
    /// The boot-time table.
    pub table: camsim_core::PredictionTable<T, CHIP_GRID>,
    /// The interpolation checks at `CHIP_CHECK_RPM`.
    pub checks: Vec<InterpCheck<T>>,
    /// Every speed reading of the scripted machine, in order, with the prediction (at a
    /// vouched speed) and the alarm state after it.
    pub samples: Vec<ChipStep<T>>,
}

/// Runs the chip's predictor (shared scene, scripted machine) in `T` for the reference
/// design, or for a scene file's design (`Design<f64>`, as the firmware's build script
/// reads `CAMSIM_SCENE`): `camsim_chip::chip_design_from` is the conversion the
/// firmware's image carries, so the bits agree.
pub fn compute<T: Real>(
    scene: Option<&Design<f64>>,
    profile: Option<&ProfileKnots>,
) -> Result<Prediction<T>> {
    let design = match scene {
        Some(d) => chip_design_from::<T>(d).map_err(|e| {
            let why = camsim_scene_file::refusal("design", e);
            anyhow::anyhow!("scene in {}: {why}", std::any::type_name::<T>())
        })?,
        None => chip_design::<T>(),
    };
    match profile {
        None => compute_on(&design, TheoreticalLift),
        Some(k) => {
            // The firmware's narrowing (build.rs) and spline (boot): the same calls.
            let knots: Vec<T> = k.knots_rad.iter().map(|x| T::from_f64(*x)).collect();
            let values: Vec<T> = k.values_in.iter().map(|x| T::from_f64(*x)).collect();
            let mut dev = Box::new(ChipDeviation::<T, CHIP_PROFILE_MAX_KNOTS>::EMPTY);
            dev.refit_periodic(&knots, &values).map_err(|e| {
                anyhow::anyhow!(
                    "the measured profile in {}: {e}",
                    std::any::type_name::<T>()
                )
            })?;
            compute_on(&design, &*dev)
        }
    }
}

/// [`compute`] for a design whose roller rides on `profile`.
fn compute_on<T: Real, P: LiftProfile<T> + Copy>(
    design: &Design<T>,
    profile: P,
) -> Result<Prediction<T>> {
    // The lift table the firmware's build script fills into the chip's flash
    // (camsim_chip::ChipConfig::tabulate).
    let mut lift_table = Box::new(ChipTable::<T>::EMPTY);
    let chip = ChipConfig::new(design)
        .on(profile)
        .tabulate(&mut lift_table)
        .map_err(|e| anyhow::anyhow!("the lift table (built into the chip's flash): {e}"))?;
    let table = chip
        .prediction_table()
        .map_err(|e| anyhow::anyhow!("the predictor's table (at boot on the chip): {e}"))?;
    let mut checks = Vec::new();
    for r in CHIP_CHECK_RPM {
        let rpm = T::from_f64(r);
        let direct = chip
            .steady_state(rpm)
            .map_err(|e| anyhow::anyhow!("the interpolation check's direct run at {r} rpm: {e}"))?;
        checks.push(InterpCheck {
            rpm,
            interpolated: table.predict(rpm),
            direct,
        });
    }
    // The firmware's loop (src/bin/predictor.rs): the same train, monitor and steps.
    let mut monitor =
        ChipMonitor::<T>::new(CHIP_TICK_HZ).map_err(|e| anyhow::anyhow!("the monitor: {e}"))?;
    let mut train = ScriptedPulseTrain::chip();
    let mut samples = Vec::new();
    while !train.finished() {
        if let Some(step) = monitor.step(&table, &mut train) {
            samples.push(step);
        }
    }
    Ok(Prediction {
        table,
        checks,
        samples,
    })
}
