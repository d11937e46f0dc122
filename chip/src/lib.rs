//! The cam predictor chip's product configuration, in ONE place read by the firmware and
//! by `camsim predict` (host parity): the scene, solver settings, speed grid, jump-onset
//! resolution, alarm thresholds and the scripted speed profile of the QEMU run. The
//! predictor itself (table, observer, alarm, onset search) is `camsim_core`'s.
//!
//! Chosen by measurement (the figures are in firmware/README.md): the vertical 16-state
//! model, whose vertical motion is that of the full 22-state one (docs/MODEL.md §2) at
//! less cost, and rtol 1e-3 (the thesis ran at 2 %) with atol 1e-8 in (docs/MODEL.md §5.12).

#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

use camsim_core::{
    steady_state_at, CamModel, Design, JumpAlarm, PredictionTable, Real, RegulatedVertical, Result,
    Scene, SolverSettings, SpeedSource, Start, SteadyState,
};

/// The chip's scene: regulated drive, vertical DOFs only.
pub type ChipScene = RegulatedVertical;
/// State size of the chip's model (6 + 2·5 = 16).
pub const CHIP_STATES: usize = <ChipScene as Scene>::N;
/// The chip's model type.
pub type ChipModel<T> = CamModel<T, ChipScene, CHIP_STATES>;
/// Number of grid speeds of the boot-time table.
pub const CHIP_GRID: usize = 10;
/// Grid speeds of the boot-time table, rpm (ascending; denser towards the reference
/// design's jump onset, which lies between 900 and 950 rpm with the study spring).
pub const CHIP_GRID_RPM: [f64; CHIP_GRID] = [
    300.0, 400.0, 500.0, 600.0, 700.0, 750.0, 800.0, 850.0, 900.0, 950.0,
];
/// Upper limit of the jump search when no grid speed jumps, rpm.
pub const CHIP_MAX_RPM: f64 = 1200.0;
/// Resolution of the jump-onset bisection, rpm.
pub const CHIP_RESOLUTION_RPM: f64 = 1.0;
/// Speeds between grid points where the boot check compares the interpolated
/// prediction with a direct simulation, rpm.
pub const CHIP_CHECK_RPM: [f64; 3] = [450.0, 650.0, 825.0];
/// The jump alarm turns on at this speed margin (rpm) or less.
pub const CHIP_ALARM_ON_MARGIN_RPM: f64 = 50.0;
/// An active jump alarm turns off once the speed margin exceeds this (rpm).
pub const CHIP_ALARM_OFF_MARGIN_RPM: f64 = 100.0;

/// The design compiled into the chip and run by the host's parity check when no scene
/// is chosen: the reference design of VI.1.
pub fn chip_design<T: Real>() -> Design<T> {
    Design::reference()
}

/// A scene file's design (`Design<f64>`, as `camsim_scene_file` reads it) in the chip's
/// precision `T`: [`Design::cast`], then [`Design::validate`] in `T`. The firmware's
/// build script (`CAMSIM_SCENE`) and `camsim predict --scene` both call this, so the
/// chip and the host's parity check run the same bits.
pub fn chip_design_from<T: Real>(scene: &Design<f64>) -> Result<Design<T>> {
    let d = scene.cast::<T>()?;
    d.validate()?;
    Ok(d)
}

/// Solver settings of the chip's predictor: rtol 1e-3, atol 1e-8 in, at most 1/500
/// revolution per double step, from static equilibrium. The thesis's all-zero start
/// leaves a start-up impact whose roller ringing is still there in the second revolution,
/// so it is not a steady state (docs/MODEL.md §5.11, §7.3; its effect on the jump speed
/// is measured in firmware/README.md).
pub fn chip_solver_settings<T: Real>() -> SolverSettings<T> {
    SolverSettings {
        rtol: T::from_f64(1e-3),
        atol: T::from_f64(1e-8),
        max_step_fraction: T::from_f64(1.0 / 500.0),
        max_steps_per_rev: 2_000_000,
        start: Start::Static,
    }
}

/// [`CHIP_GRID_RPM`] in `T`.
pub fn chip_grid_rpm<T: Real>() -> [T; CHIP_GRID] {
    CHIP_GRID_RPM.map(T::from_f64)
}

