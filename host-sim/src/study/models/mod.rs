//! Which scene is accurate enough for which question (`camsim models`). Every scene of
//! the regulated drive (the full 22-state model, the vertical one, and the reduced
//! followers of docs/MODEL.md §10) at the chip's tolerance, against the full model at a
//! tight one: state size, memory, work and time per revolution, the stiffest eigenvalue
//! left (what bounds the step), and the errors on the jump-onset speed, the timing at the
//! firmware's lift points, the smallest contact force and the load's acceleration.
//!
//! The study takes a [`Spec`] and returns a [`ScenesReport`] (its rows measured in
//! `rows.rs`, its text in `text.rs`); `camsim models` (crate::cmd::models) builds the spec
//! from its arguments and prints the report.

use std::time::Instant;

use anyhow::Result;
use camsim_core::{FollowerModel, SolverSettings, Start, StepRule};

mod report;
mod rows;
mod text;

pub use report::{SceneReference, SceneRow, ScenesReport};
use rows::{follower_row, reference_truth, row, Full, Row, NF};

/// What the study measures: the cam speed of the work, time and error columns, and the
/// quick mode (fewer timed repetitions, a coarser jump-onset bisection).
#[derive(Clone, Copy, Debug)]
pub struct Spec {
    /// Cam speed, rpm.
    pub rpm: f64,
    /// Quick mode (CI).
    pub quick: bool,
    /// Show a progress bar (on a terminal).
    pub progress: bool,
}

/// The questions and what "accurate enough" means for each (the thresholds, stated once).
pub mod enough {
    /// Jump-onset speed within this fraction of the full model's.
    pub const ONSET_REL: f64 = 0.01;
    /// Smallest contact force within this many lb (2 % of the 50 lb preload).
    pub const FMIN_LB: f64 = 1.0;
    /// Timing at the lift points within this many degrees of cam angle.
    pub const TIMING_DEG: f64 = 0.01;
    /// Load acceleration: RMS error within this fraction of the signal's RMS.
    pub const ACC_REL: f64 = 0.01;
}

/// The tolerance every scene runs at: the chip's (rtol 1e-3, atol 1e-8 in), static
/// start, with a largest step of 1/100 revolution so the controller, not the cap,
/// decides (the reduced scenes take steps longer than the default 1/2000).
pub fn scene_settings(rtol: f64) -> SolverSettings<f64> {
    SolverSettings {
        rtol,
        atol: if rtol < 1e-6 { 1e-3 * rtol } else { 1e-8 },
        max_step_fraction: 0.01,
        max_steps_per_rev: 2_000_000,
        start: Start::Static,
        // The chip's control too: at these tolerances accuracy holds the step, and the
        // scenes' adequacy figures stay those of the thesis's rule.
        step_control: StepRule::Thesis,
        method: camsim_core::Method::England,
    }
}

/// The reference's tolerance (the full model).
pub const REFERENCE_RTOL: f64 = 1e-9;
/// The tolerance of each scene's converged onset (its model error alone).
pub const CONVERGED_RTOL: f64 = 1e-6;
/// The tolerances of the rows: the chip's and ten times looser.
pub const ROW_RTOLS: [f64; 2] = [1e-3, 1e-2];

/// Measures every scene, with a progress bar on a terminal (`spec.progress`).
pub fn report(spec: &Spec) -> Result<ScenesReport> {
    let Spec {
        rpm,
        quick,
        progress,
    } = *spec;
    let start = Instant::now();
    // The reference (its run, steady state and onset), then every row.
    let bar = crate::study_limits::progress_bar(
        1 + (ROW_RTOLS.len() * (1 + FollowerModel::ALL.len())) as u64,
        progress,
        "{elapsed_precise} [{bar:40}] {pos}/{len} scenes and tolerances, eta {eta}",
    );
    let resolution = if quick { 0.5 } else { 0.05 };
    let repeat = if quick { 3 } else { 11 };
    let truth = reference_truth(rpm, resolution)?;
    bar.inc(1);
    let mut rows = Vec::new();
    for rtol in ROW_RTOLS {
        let at = |follower| Row {
            follower,
            rtol,
            truth: &truth,
            rpm,
            repeat,
        };
        rows.push(row::<Full, NF>(at(FollowerModel::Full))?);
        bar.inc(1);
        for follower in FollowerModel::ALL {
            rows.push(follower_row(at(follower))?);
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    Ok(ScenesReport {
        rpm,
        quick,
        reference: truth.reference,
        rows,
        seconds: start.elapsed().as_secs_f64(),
    })
}
