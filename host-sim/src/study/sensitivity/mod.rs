//! The sensitivity study of VI.4.3 (Tables VI.11-VI.12) and, beyond the thesis, every
//! design key's elasticity.
//!
//! Three groups of dynamic characteristics ([`Group`]) are each changed together by
//! −30, −10, +10 and +30 % ([`scaled`], the one place that says what a group holds;
//! docs/MODEL.md §11), on the theoretical cam and on one actual cam (sample 0 of the
//! master seed, built once by [`crate::actual::build_profile`] from the baseline design:
//! the groups touch neither the program nor the geometry, so every case rides on the
//! same profile). Each case reports, over the whole of revolution 2 ([`Outputs`]), the
//! RMS of the load's displacement, velocity and acceleration deviations from the
//! theoretical response, the RMS of the cam's angular-velocity deviation from ω0, the
//! time-averaged contact stress, and whether the follower separated.
//!
//! `--per-key` ([`per_key()`]): d ln(output) / d ln(key) by central differences at ±1 %
//! of every numeric design key ([`key_scaled`]) on the five outputs (theoretical cam)
//! and on the jump-onset speed ([`crate::study::jump_speed::find`]), ranked by the
//! onset's.
//!
//! The study takes a typed [`Spec`] and returns a [`SensitivityReport`] (its text in
//! [`text`]); `camsim sensitivity` (crate::cmd::sensitivity) builds the spec from its
//! arguments, prints the report and draws its figure.

use std::sync::Arc;

use anyhow::Result;
use serde::Serialize;

use crate::actual::{self, Cams, ProfileStats};
use crate::sim::RunSpec;

pub mod cases;
pub mod outputs;
pub mod per_key;
#[cfg(test)]
mod tests;
pub mod text;

pub use cases::*;
pub use outputs::*;
pub use per_key::*;
pub(crate) use text::{fmt_value, output_unit, pct};

/// The changes of every group, % (VI.4.3).
pub const CHANGES_PCT: [i32; 4] = [-30, -10, 10, 30];
/// The changes of `--quick`, %.
pub const QUICK_CHANGES_PCT: [i32; 2] = [-30, 30];
/// The relative step of `--per-key`'s central differences (±1 %).
pub const KEY_STEP: f64 = 0.01;
/// Resolution of `--per-key`'s jump-onset searches, rpm (`--quick`: [`QUICK_ONSET_RESOLUTION_RPM`]).
/// At a 900 rpm onset and ±1 % steps it resolves an elasticity to 0.01 / 900 / 0.02 ≈ 6e-4.
pub const ONSET_RESOLUTION_RPM: f64 = 0.01;
/// `--quick`'s onset resolution, rpm.
pub const QUICK_ONSET_RESOLUTION_RPM: f64 = 1.0;
/// The revolution the study measures (the thesis's steady state, as the other studies).
pub const REVOLUTION: u32 = 2;

/// What the study runs.
#[derive(Clone, Debug)]
pub struct Spec {
    /// The baseline run: the scene at the study's speed, revolution [`REVOLUTION`] (the
    /// vertical model with `quick`), validated.
    pub run: RunSpec,
    /// The actual cam's tolerances and interval (sample 0 of their seed is the study's
    /// actual cam).
    pub actual: Cams,
    /// `--quick`: changes of ±30 % only ([`QUICK_CHANGES_PCT`]) and a 1 rpm onset resolution.
    pub quick: bool,
    /// Also every design key's elasticity ([`per_key()`]).
    pub per_key: bool,
    /// Worker threads (the result does not depend on them).
    pub threads: usize,
}

/// What `camsim sensitivity` prints.
#[derive(Clone, Debug, Serialize)]
pub struct SensitivityReport {
    /// Cam speed, rpm.
    pub rpm: f64,
    /// Whether the vertical scene ran (--quick).
    pub quick: bool,
    /// The revolution measured.
    pub revolution: u32,
    /// The actual cam (sample 0 of the master seed).
    pub actual_profile: ProfileStats,
    /// The baseline on each cam (change 0).
    pub baseline: Vec<Case>,
    /// Every group, change and cam whose run stayed in the model's valid range.
    pub cases: Vec<Case>,
    /// The cases whose run left the model's valid range (docs/MODEL.md §3.20), in the
    /// study's order: each a jump (the follower had separated first) or not workable.
    pub not_workable: Vec<NotWorkableCase>,
    /// `--per-key`'s elasticities.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub per_key: Option<PerKey>,
    /// Wall-clock time, s.
    pub wall_s: f64,
}

/// Runs the study: the cases of every group on both cams, then (`per_key`) the
/// elasticities.
pub fn report(spec: &Spec) -> Result<SensitivityReport> {
    let t0 = std::time::Instant::now();
    let mut actual_args = spec.actual.clone();
    actual_args.actual = true;
    let (dev, profile) = actual::build_profile(&spec.run.design, &actual_args, 0)?;
    let dev = Arc::new(dev);
    let changes: &[i32] = if spec.quick {
        &QUICK_CHANGES_PCT
    } else {
        &CHANGES_PCT
    };
    let (baseline, cases, not_workable) = run_cases(&spec.run, &dev, changes, spec.threads)?;
    let per_key = if spec.per_key {
        let res = if spec.quick {
            QUICK_ONSET_RESOLUTION_RPM
        } else {
            ONSET_RESOLUTION_RPM
        };
        Some(per_key(&spec.run, res, spec.threads, true)?)
    } else {
        None
    };
    Ok(SensitivityReport {
        rpm: camsim_core::rad_per_s_to_rpm(spec.run.design.omega0),
        quick: spec.quick,
        revolution: REVOLUTION,
        actual_profile: profile,
        baseline,
        cases,
        not_workable,
        per_key,
        wall_s: t0.elapsed().as_secs_f64(),
    })
}