/// Builds the chip's prediction table for `design` (the boot-time computation).
pub fn chip_prediction_table<T: Real>(design: &Design<T>) -> Result<PredictionTable<T, CHIP_GRID>> {
    PredictionTable::build::<ChipScene, CHIP_STATES>(
        design,
        chip_grid_rpm(),
        T::from_f64(CHIP_MAX_RPM),
        T::from_f64(CHIP_RESOLUTION_RPM),
        &chip_solver_settings(),
    )
}

/// The direct steady state at `rpm` with the chip's model (for the interpolation check).
pub fn chip_steady_state<T: Real>(design: &Design<T>, rpm: T) -> Result<SteadyState<T>> {
    steady_state_at::<T, ChipScene, CHIP_STATES>(design, rpm, &chip_solver_settings())
}

/// The chip's jump alarm (thresholds [`CHIP_ALARM_ON_MARGIN_RPM`], [`CHIP_ALARM_OFF_MARGIN_RPM`]).
pub fn chip_alarm<T: Real>() -> Result<JumpAlarm<T>> {
    JumpAlarm::new(
        T::from_f64(CHIP_ALARM_ON_MARGIN_RPM),
        T::from_f64(CHIP_ALARM_OFF_MARGIN_RPM),
    )
}

/// Scripted cam speed for the QEMU run and the host: a ramp 300 -> 800 rpm in 25 rpm
/// steps, a step up to 925 rpm (across the reference design's jump onset), 950 rpm, then
/// back down to 300 rpm in 25 rpm steps (49 samples, one per revolution).
#[derive(Clone, Debug)]
pub struct ScriptedProfile {
    next: Option<i32>,
    rising: bool,
}

impl ScriptedProfile {
    /// Lowest speed, rpm.
    pub const LOW_RPM: i32 = 300;
    /// Highest speed, rpm.
    pub const HIGH_RPM: i32 = 950;
    /// Ramp increment per sample, rpm.
    pub const STEP_RPM: i32 = 25;
    /// Speed after which the step up happens, rpm.
    pub const STEP_AT_RPM: i32 = 800;
    /// Speed the step goes to, rpm.
    pub const STEP_TO_RPM: i32 = 925;
    /// Samples in the whole profile: 21 (300..=800) + 2 (925, 950) + 26 (925..=300).
    pub const SAMPLES: usize = 49;

    /// The profile from its first sample.
    pub fn new() -> Self {
        Self {
            next: Some(Self::LOW_RPM),
            rising: true,
        }
    }
}

impl Default for ScriptedProfile {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Real> SpeedSource<T> for ScriptedProfile {
    fn next_rpm(&mut self) -> Option<T> {
        let rpm = self.next?;
        self.next = if self.rising {
            if rpm == Self::STEP_AT_RPM {
                Some(Self::STEP_TO_RPM)
            } else if rpm >= Self::HIGH_RPM {
                self.rising = false;
                Some(rpm - Self::STEP_RPM)
            } else {
                Some(rpm + Self::STEP_RPM)
            }
        } else if rpm <= Self::LOW_RPM {
            None
        } else {
            Some(rpm - Self::STEP_RPM)
        };
        Some(T::from_i32(rpm))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profile_has_the_documented_samples() {
        let mut p = ScriptedProfile::new();
        let mut v = [0.0f64; 64];
        let mut n = 0;
        while let Some(r) = SpeedSource::<f64>::next_rpm(&mut p) {
            v[n] = r;
            n += 1;
        }
        assert_eq!(n, ScriptedProfile::SAMPLES);
        assert_eq!(&v[..3], &[300.0, 325.0, 350.0]);
        assert_eq!(&v[20..22], &[800.0, 925.0]); // the step
        assert_eq!(v[22], 950.0);
        assert_eq!(v[23], 925.0);
        assert_eq!(v[48], 300.0);
    }

    #[test]
    fn grid_ascends_and_brackets_the_checks() {
        assert!(CHIP_GRID_RPM.windows(2).all(|w| w[0] < w[1]));
        for c in CHIP_CHECK_RPM {
            assert!(
                !CHIP_GRID_RPM.contains(&c)
                    && c > CHIP_GRID_RPM[0]
                    && c < CHIP_GRID_RPM[CHIP_GRID - 1]
            );
        }
        assert!(chip_alarm::<f32>().is_ok());
    }
}
