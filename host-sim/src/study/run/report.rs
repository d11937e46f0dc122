//! `camsim run`'s report: the per-period table of every revolution, the jumps, the
//! solver statistics, the verdict and the run time ([`RunReport`]; its text in
//! [`super::text`]).

use serde::Serialize;

use crate::actual::ProfileStats;
use crate::measured::MeasuredStats;
use crate::sim::{self, PeriodRow, RunSpec, SteadyCheck};
use crate::units::{Force, Length};
pub use crate::verdict::JumpRow;

/// What an actual or measured cam's profile is (the JSON `profile`).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum ProfileReport {
    /// `--actual`: drawn from tolerances.
    Actual(ProfileStats),
    /// `--measured FILE`.
    Measured(MeasuredStats),
}

impl ProfileReport {
    /// The waviness frequency per revolution.
    pub fn fpr(&self) -> usize {
        match self {
            ProfileReport::Actual(s) => s.fpr,
            ProfileReport::Measured(s) => s.fpr,
        }
    }
}

/// Everything `camsim run` prints (`--json`: keys sorted, as before the report was a
/// struct; `wall_ms` is a timing; `fpr` and `profile` only for an actual or measured cam).
#[derive(Clone, Debug, Serialize)]
pub struct RunReport {
    /// The camsim that ran it (its version).
    pub camsim_version: &'static str,
    /// The scene file given (absent: the built-in reference design).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scene_file: Option<String>,
    /// The scene that ran, as a scene file (TOML; the options that override it applied):
    /// `camsim run` on this text reproduces the run (set by [`report()`](super::report())).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scene: Option<String>,
    /// The verdict: contact, geometry, loads, spring, margin, steady state, warnings
    /// (set by [`report()`](super::report()); absent from a bare [`RunReport::new`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub verdict: Option<crate::verdict::Verdict>,
    /// Waviness frequency per revolution of the profile (VI.4.1; actual and measured
    /// cams only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fpr: Option<usize>,
    /// The actual or measured profile (None: the theoretical cam).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub profile: Option<ProfileReport>,
    /// Per-period statistics of every revolution.
    pub per_period: Vec<PeriodRow>,
    /// Every recorded separation interval.
    pub jumps: Vec<JumpRow>,
    /// Accepted (double) steps.
    pub steps: u32,
    /// Rejected (double) steps.
    pub rejected_steps: u32,
    /// Right-hand-side evaluations.
    pub rhs_evals: u32,
    /// Separation intervals not recorded (past the statistics' capacity).
    pub jumps_dropped: u32,
    /// The last two revolutions compared (absent with one revolution).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub steady_state: Option<SteadyCheck>,
    /// Wall-clock time of the simulation, ms.
    pub wall_ms: f64,
    /// The preload F_p, lb.
    pub preload_lb: Force,
    /// Cam speed ω0, rpm.
    pub rpm: f64,
    /// Revolutions simulated.
    pub revolutions: u32,
    /// Degrees of freedom of the scene (text only).
    #[serde(skip)]
    pub dofs: usize,
    /// Solver relative tolerance (text only).
    #[serde(skip)]
    pub rtol: f64,
    /// The integration method (`solver.method`; text only, the JSON's scene has it).
    #[serde(skip)]
    pub method: &'static str,
    /// Solver absolute tolerance, in (text only).
    #[serde(skip)]
    pub atol_in: Length,
    /// The name of each period of the program (text only).
    #[serde(skip)]
    pub periods: Vec<&'static str>,
    /// The files the run wrote (--csv, the plots of --plot; absent when none).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub files: Vec<String>,
}

impl RunReport {
    /// The report of a finished run of `spec`.
    pub fn new(spec: &RunSpec, result: &sim::RunResult) -> Self {
        let per_period = sim::period_rows(&spec.design, &result.stats);
        let steady_state = sim::steady_check(&per_period);
        let jumps = result
            .stats
            .jumps()
            .iter()
            .map(|j| JumpRow {
                revolution: j.revolution,
                start_deg: j.start_deg,
                end_deg: j.end_deg,
                period: spec.design.program.segment_at(j.start_deg.to_radians()),
            })
            .collect();
        RunReport {
            camsim_version: env!("CARGO_PKG_VERSION"),
            scene_file: None,
            scene: None,
            verdict: None,
            fpr: None,
            profile: None,
            per_period,
            jumps,
            steps: result.solver.accepted,
            rejected_steps: result.solver.rejected,
            rhs_evals: result.solver.rhs_evals,
            jumps_dropped: result.stats.jumps_dropped,
            steady_state,
            wall_ms: result.wall_ms,
            preload_lb: Force::inch(result.preload),
            rpm: camsim_core::rad_per_s_to_rpm(spec.design.omega0),
            revolutions: spec.revolutions,
            dofs: result.scene.dofs,
            rtol: spec.solver.rtol,
            method: spec.solver.method.resolve(spec.solver.rtol).name(),
            atol_in: Length::inch(spec.solver.atol),
            periods: sim::period_names(&spec.design),
            files: Vec::new(),
        }
    }
}
