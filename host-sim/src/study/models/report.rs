//! The models study's report: one row per scene and tolerance, and the reference.

use camsim_core::TIMING_POINTS;
use serde::Serialize;

use crate::units::{Acceleration, Force};

/// One scene's row.
#[derive(Clone, Debug, Serialize)]
pub struct SceneRow {
    /// Scene name.
    pub scene: String,
    /// The follower's model.
    pub follower: &'static str,
    /// Degrees of freedom kept as states.
    pub dofs: usize,
    /// State length N.
    pub states: usize,
    /// `size_of` the model (f64), bytes.
    pub model_bytes: usize,
    /// `size_of` England's solver (f64), bytes.
    pub solver_bytes: usize,
    /// `size_of` the model in f32 (the chip's precision), bytes.
    pub model_f32_bytes: usize,
    /// `size_of` England's solver in f32, bytes.
    pub solver_f32_bytes: usize,
    /// Relative tolerance of the row.
    pub rtol: f64,
    /// Accepted double steps per revolution (mean of the 2).
    pub steps_per_rev: f64,
    /// Rejected of attempted steps, %.
    pub rejected_pct: f64,
    /// Right-hand-side evaluations per revolution.
    pub rhs_evals_per_rev: f64,
    /// Host time of the 2 revolutions of one steady-state evaluation (the chip's pipeline,
    /// `steady_state`, with the model built beforehand), median, ms.
    pub ms_2rev: f64,
    /// Largest spectral radius of the scene's Jacobian over revolution 2, 1/s.
    pub stiffest_rad_s: f64,
    /// The stiffest eigenvalue there, (Re, Im), 1/s.
    pub stiffest_eigenvalue: [f64; 2],
    /// Fewest England double steps per revolution its eigenvalues allow.
    pub limit_steps_per_rev: f64,
    /// Jump-onset speed, rpm.
    pub onset_rpm: f64,
    /// Its error against the reference's, %.
    pub onset_err_pct: f64,
    /// The scene's own onset, converged (rtol [`super::CONVERGED_RTOL`]): the model's error
    /// without the solver's, rpm.
    pub model_onset_rpm: f64,
    /// Its error against the reference's, %.
    pub model_onset_err_pct: f64,
    /// Smallest contact force of revolution 2, lb.
    pub fmin_lb: Force,
    /// Its error, lb.
    pub fmin_err_lb: Force,
    /// Largest timing error difference at the 6 lift points, degrees of cam angle.
    pub timing_err_deg: f64,
    /// RMS error of the load acceleration over revolution 2 (every 0.5°), in/s².
    pub acc_rms_err: Acceleration,
    /// ... over the signal's RMS.
    pub acc_rms_rel: f64,
    /// Accurate enough for the jump-onset speed ([`super::enough::ONSET_REL`]).
    pub ok_onset: bool,
    /// ... for the smallest contact force ([`super::enough::FMIN_LB`]).
    pub ok_fmin: bool,
    /// ... for the timing at the lift points ([`super::enough::TIMING_DEG`]).
    pub ok_timing: bool,
    /// ... for the acceleration waveform ([`super::enough::ACC_REL`]).
    pub ok_acc: bool,
}

/// The reference (the full model at [`super::REFERENCE_RTOL`]).
#[derive(Clone, Debug, Serialize)]
pub struct SceneReference {
    /// Relative tolerance.
    pub rtol: f64,
    /// Jump-onset speed, rpm.
    pub onset_rpm: f64,
    /// Smallest contact force of revolution 2, lb.
    pub fmin_lb: Force,
    /// Timing errors at the lift points against the program, degrees.
    pub timing_deg: [f64; TIMING_POINTS],
    /// RMS of the load acceleration over revolution 2, in/s².
    pub acc_rms: Acceleration,
}

/// `camsim models`'s report.
#[derive(Clone, Debug, Serialize)]
pub struct ScenesReport {
    /// Cam speed, rpm.
    pub rpm: f64,
    /// Quick mode.
    pub quick: bool,
    /// The reference.
    pub reference: SceneReference,
    /// One row per scene and tolerance.
    pub rows: Vec<SceneRow>,
    /// Whole command, s.
    pub seconds: f64,
}
