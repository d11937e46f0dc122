//! The firmware's cam-timing and jump predictor run on the host with the same scene (the
//! `camsim-chip` crate), the same scripted machine (`CHIP_SCRIPT`'s index pulses through
//! the chip's `ChipMonitor`, as the QEMU image feeds them) and the same core code: the
//! boot-time table, the interpolation check, and for every speed reading (a vouched speed,
//! or a fault: out of the grid, a rejected pulse, the speed lost, an acquisition) the
//! prediction and the alarm state.
//!
//! In `f32` it computes exactly as the chip does (same libm code, no FMA contraction in
//! Rust, IEEE single precision on both SSE and the M4F's FPU), so the firmware's decoded
//! defmt log can be checked bit for bit ([`parity`]): every line of the log starting with
//! `parity ` must equal the host's line at the same position.
//!
//! On a measured profile the roller rides as on the firmware built with
//! `CAMSIM_PROFILE=FILE.csv`: the same reader (`camsim_scene_file::measured`, at most
//! `CHIP_PROFILE_MAX_KNOTS - 1` rows), the same deviation knots on the scene's `f64`
//! design, narrowed to `T` and splined by `DeviatedLift::refit_periodic`, the chip's
//! `ChipDeviation` ([`prediction`]).
//!
//! The study takes a typed [`Spec`] and returns a [`PredictReport`] (its rows in [`rows`],
//! its text in [`text`]); `camsim predict` (crate::cmd::predict) builds the spec from its
//! arguments and prints the report or the parity check's result.

use anyhow::Result;

use camsim_core::Design;

use crate::units::Units;

pub mod parity;
pub mod prediction;
pub mod report;
pub mod rows;
pub mod text;

pub use parity::{check_parity, log_parity_lines, parity_lines};
pub use prediction::{compute, InterpCheck, Prediction, ProfileKnots};
pub use report::{
    AlarmTransition, CheckBits, CheckRow, FaultRow, Num, PredictReport, SampleBits, SampleRow,
    SceneReport, TableBits, TableRow,
};
pub use text::render_text;

/// The scene name of the report when no scene file is given.
pub const REFERENCE_SCENE: &str = "reference";

/// A measured profile the roller rides on: its file's name and its deviation knots.
#[derive(Clone, Debug, PartialEq)]
pub struct Measured {
    /// The file, as the report names it.
    pub file: String,
    /// Its deviation knots, read as the firmware's build script reads them.
    pub knots: ProfileKnots,
}

/// What the predictor runs.
#[derive(Clone, Debug, PartialEq)]
pub struct Spec {
    /// Compute in `f32` as the chip does (else `f64`).
    pub single: bool,
    /// The scene file's design (None: the reference design, `camsim_chip::chip_design`).
    pub scene: Option<Design<f64>>,
    /// The scene as the report names it: its file, or [`REFERENCE_SCENE`].
    pub scene_name: String,
    /// The measured profile (None: the theoretical cam).
    pub measured: Option<Measured>,
}

impl Spec {
    /// The prediction of the spec's scene and profile, computed in `T`.
    fn compute<T: camsim_core::Real>(&self) -> Result<Prediction<T>> {
        compute::<T>(
            self.scene.as_ref(),
            self.measured.as_ref().map(|m| &m.knots),
        )
    }
}

/// Runs the predictor in the spec's precision and reports it. A table with a timing point
/// the follower never crossed is refused (nothing reported), its force in `units`.
pub fn report(spec: &Spec, units: Units) -> Result<PredictReport> {
    let measured = spec
        .measured
        .as_ref()
        .map(|m| (m.file.as_str(), m.knots.knots_rad.len()));
    let name = spec.scene_name.as_str();
    let report = if spec.single {
        PredictReport::of(&spec.compute::<f32>()?, true, name, measured)
    } else {
        PredictReport::of(&spec.compute::<f64>()?, false, name, measured)
    };
    report::ensure_reached(&report, units)?;
    Ok(report)
}

/// The `parity ...` lines of the spec's scene and profile run in `f32`, the chip's (the
/// spec's precision aside): what the firmware's log must repeat bit for bit.
pub fn host_parity(spec: &Spec) -> Result<Vec<String>> {
    Ok(parity_lines(&spec.compute::<f32>()?))
}
