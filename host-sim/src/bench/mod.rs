//! `camsim bench`: run time against error on the reference design (the full 11-DOF
//! scene, static start, 2 revolutions, 500 rpm by default) for England's method as it is,
//! England's method with the PI controller and the stiffness cap, classic RK4 at fixed
//! steps and Dormand-Prince 5(4) from the `ode_solvers` crate, in f64 and f32 (the f32
//! math is libm, or micromath in a build with the `micromath` feature), and in the full
//! run (f64, rtol 1e-2 to 1e-8) the linearly implicit Rosenbrock-W method ROS34PW2
//! ([`rosenbrock`]), its Jacobian every step or every 10 steps.
//!
//! Errors are measured against a reference from a very tight England run, confirmed by a
//! second method (Dormand-Prince at the same tolerance; their disagreement is reported
//! and must be far below the errors measured): RMS over revolution 2 of the load's
//! displacement and acceleration sampled every 0.5° of cam angle through each method's
//! continuous extension ([`sample`]), the smallest contact force, and (full run only) the
//! jump-onset speed. Work: right-hand-side evaluations, accepted and rejected steps, wall
//! time (median of several runs), and steps per revolution against the stability limit
//! from the eigenvalues of the model's own Jacobian ([`stability`]).

pub mod methods;
pub mod plot;
pub mod rosenbrock;
pub mod sample;
pub mod stability;
pub mod text;

use std::time::Instant;

use anyhow::{bail, Context, Result};
use camsim_core::{
    jump_verdict, CamModel, ConstCamVertical, ConstMotorVertical, Design, DriveLaw, Onset,
    OnsetSearch, Real, RegulatedFull, RegulatedVertical, Scene, SolverSettings, Start,
};
use ode_solvers::dop_shared::FloatNumber;
use serde::Serialize;

use methods::{Method, Work};
use sample::{Sampler, Samples};
use stability::StabilityLimit;

/// Revolutions of every run; revolution 2 is measured.
pub const REVOLUTIONS: u32 = 2;
/// The measured revolution.
pub const MEASURED: u32 = 2;
/// The reference's relative tolerance (England), and the confirming run's.
pub const REFERENCE_RTOL: f64 = 1e-13;
/// Absolute tolerance of displacements for a relative tolerance, in: `1e-3 in · rtol`.
pub fn atol_for(rtol: f64) -> f64 {
    1e-3 * rtol
}

/// The tolerance ladder of the full run (f64).
pub const FULL_RTOLS: [f64; 9] = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10];
/// The f32 ladder of the full run (single precision resolves about 1e-7 of a value).
pub const FULL_RTOLS_F32: [f64; 5] = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6];
/// The ladder of `--quick`.
pub const QUICK_RTOLS: [f64; 3] = [1e-3, 1e-5, 1e-7];
/// The f32 ladder of `--quick`.
pub const QUICK_RTOLS_F32: [f64; 1] = [1e-4];
/// RK4's fixed steps per revolution as multiples of its fixed-step stability limit.
pub const FULL_RK4_FACTORS: [f64; 7] = [1.05, 1.25, 1.5, 2.0, 3.0, 4.0, 6.0];
/// ... in f32.
pub const FULL_RK4_FACTORS_F32: [f64; 4] = [1.05, 1.5, 2.0, 4.0];
/// ... of `--quick`.
pub const QUICK_RK4_FACTORS: [f64; 3] = [1.25, 2.0, 4.0];
/// ... of `--quick`, f32.
pub const QUICK_RK4_FACTORS_F32: [f64; 1] = [1.25];
/// The tightest tolerance of the Rosenbrock rows (full run, f64 only).
pub const ROSENBROCK_TIGHTEST_RTOL: f64 = 1e-8;
/// Tolerances at which the full run also measures the jump-onset speed.
pub const ONSET_RTOLS: [f64; 4] = [1e-3, 1e-5, 1e-7, 1e-9];
/// RK4 factors at which the full run measures the jump-onset speed.
pub const ONSET_RK4_FACTORS: [f64; 3] = [1.25, 2.0, 4.0];
/// The jump-onset search: bracket (rpm) and resolution (rpm).
pub const ONSET_BRACKET: (f64, f64) = (800.0, 1000.0);
/// Bisection stops when the bracket is this narrow, rpm.
pub const ONSET_RESOLUTION: f64 = 1e-3;

/// What to run.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// Cam speed, rpm.
    pub rpm: f64,
    /// A few points only (CI).
    pub quick: bool,
    /// Timed repetitions of each run (the median is reported).
    pub repeat: u32,
    /// Measure the jump-onset speed.
    pub onset: bool,
    /// Run past [`MAX_BENCH_SECONDS`] of estimated time (`--allow-long`).
    pub allow_long: bool,
    /// Show the elapsed and estimated time on a terminal while it runs.
    pub progress: bool,
}

/// The longest a bench may be estimated to run without `--allow-long`: 1 hour. The
/// bench is run by hand or in CI (`--quick`), never as a batch job, and an hour holds the
/// default full bench (`--repeat 5`) even on a loaded machine (about 34 min estimated at
/// a 2.8 s reference run, load 15 on 2 cores).
pub const MAX_BENCH_SECONDS: f64 = 3600.0;

/// The bench's time in units of its reference run's (the first thing it runs, timed):
/// `(fixed, per repetition)`, for `--quick` and for the full bench; the ratios hold across
/// machines and loads as far as every run slows alike. Measured (BENCHMARKS.md, "How long
/// the bench runs"): `--quick` 4.3 references at `--repeat 1` and 5.9 at 3 (10.7 s and
/// 16.9 s); the full bench 247 references at `--repeat 1` (698 s, reference 2.83 s),
/// split about evenly between the fixed part (reference, stability, jump onsets) and
/// the repetitions, an estimate: no second full run was measured.
pub const BENCH_TIME_IN_REFERENCES: [(f64, f64); 2] = [
    (QUICK_FIXED, QUICK_PER_REPEAT),
    (FULL_FIXED, FULL_PER_REPEAT),
];
const QUICK_FIXED: f64 = 3.5;
const QUICK_PER_REPEAT: f64 = 0.9;
const FULL_FIXED: f64 = 130.0;
const FULL_PER_REPEAT: f64 = 120.0;

/// The estimated wall time, s, of a bench of `repeat` repetitions whose reference run took
/// `reference_s`.
pub fn estimate_seconds(reference_s: f64, quick: bool, repeat: u32) -> f64 {
    let (fixed, per) = BENCH_TIME_IN_REFERENCES[usize::from(!quick)];
    reference_s * (fixed + per * f64::from(repeat))
}

/// Refuses a bench estimated past [`MAX_BENCH_SECONDS`] unless `allow`.
pub fn check_time(estimate_s: f64, repeat: u32, allow: bool) -> Result<()> {
    if estimate_s > MAX_BENCH_SECONDS && !allow {
        anyhow::bail!(
            "--repeat {repeat}: the bench would take about {} (from its reference run), over the {} limit (use a smaller --repeat, or --allow-long)",
            crate::study_limits::duration(estimate_s),
            crate::study_limits::duration(MAX_BENCH_SECONDS)
        );
    }
    Ok(())
}

/// The f32 math of this build.
pub fn f32_math() -> &'static str {
    if cfg!(feature = "micromath") {
        "micromath"
    } else {
        "libm"
    }
}

/// One measured run (every number present: a failed run is in [`BenchReport::failed`]).
#[derive(Clone, Debug, Serialize)]
pub struct RunRow {
    /// `england`, `england_scaled_cap`, `england_pi_capped`, `merson_4_3[_capped]`, `rk4_fixed`,
    /// `dopri5_ode_solvers` or
    /// `rosenbrock_ros34pw2[_j10]`.
    pub method: String,
    /// The scene (`full_11dof` for the comparison; reduced scenes name themselves).
    pub scene: String,
    /// `f64` or `f32`.
    pub precision: String,
    /// The math library of that precision (`libm`, or `micromath` for f32 in a
    /// micromath build).
    pub math: String,
    /// Relative tolerance; 0 for RK4 at a fixed step (no tolerance: see
    /// `fixed_steps_per_rev`).
    pub rtol: f64,
    /// Absolute tolerance of displacements, in (0 for RK4).
    pub atol_in: f64,
    /// RK4's steps per nominal revolution.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fixed_steps_per_rev: Option<u32>,
    /// Accepted steps over both revolutions (England: double steps).
    pub steps: u64,
    /// Rejected steps over both revolutions.
    pub rejected: u64,
    /// Right-hand-side evaluations over both revolutions.
    pub rhs_evals: u64,
    /// Median wall time of the repetitions, ms (integration and sampling).
    pub wall_ms: f64,
    /// Fastest repetition, ms.
    pub wall_ms_min: f64,
    /// Median CPU time of the bench's thread over the repetitions, ms (what the run
    /// cost, whatever else the machine ran; Unix only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cpu_ms: Option<f64>,
    /// RMS error of the load displacement over revolution 2 (every 0.5°), in.
    pub err_disp_rms: f64,
    /// RMS error of the load acceleration over revolution 2, in/s².
    pub err_acc_rms: f64,
    /// Error of the smallest sampled contact force of revolution 2, lb.
    pub err_force_min_lb: f64,
    /// The follower left the cam at a sample of revolution 2 (the reference does not).
    pub contact_lost: bool,
    /// Accepted steps in revolution 2.
    pub steps_rev2: u64,
    /// Rejected steps in revolution 2.
    pub rejected_rev2: u64,
    /// Right-hand-side evaluations in revolution 2.
    pub rhs_evals_rev2: u64,
    /// Rejected over attempted steps in revolution 2.
    pub rejected_fraction_rev2: f64,
    /// This method's stability limit, steps per revolution (England: double steps; RK4
    /// at a fixed step: the fixed-step limit); only for the full scene.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub limit_steps_per_rev: Option<f64>,
    /// Steps in revolution 2 over that limit.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub steps_over_limit: Option<f64>,
    /// The acceleration error is at least 10 times the two references' disagreement
    /// (a smaller one would measure the reference: such points are not plotted).
    pub acc_err_resolved: bool,
    /// The same for the displacement error.
    pub disp_err_resolved: bool,
    /// Jump-onset speed with this method and tolerance, rpm (full run, some tolerances).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump_onset_rpm: Option<f64>,
    /// Its error against the reference's onset, rpm (0: the same bisection bracket, an
    /// error below the search's resolution, `onset_resolution_rpm` of the report).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump_onset_err_rpm: Option<f64>,
    /// `ok`.
    pub status: String,
}

/// A run that failed: what it was and why (no numbers).
#[derive(Clone, Debug, Serialize)]
pub struct FailedRun {
    /// Method name.
    pub method: String,
    /// Scene.
    pub scene: String,
    /// Precision.
    pub precision: String,
    /// Math library.
    pub math: String,
    /// Relative tolerance (0 for RK4).
    pub rtol: f64,
    /// RK4's steps per revolution.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fixed_steps_per_rev: Option<u32>,
    /// `failed: <reason>`.
    pub status: String,
}

/// The reference solution and its confirmation.
#[derive(Clone, Debug, Serialize)]
pub struct ReferenceInfo {
    /// The reference: method, rtol, atol.
    pub method: String,
    /// Its relative tolerance.
    pub rtol: f64,
    /// Its absolute tolerance of displacements, in.
    pub atol_in: f64,
    /// Its work.
    pub steps: u64,
    /// Its right-hand-side evaluations.
    pub rhs_evals: u64,
    /// The confirming run's method.
    pub confirm_method: String,
    /// The confirming run's relative tolerance.
    pub confirm_rtol: f64,
    /// RMS difference of the two in load displacement over revolution 2, in.
    pub agree_disp_rms: f64,
    /// RMS difference in load acceleration, in/s².
    pub agree_acc_rms: f64,
    /// Difference of the smallest contact force, lb.
    pub agree_force_min_lb: f64,
    /// RMS of the load displacement signal over revolution 2, in (for scale).
    pub signal_disp_rms: f64,
    /// RMS of the load acceleration signal, in/s².
    pub signal_acc_rms: f64,
    /// The reference's smallest contact force in revolution 2, lb.
    pub force_min_lb: f64,
    /// The reference's jump-onset speed, rpm (full run).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump_onset_rpm: Option<f64>,
    /// The confirming method's jump-onset speed at the same tolerance, rpm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub confirm_jump_onset_rpm: Option<f64>,
}

/// Everything `camsim bench` reports (`--json`: `runs` first; the rest describes them).
#[derive(Clone, Debug, Serialize)]
pub struct BenchReport {
    /// The measured runs.
    pub runs: Vec<RunRow>,
    /// Runs that failed (listed here only).
    pub failed: Vec<FailedRun>,
    /// The reference and its confirmation.
    pub reference: ReferenceInfo,
    /// The stability limit from the Jacobian's eigenvalues along the reference.
    pub stability: StabilityLimit,
    /// Cam speed, rpm.
    pub rpm: f64,
    /// Revolutions of every run.
    pub revolutions: u32,
    /// `--quick`.
    pub quick: bool,
    /// Timed repetitions of each run.
    pub repeat: u32,
    /// Wall time of the whole bench, s.
    pub bench_seconds: f64,
    /// Wall time of its reference run (the first thing it runs), s.
    pub reference_seconds: f64,
    /// The time estimated from the reference run before the rest ran, s.
    pub estimated_seconds: f64,
    /// Resolution of the jump-onset bisection, rpm.
    pub onset_resolution_rpm: f64,
    /// Each method against Dormand-Prince at equal acceleration error (full scene f64;
    /// the chip's scene f64 and f32).
    pub equal_error: Vec<EqualError>,
    /// The chip's scene: its own reference and stability limit.
    pub chip: ChipInfo,
    /// Fixed memory of a simulation, bytes.
    pub memory: Memory,
}

/// A method's work against Dormand-Prince's at the acceleration error of one of
/// Dormand-Prince's runs, interpolated (log-log) along the method's own best runs (its
/// Pareto front of work against error); only where the front reaches that error.
#[derive(Clone, Debug, Serialize)]
pub struct EqualError {
    /// The method compared.
    pub method: String,
    /// The scene (`full_11dof`, or the chip's [`CHIP_SCENE`]).
    pub scene: String,
    /// `f64` or `f32`.
    pub precision: String,
    /// Dormand-Prince's rtol.
    pub peer_rtol: f64,
    /// The acceleration error, in/s².
    pub err_acc_rms: f64,
    /// Dormand-Prince's evaluations.
    pub peer_rhs_evals: u64,
    /// The method's evaluations for that error (interpolated).
    pub rhs_evals: f64,
    /// Method over peer, evaluations.
    pub evals_ratio: f64,
    /// Method over peer, median wall time (interpolated the same way), if the method's
    /// front in wall time reaches that error.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wall_ratio: Option<f64>,
    /// Method over peer, median CPU time, the same way.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cpu_ratio: Option<f64>,
}

/// `cost` at error `err` along the Pareto front of `(cost, err)` points (log-log
/// interpolation between the two front points that bracket `err`).
pub fn cost_at_error(points: &[(f64, f64)], err: f64) -> Option<f64> {
    let mut p: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|(c, e)| c.is_finite() && *c > 0.0 && e.is_finite() && *e > 0.0)
        .collect();
    p.sort_by(|a, b| a.0.total_cmp(&b.0));
    // The front: each point more accurate than every cheaper one.
    let mut front: Vec<(f64, f64)> = Vec::new();
    for q in p {
        if front.last().is_none_or(|l| q.1 < l.1) {
            front.push(q);
        }
    }
    front.windows(2).find_map(|w| {
        let ((c0, e0), (c1, e1)) = (w[0], w[1]);
        if e0 >= err && err >= e1 {
            let f = (err.ln() - e0.ln()) / (e1.ln() - e0.ln());
            Some((c0.ln() + f * (c1.ln() - c0.ln())).exp())
        } else {
            None
        }
    })
}

/// [`EqualError`] rows for every method against Dormand-Prince's resolved f64 runs.
fn equal_error(runs: &[RunRow], scene: &str, precision: &str) -> Vec<EqualError> {
    equal_error_of(runs, scene, precision)
}

/// [`EqualError`] rows for every method against Dormand-Prince's resolved runs of one
/// scene and precision.
fn equal_error_of(runs: &[RunRow], scene: &str, precision: &str) -> Vec<EqualError> {
    let full = |r: &&RunRow| r.scene == scene && r.precision == precision && r.acc_err_resolved;
    let mut out = Vec::new();
    for method in [
        "england",
        "england_scaled_cap",
        "england_pi_capped",
        "merson_4_3",
        "merson_4_3_capped",
        "rk4_fixed",
        "rosenbrock_ros34pw2",
        "rosenbrock_ros34pw2_j10",
    ] {
        let mine: Vec<&RunRow> = runs
            .iter()
            .filter(full)
            .filter(|r| r.method == method)
            .collect();
        let by_evals: Vec<(f64, f64)> = mine
            .iter()
            .map(|r| (r.rhs_evals as f64, r.err_acc_rms))
            .collect();
        let by_wall: Vec<(f64, f64)> = mine.iter().map(|r| (r.wall_ms, r.err_acc_rms)).collect();
        let by_cpu: Vec<(f64, f64)> = mine
            .iter()
            .filter_map(|r| r.cpu_ms.map(|c| (c, r.err_acc_rms)))
            .collect();
        for peer in runs
            .iter()
            .filter(full)
            .filter(|r| r.method == "dopri5_ode_solvers")
        {
            let Some(evals) = cost_at_error(&by_evals, peer.err_acc_rms) else {
                continue;
            };
            out.push(EqualError {
                method: method.into(),
                scene: scene.into(),
                precision: precision.into(),
                peer_rtol: peer.rtol,
                err_acc_rms: peer.err_acc_rms,
                peer_rhs_evals: peer.rhs_evals,
                rhs_evals: evals,
                evals_ratio: evals / peer.rhs_evals as f64,
                wall_ratio: cost_at_error(&by_wall, peer.err_acc_rms).map(|w| w / peer.wall_ms),
                cpu_ratio: match (cost_at_error(&by_cpu, peer.err_acc_rms), peer.cpu_ms) {
                    (Some(c), Some(p)) => Some(c / p),
                    _ => None,
                },
            });
        }
    }
    out
}

/// What each part of a simulation occupies, bytes.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Memory {
    /// The full model, f64, 22 states.
    pub model_f64_22_bytes: usize,
    /// England's solver, f64, 22 states.
    pub solver_f64_22_bytes: usize,
    /// The chip's model, f32 ([`camsim_chip::CHIP_STATES`] states).
    pub model_f32_chip_bytes: usize,
    /// England's solver, f32, the chip's states.
    pub solver_f32_chip_bytes: usize,
    /// The chip's state length.
    pub chip_states: usize,
}

impl Memory {
    /// The sizes of this build.
    pub fn of_this_build() -> Self {
        use std::mem::size_of;
        Memory {
            model_f64_22_bytes: size_of::<camsim_core::RegulatedFullModel<f64>>(),
            solver_f64_22_bytes: size_of::<camsim_core::England<f64, { RegulatedFull::N }>>(),
            model_f32_chip_bytes: size_of::<camsim_chip::ChipModel<f32>>(),
            solver_f32_chip_bytes: size_of::<camsim_core::England<f32, { camsim_chip::CHIP_STATES }>>(
            ),
            chip_states: camsim_chip::CHIP_STATES,
        }
    }
}

/// Solver settings with `rtol`, atol [`atol_for`] and the default largest step, from
/// static equilibrium (every run of the bench), on England's method (each bench method
/// builds its own integrator; what runs through `simulate`, the onsets, is England's).
pub fn settings<T: Real>(rtol: f64) -> SolverSettings<T> {
    SolverSettings {
        rtol: T::from_f64(rtol),
        atol: T::from_f64(atol_for(rtol)),
        start: Start::Static,
        method: camsim_core::Method::England,
        ..SolverSettings::reference()
    }
}

/// One run's outcome: its work (both revolutions and revolution 2), its samples and its
/// wall times.
struct Measured {
    work: Work,
    rev2: Work,
    samples: Samples,
    wall_ms: Vec<f64>,
    cpu_ms: Vec<f64>,
}

/// CPU time of the calling thread, s (None where unknown).
pub fn thread_cpu_seconds() -> Option<f64> {
    #[cfg(unix)]
    {
        use nix::time::{clock_gettime, ClockId};
        clock_gettime(ClockId::CLOCK_THREAD_CPUTIME_ID)
            .ok()
            .map(|t| t.tv_sec() as f64 + 1e-9 * t.tv_nsec() as f64)
    }
    #[cfg(not(unix))]
    {
        None
    }
}

/// Runs `method` `repeat` times (timed), plus once to the end of revolution 1 (for the
/// work of revolution 2).
fn measure_run<T, S, const N: usize>(
    method: Method,
    model: &CamModel<T, S, N>,
    settings: &SolverSettings<T>,
    repeat: u32,
    keep_states: bool,
) -> Result<Measured>
where
    T: Real + FloatNumber,
    S: Scene,
    f64: From<T>,
{
    let mut wall_ms = Vec::new();
    let mut cpu_ms = Vec::new();
    let mut first: Option<(Work, Samples)> = None;
    for _ in 0..repeat.max(1) {
        let mut sampler = Sampler::new(model, REVOLUTIONS, Some(MEASURED));
        if keep_states {
            sampler = sampler.keep_states();
        }
        let c0 = thread_cpu_seconds();
        let t0 = Instant::now();
        let work = methods::run(method, model, settings, REVOLUTIONS, &mut sampler)?;
        wall_ms.push(t0.elapsed().as_secs_f64() * 1e3);
        if let (Some(a), Some(b)) = (c0, thread_cpu_seconds()) {
            cpu_ms.push((b - a) * 1e3);
        }
        anyhow::ensure!(
            sampler.complete(),
            "only {} of the {} samples were taken",
            sampler.samples.len(),
            sample::SAMPLES_PER_REV
        );
        match &first {
            None => first = Some((work, sampler.samples)),
            Some((w, s)) => {
                // Every repetition must do the same thing (a timing of something else
                // would be meaningless).
                anyhow::ensure!(*w == work && *s == sampler.samples, "a repetition differed");
            }
        }
    }
    let (work, samples) = first.context("no run")?;
    let mut sampler = Sampler::new(model, MEASURED - 1, None);
    let rev1 = methods::run(method, model, settings, MEASURED - 1, &mut sampler)?;
    Ok(Measured {
        work,
        rev2: work.since(&rev1),
        samples,
        wall_ms,
        cpu_ms,
    })
}

/// The median of `v` (sorted in place; NaN when empty).
pub fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

/// The reference design at `rpm`.
pub fn design_at(rpm: f64) -> Result<Design<f64>> {
    let mut d = Design::reference();
    d.set_speed_rpm(rpm)?;
    Ok(d)
}

/// Whether the follower leaves the cam in revolution 2 at `rpm` with `method` (a run
/// that fails after the follower left the cam counts as leaving it): the full model.
fn jumps_at<T>(method: Method, rpm: f64, rtol: f64) -> Result<bool>
where
    T: Real + FloatNumber,
    f64: From<T>,
{
    let design = Design::reference();
    scene_jumps_at::<T, RegulatedFull, { RegulatedFull::N }>(method, &design, rpm, &settings(rtol))
}

/// Whether the follower leaves the cam in revolution 2 (a run that fails after it left
/// the cam counts as leaving it), for scene `S`'s model of `design` moved to `rpm`, with
/// `method` and `settings`.
pub fn scene_jumps_at<T, S: Scene, const N: usize>(
    method: Method,
    design: &Design<f64>,
    rpm: f64,
    settings: &SolverSettings<T>,
) -> Result<bool>
where
    T: Real + FloatNumber,
    f64: From<T>,
{
    let mut d = design.clone();
    d.set_speed_rpm(rpm)?;
    let model = CamModel::<T, S, N>::new(d.cast::<T>()?)?;
    let mut sampler = Sampler::new(&model, REVOLUTIONS, Some(MEASURED)).watch_contact();
    let run = methods::run(method, &model, settings, REVOLUTIONS, &mut sampler);
    // Core's rule (docs/MODEL.md): a failure after any separation is a jump.
    jump_verdict(run, &sampler.jump_watch)
        .map(|v| v.jumped())
        .with_context(|| format!("{} at {rpm} rpm", method.name()))
}

/// The jump-onset speed of `method` by bisection in [`ONSET_BRACKET`] to
/// [`ONSET_RESOLUTION`]: the midpoint of the last bracket.
fn jump_onset<T>(method: Method, rtol: f64) -> Result<f64>
where
    T: Real + FloatNumber,
    f64: From<T>,
{
    onset_by_bisection(ONSET_BRACKET, ONSET_RESOLUTION, |rpm| {
        jumps_at::<T>(method, rpm, rtol)
    })
}

/// The lowest speed at which `jumps` holds, by bisection in `bracket` (rpm) until it is
/// `resolution` wide (core's `OnsetSearch::bisect`): the midpoint of the last bracket. An
/// error unless the bracket's low end holds contact and its high end jumps.
pub fn onset_by_bisection(
    bracket: (f64, f64),
    resolution: f64,
    mut jumps: impl FnMut(f64) -> Result<bool>,
) -> Result<f64> {
    let (lo, hi) = bracket;
    if jumps(lo)? || !jumps(hi)? {
        bail!("the jump onset is not within {lo}-{hi} rpm");
    }
    match OnsetSearch::new(lo, None, hi, resolution)?.bisect(lo, hi, jumps)? {
        Onset::Bracketed { below, at } => Ok(0.5 * (below + at)),
        other => bail!("bisection of a known bracket ended as {other:?}"),
    }
}

/// The reference samples and how far the confirming run is from them: (acceleration,
/// displacement) RMS differences.
pub struct ReferenceSamples<'a> {
    samples: &'a Samples,
    agree: (f64, f64),
}

/// Builds the report row of a measured run against the reference samples.
#[allow(clippy::too_many_arguments)]
fn row(
    method: Method,
    scene: &str,
    precision: &str,
    math: &str,
    rtol: f64,
    m: &mut Measured,
    reference: &ReferenceSamples<'_>,
    limit: Option<f64>,
) -> RunRow {
    let (reference, agree) = (reference.samples, reference.agree);
    let attempted = m.rev2.accepted + m.rev2.rejected;
    let fixed = match method {
        Method::Rk4 { steps_per_rev } => Some(steps_per_rev),
        _ => None,
    };
    let min_wall = m.wall_ms.iter().copied().fold(f64::INFINITY, f64::min);
    RunRow {
        method: method.name().into(),
        scene: scene.into(),
        precision: precision.into(),
        math: math.into(),
        rtol: if method.adaptive() { rtol } else { 0.0 },
        atol_in: if method.adaptive() {
            atol_for(rtol)
        } else {
            0.0
        },
        fixed_steps_per_rev: fixed,
        steps: m.work.accepted,
        rejected: m.work.rejected,
        rhs_evals: m.work.evals,
        wall_ms: median(&mut m.wall_ms),
        wall_ms_min: min_wall,
        cpu_ms: if m.cpu_ms.is_empty() {
            None
        } else {
            Some(median(&mut m.cpu_ms))
        },
        err_disp_rms: Samples::rms_diff(&m.samples.disp, &reference.disp),
        err_acc_rms: Samples::rms_diff(&m.samples.acc, &reference.acc),
        err_force_min_lb: (m.samples.force_min() - reference.force_min()).abs(),
        contact_lost: m.samples.force_min() <= 0.0,
        steps_rev2: m.rev2.accepted,
        rejected_rev2: m.rev2.rejected,
        rhs_evals_rev2: m.rev2.evals,
        rejected_fraction_rev2: if attempted > 0 {
            m.rev2.rejected as f64 / attempted as f64
        } else {
            0.0
        },
        limit_steps_per_rev: limit,
        steps_over_limit: limit.map(|l| m.rev2.accepted as f64 / l),
        acc_err_resolved: Samples::rms_diff(&m.samples.acc, &reference.acc) >= 10.0 * agree.0,
        disp_err_resolved: Samples::rms_diff(&m.samples.disp, &reference.disp) >= 10.0 * agree.1,
        jump_onset_rpm: None,
        jump_onset_err_rpm: None,
        status: "ok".into(),
    }
}

/// The explicit stability limit of `method`'s steps a revolution (none for the A-stable
/// Rosenbrock method).
fn stability_limit(method: Method, limits: &StabilityLimit) -> Option<f64> {
    match method {
        Method::England | Method::EnglandScaledCap | Method::EnglandPiCapped => {
            Some(limits.england_double_steps_per_rev)
        }
        Method::Rk4 { .. } => Some(limits.rk4_fixed_steps_per_rev),
        Method::Dopri5 => Some(limits.dopri5_steps_per_rev),
        Method::Merson { .. } => Some(limits.merson_steps_per_rev),
        // A-stable: no explicit stability limit.
        Method::Rosenbrock { .. } => None,
    }
}

/// The runs of one precision on scene `S` (`scene` its name in the report): every method
/// over its ladder.
#[allow(clippy::too_many_arguments)]
fn sweep<T, S: Scene, const N: usize>(
    scene: &str,
    precision: &str,
    math: &str,
    rtols: &[f64],
    rk4_factors: &[f64],
    opts: &Options,
    reference: &ReferenceSamples<'_>,
    limits: &StabilityLimit,
    runs: &mut Vec<RunRow>,
    failed: &mut Vec<FailedRun>,
) -> Result<()>
where
    T: Real + FloatNumber,
    f64: From<T>,
{
    let design = design_at(opts.rpm)?.cast::<T>()?;
    let model = CamModel::<T, S, N>::new(design).context("the bench's model in this precision")?;
    let mut cases: Vec<(Method, f64)> = Vec::new();
    for m in [
        Method::England,
        Method::EnglandScaledCap,
        Method::EnglandPiCapped,
        Method::Merson { capped: false },
        Method::Merson { capped: true },
        Method::Dopri5,
    ] {
        for &r in rtols {
            cases.push((m, r));
        }
    }
    // The linearly implicit method: the full f64 sweep only (its LU factorisations make
    // it the slowest row per step; --quick stays short).
    if !opts.quick && precision == "f64" && scene == "full_11dof" {
        for jac_every in [1, 10] {
            // Third order: below 1e-8 its steps (and LU factorisations) multiply.
            for &r in rtols.iter().filter(|&&r| r >= ROSENBROCK_TIGHTEST_RTOL) {
                cases.push((Method::Rosenbrock { jac_every }, r));
            }
        }
    }
    for &f in rk4_factors {
        // Rounded up to a multiple of 100 steps per revolution.
        let n = (limits.rk4_fixed_steps_per_rev * f / 100.0).ceil() * 100.0;
        cases.push((
            Method::Rk4 {
                steps_per_rev: n as u32,
            },
            0.0,
        ));
    }
    for (method, rtol) in cases {
        let limit = stability_limit(method, limits);
        let s = settings::<T>(rtol.max(1e-16));
        match measure_run(method, &model, &s, opts.repeat, false) {
            Ok(mut m) => runs.push(row(
                method, scene, precision, math, rtol, &mut m, reference, limit,
            )),
            Err(e) => failed.push(FailedRun {
                method: method.name().into(),
                scene: scene.into(),
                precision: precision.into(),
                math: math.into(),
                rtol: if method.adaptive() { rtol } else { 0.0 },
                fixed_steps_per_rev: match method {
                    Method::Rk4 { steps_per_rev } => Some(steps_per_rev),
                    _ => None,
                },
                status: format!("failed: {e:#}"),
            }),
        }
    }
    Ok(())
}

/// The reduced scenes the bench has always compared (England as it is, the default
/// tolerances) against the full model's reference.
fn reduced_scenes(
    opts: &Options,
    reference: &ReferenceSamples<'_>,
    runs: &mut Vec<RunRow>,
    failed: &mut Vec<FailedRun>,
) -> Result<()> {
    fn one<S: Scene, const N: usize>(
        name: &str,
        design: Design<f64>,
        opts: &Options,
        reference: &ReferenceSamples<'_>,
        runs: &mut Vec<RunRow>,
        failed: &mut Vec<FailedRun>,
    ) -> Result<()> {
        let model = CamModel::<f64, S, N>::new(design)?;
        let rtol = 1e-6;
        match measure_run(Method::England, &model, &settings(rtol), opts.repeat, false) {
            Ok(mut m) => {
                runs.push(row(
                    Method::England,
                    name,
                    "f64",
                    "libm",
                    rtol,
                    &mut m,
                    reference,
                    None,
                ));
            }
            Err(e) => failed.push(FailedRun {
                method: Method::England.name().into(),
                scene: name.into(),
                precision: "f64".into(),
                math: "libm".into(),
                rtol,
                fixed_steps_per_rev: None,
                status: format!("failed: {e:#}"),
            }),
        }
        Ok(())
    }
    let d = design_at(opts.rpm)?;
    one::<RegulatedVertical, { RegulatedVertical::N }>(
        "vertical_regulated_16",
        d.clone(),
        opts,
        reference,
        runs,
        failed,
    )?;
    let mut m = d.clone();
    m.drive = DriveLaw::ConstantMotorSpeed;
    one::<ConstMotorVertical, { ConstMotorVertical::N }>(
        "vertical_const_motor_15",
        m,
        opts,
        reference,
        runs,
        failed,
    )?;
    let mut c = d;
    c.drive = DriveLaw::ConstantCamSpeed;
    one::<ConstCamVertical, { ConstCamVertical::N }>(
        "vertical_const_cam_10",
        c,
        opts,
        reference,
        runs,
        failed,
    )
}

/// The chip's scene in the report (the quasi-static rod, [`camsim_chip::ChipScene`]).
pub const CHIP_SCENE: &str = "chip_qs_rod";

/// The chip's scene's reference (England at [`REFERENCE_RTOL`], f64) and stability limit.
#[derive(Clone, Debug, Serialize)]
pub struct ChipInfo {
    /// Its reference's right-hand-side evaluations.
    pub reference_rhs_evals: u64,
    /// Dormand-Prince at the same tolerance against it: RMS difference in load
    /// acceleration over revolution 2, in/s².
    pub agree_acc_rms: f64,
    /// The stability analysis along its reference.
    pub stability: StabilityLimit,
}

/// The comparison on the chip's scene: its own reference (the model differs from the full
/// one), then every method over the ladders in f64 and f32.
fn chip_scene(
    opts: &Options,
    ladders: &Ladders,
    runs: &mut Vec<RunRow>,
    failed: &mut Vec<FailedRun>,
) -> Result<ChipInfo> {
    use camsim_chip::{ChipScene, CHIP_STATES};
    let model = CamModel::<f64, ChipScene, CHIP_STATES>::new(design_at(opts.rpm)?)?;
    let ref_settings = settings::<f64>(REFERENCE_RTOL);
    let reference = measure_run(Method::England, &model, &ref_settings, 1, true)
        .context("the chip scene's reference run")?;
    let confirm = measure_run(Method::Dopri5, &model, &ref_settings, 1, false)
        .context("the chip scene's confirming run")?;
    let r = &reference.samples;
    let agree = (
        Samples::rms_diff(&confirm.samples.acc, &r.acc),
        Samples::rms_diff(&confirm.samples.disp, &r.disp),
    );
    let limits = stability::analyse(
        &model,
        &settings::<f64>(1e-6),
        &r.t,
        &r.states,
        if opts.quick { 4 } else { 1 },
    )
    .context("the chip scene's stability analysis")?;
    let refs = ReferenceSamples { samples: r, agree };
    sweep::<f64, ChipScene, CHIP_STATES>(
        CHIP_SCENE,
        "f64",
        "libm",
        ladders.rtols,
        ladders.rk4,
        opts,
        &refs,
        &limits,
        runs,
        failed,
    )?;
    sweep::<f32, ChipScene, CHIP_STATES>(
        CHIP_SCENE,
        "f32",
        f32_math(),
        ladders.rtols32,
        ladders.rk4_32,
        opts,
        &refs,
        &limits,
        runs,
        failed,
    )?;
    Ok(ChipInfo {
        reference_rhs_evals: reference.work.evals,
        agree_acc_rms: agree.0,
        stability: limits,
    })
}

/// The tolerance ladders of one bench (`--quick` or full): f64 and f32 rtols, and the
/// fixed steps as factors of RK4's fewest steps per revolution.
struct Ladders {
    rtols: &'static [f64],
    rtols32: &'static [f64],
    rk4: &'static [f64],
    rk4_32: &'static [f64],
}

impl Ladders {
    /// The `--quick` ladders or the full ones.
    fn of(quick: bool) -> Self {
        if quick {
            Ladders {
                rtols: &QUICK_RTOLS,
                rtols32: &QUICK_RTOLS_F32,
                rk4: &QUICK_RK4_FACTORS,
                rk4_32: &QUICK_RK4_FACTORS_F32,
            }
        } else {
            Ladders {
                rtols: &FULL_RTOLS,
                rtols32: &FULL_RTOLS_F32,
                rk4: &FULL_RK4_FACTORS,
                rk4_32: &FULL_RK4_FACTORS_F32,
            }
        }
    }
}

/// Runs the bench.
pub fn measure(opts: &Options) -> Result<BenchReport> {
    let start = Instant::now();
    let model = CamModel::<f64, RegulatedFull, { RegulatedFull::N }>::new(design_at(opts.rpm)?)?;

    // The reference and its confirmation by a different method.
    let ref_settings = settings::<f64>(REFERENCE_RTOL);
    let t_ref = Instant::now();
    let reference = measure_run(Method::England, &model, &ref_settings, 1, true)
        .context("the reference run")?;
    let reference_s = t_ref.elapsed().as_secs_f64();
    let estimated_s = estimate_seconds(reference_s, opts.quick, opts.repeat);
    check_time(estimated_s, opts.repeat, opts.allow_long)?;
    // Elapsed against the estimate, on a terminal (the bench runs for minutes).
    let bar = crate::study_limits::progress_bar(
        1,
        opts.progress,
        "{spinner} {elapsed_precise} of about {msg} estimated: camsim bench",
    );
    bar.set_message(crate::study_limits::duration(estimated_s));
    bar.enable_steady_tick(std::time::Duration::from_millis(250));
    let confirm = measure_run(Method::Dopri5, &model, &ref_settings, 1, false)
        .context("the confirming reference run")?;
    let r = &reference.samples;
    let mut info = reference_info(&reference, &confirm);
    let limits = stability::analyse(
        &model,
        &settings::<f64>(1e-6),
        &r.t,
        &r.states,
        if opts.quick { 4 } else { 1 },
    )
    .context("the stability analysis")?;

    let refs = ReferenceSamples {
        samples: r,
        agree: (info.agree_acc_rms, info.agree_disp_rms),
    };
    let ladders = Ladders::of(opts.quick);
    let (mut runs, mut failed) = (Vec::new(), Vec::new());
    full_scene(opts, &ladders, &refs, &limits, &mut runs, &mut failed)?;
    if !opts.quick {
        reduced_scenes(opts, &refs, &mut runs, &mut failed)?;
    }
    let chip = chip_scene(opts, &ladders, &mut runs, &mut failed)?;
    if opts.onset {
        jump_onsets(&limits, &mut info, &mut runs)?;
    }

    let mut equal_error = equal_error(&runs, "full_11dof", "f64");
    equal_error.extend(equal_error_of(&runs, CHIP_SCENE, "f64"));
    equal_error.extend(equal_error_of(&runs, CHIP_SCENE, "f32"));
    bar.finish_and_clear();
    Ok(BenchReport {
        chip,
        runs,
        failed,
        reference: info,
        stability: limits,
        rpm: opts.rpm,
        revolutions: REVOLUTIONS,
        quick: opts.quick,
        repeat: opts.repeat,
        bench_seconds: start.elapsed().as_secs_f64(),
        reference_seconds: reference_s,
        estimated_seconds: estimated_s,
        onset_resolution_rpm: ONSET_RESOLUTION,
        equal_error,
        memory: Memory::of_this_build(),
    })
}

/// The reference run against its confirming run by a different method, and its signals
/// (the jump onsets are measured later, when asked for).
fn reference_info(reference: &Measured, confirm: &Measured) -> ReferenceInfo {
    let r = &reference.samples;
    ReferenceInfo {
        method: Method::England.name().into(),
        rtol: REFERENCE_RTOL,
        atol_in: atol_for(REFERENCE_RTOL),
        steps: reference.work.accepted,
        rhs_evals: reference.work.evals,
        confirm_method: Method::Dopri5.name().into(),
        confirm_rtol: REFERENCE_RTOL,
        agree_disp_rms: Samples::rms_diff(&confirm.samples.disp, &r.disp),
        agree_acc_rms: Samples::rms_diff(&confirm.samples.acc, &r.acc),
        agree_force_min_lb: (confirm.samples.force_min() - r.force_min()).abs(),
        signal_disp_rms: Samples::rms(&r.disp),
        signal_acc_rms: Samples::rms(&r.acc),
        force_min_lb: r.force_min(),
        jump_onset_rpm: None,
        confirm_jump_onset_rpm: None,
    }
}

/// The full 11-DOF scene's runs: every method over the ladders in f64, then in f32.
fn full_scene(
    opts: &Options,
    ladders: &Ladders,
    refs: &ReferenceSamples<'_>,
    limits: &StabilityLimit,
    runs: &mut Vec<RunRow>,
    failed: &mut Vec<FailedRun>,
) -> Result<()> {
    sweep::<f64, RegulatedFull, { RegulatedFull::N }>(
        "full_11dof",
        "f64",
        "libm",
        ladders.rtols,
        ladders.rk4,
        opts,
        refs,
        limits,
        runs,
        failed,
    )?;
    sweep::<f32, RegulatedFull, { RegulatedFull::N }>(
        "full_11dof",
        "f32",
        f32_math(),
        ladders.rtols32,
        ladders.rk4_32,
        opts,
        refs,
        limits,
        runs,
        failed,
    )
}

/// The reference's jump onset (and its confirming method's), then the onset and its error
/// of each full-scene f64 run on the onset ladders ([`ONSET_RTOLS`], [`ONSET_RK4_FACTORS`]);
/// a run whose onset search fails keeps none.
fn jump_onsets(
    limits: &StabilityLimit,
    info: &mut ReferenceInfo,
    runs: &mut [RunRow],
) -> Result<()> {
    let onset =
        jump_onset::<f64>(Method::England, REFERENCE_RTOL).context("the reference's jump onset")?;
    info.jump_onset_rpm = Some(onset);
    info.confirm_jump_onset_rpm = jump_onset::<f64>(Method::Dopri5, REFERENCE_RTOL).ok();
    for run in runs
        .iter_mut()
        .filter(|r| r.scene == "full_11dof" && r.precision == "f64")
    {
        let Some(method) = method_of(run) else {
            continue;
        };
        if !on_onset_ladder(method, run, limits) {
            continue;
        }
        if let Ok(o) = jump_onset::<f64>(method, run.rtol.max(1e-16)) {
            run.jump_onset_rpm = Some(o);
            run.jump_onset_err_rpm = Some((o - onset).abs());
        }
    }
    Ok(())
}

/// The method of a full-scene run, from its name (RK4 from its fixed step); None for one
/// the onset search does not take (Rosenbrock's).
fn method_of(run: &RunRow) -> Option<Method> {
    Some(match run.method.as_str() {
        "england" => Method::England,
        "england_scaled_cap" => Method::EnglandScaledCap,
        "england_pi_capped" => Method::EnglandPiCapped,
        "dopri5_ode_solvers" => Method::Dopri5,
        "merson_4_3" => Method::Merson { capped: false },
        "merson_4_3_capped" => Method::Merson { capped: true },
        _ => Method::Rk4 {
            steps_per_rev: run.fixed_steps_per_rev?,
        },
    })
}

/// Whether the run is on the onset ladders: its rtol one of [`ONSET_RTOLS`], or its fixed
/// step one of [`ONSET_RK4_FACTORS`] times RK4's fewest steps (rounded up to hundreds).
fn on_onset_ladder(method: Method, run: &RunRow, limits: &StabilityLimit) -> bool {
    if method.adaptive() {
        ONSET_RTOLS
            .iter()
            .any(|r| (r / run.rtol - 1.0).abs() < 1e-9)
    } else {
        ONSET_RK4_FACTORS.iter().any(|f| {
            let n = (limits.rk4_fixed_steps_per_rev * f / 100.0).ceil() * 100.0;
            Some(n as u32) == run.fixed_steps_per_rev
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bench_past_the_hour_is_refused_unless_asked_for() {
        // The estimate is linear in --repeat: fixed + repeat x per-repetition references.
        let (f, p) = BENCH_TIME_IN_REFERENCES[1];
        assert_eq!(estimate_seconds(2.0, false, 10), 2.0 * (f + 10.0 * p));
        let (f, p) = BENCH_TIME_IN_REFERENCES[0];
        assert_eq!(estimate_seconds(2.0, true, 3), 2.0 * (f + 3.0 * p));
        // The full bench's default at a 2.5 s reference is well inside the hour; --repeat
        // 100 is not.
        assert!(check_time(estimate_seconds(2.5, false, 5), 5, false).is_ok());
        let long = estimate_seconds(2.5, false, 100);
        let e = check_time(long, 100, false).unwrap_err().to_string();
        assert!(
            e.starts_with("--repeat 100: the bench would take about")
                && e.contains("over the 1.0 h limit")
                && e.contains("--allow-long"),
            "{e}"
        );
        assert!(check_time(long, 100, true).is_ok());
    }

    #[test]
    fn cost_at_error_interpolates_along_the_front() {
        // err = 1e4 · evals^-4: exact in log-log between any two points.
        let pts: Vec<(f64, f64)> = [10.0, 20.0, 40.0, 80.0]
            .iter()
            .map(|&c: &f64| (c, 1e4 * c.powi(-4)))
            .collect();
        let c = cost_at_error(&pts, 1e4 * 30f64.powi(-4)).unwrap();
        assert!((c - 30.0).abs() < 1e-9, "{c}");
        // Outside the front's errors: no answer.
        assert!(cost_at_error(&pts, 1e4).is_none());
        assert!(cost_at_error(&pts, 1e-9).is_none());
        // A dearer, less accurate point is not on the front and changes nothing.
        let mut with = pts.clone();
        with.push((35.0, 1.0));
        assert_eq!(cost_at_error(&with, 1e4 * 30f64.powi(-4)), Some(c));
    }

    fn no_nulls(v: &serde_json::Value, path: &str) {
        match v {
            serde_json::Value::Null => panic!("null at {path}"),
            serde_json::Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    no_nulls(x, &format!("{path}[{i}]"));
                }
            }
            serde_json::Value::Object(o) => {
                for (k, x) in o {
                    no_nulls(x, &format!("{path}.{k}"));
                }
            }
            serde_json::Value::Number(n) => {
                assert!(n.as_f64().is_some_and(f64::is_finite), "{path}")
            }
            _ => {}
        }
    }

    fn row_of(method: Method, rtol: f64, evals: u64, err: f64) -> RunRow {
        let mut m = Measured {
            work: Work {
                accepted: evals / 9,
                rejected: 3,
                evals,
            },
            rev2: Work {
                accepted: evals / 18,
                rejected: 1,
                evals: evals / 2,
            },
            samples: Samples {
                acc: vec![err, -err],
                disp: vec![1.0, 1.0],
                force: vec![50.0, 51.0],
                ..Samples::default()
            },
            wall_ms: vec![3.0, 1.0, 2.0],
            cpu_ms: vec![],
        };
        let reference = Samples {
            acc: vec![0.0, 0.0],
            disp: vec![1.0, 1.0],
            force: vec![50.0, 51.0],
            ..Samples::default()
        };
        let refs = ReferenceSamples {
            samples: &reference,
            agree: (1e-9, 1e-16),
        };
        row(
            method,
            "full_11dof",
            "f64",
            "libm",
            rtol,
            &mut m,
            &refs,
            Some(1000.0),
        )
    }

    #[test]
    fn plots_are_written_as_png_of_their_size() {
        use crate::output::Plan;
        let dir = std::env::temp_dir().join(format!("camsim-bench-plot-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let mut runs = Vec::new();
        for (rtol, evals, err) in [
            (1e-3, 100_000, 1e-1),
            (1e-5, 150_000, 1e-3),
            (1e-7, 300_000, 1e-5),
        ] {
            runs.push(row_of(Method::England, rtol, evals, err));
            let mut r = row_of(Method::Dopri5, rtol, 2 * evals, 3.0 * err);
            r.cpu_ms = Some(1.5);
            runs.push(r);
        }
        let mut out = Plan::new(true)
            .dir("--plot", &dir, &plot::FILES)
            .unwrap()
            .open()
            .unwrap();
        plot::draw_runs(
            &mut out,
            &runs,
            500.0,
            (1e-9, 1e-16),
            crate::units::Units::Inch,
        )
        .unwrap();
        out.commit().unwrap();
        for f in plot::FILES {
            let b = std::fs::read(dir.join(f)).unwrap();
            assert_eq!(&b[1..4], b"PNG", "{f}");
            let w = u32::from_be_bytes(b[16..20].try_into().unwrap());
            let h = u32::from_be_bytes(b[20..24].try_into().unwrap());
            assert_eq!((w, h), plot::SIZE, "{f}");
            assert!(b.len() > 10_000, "{f}: {} bytes", b.len());
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn json_runs_have_every_required_number_and_no_null() {
        let runs = vec![
            row_of(Method::England, 1e-4, 90_000, 1e-2),
            row_of(
                Method::Rk4 {
                    steps_per_rev: 16_000,
                },
                0.0,
                64_000,
                1e-3,
            ),
            row_of(Method::Dopri5, 1e-6, 200_000, 1e-2),
        ];
        assert_eq!(runs[0].wall_ms, 2.0); // the median of 3, 1, 2
        assert_eq!(runs[0].err_acc_rms, 1e-2);
        assert!(runs[0].cpu_ms.is_none());
        let v = serde_json::to_value(serde_json::json!({
            "runs": runs,
            "failed": [FailedRun {
                method: "dopri5_ode_solvers".into(),
                scene: "full_11dof".into(),
                precision: "f32".into(),
                math: "libm".into(),
                rtol: 1e-8,
                fixed_steps_per_rev: None,
                status: "failed: step size underflow".into(),
            }],
        }))
        .unwrap();
        no_nulls(&v, "");
        for r in v["runs"].as_array().unwrap() {
            for key in [
                "method",
                "scene",
                "precision",
                "math",
                "rtol",
                "steps",
                "rejected",
                "rhs_evals",
                "wall_ms",
                "err_disp_rms",
                "err_acc_rms",
            ] {
                assert!(r.get(key).is_some(), "{key} missing in {r}");
            }
            let m = r["method"].as_str().unwrap();
            assert!(["england", "rk4", "dopri5"].iter().any(|k| m.contains(k)));
        }
        assert_eq!(v["runs"][1]["rtol"], 0.0);
        assert_eq!(v["runs"][1]["fixed_steps_per_rev"], 16_000);
        assert!(v["runs"][0].get("fixed_steps_per_rev").is_none());
        assert!(v["failed"][0].get("rhs_evals").is_none());
        // One run per method: no front to interpolate along, so no equal-error row.
        assert!(equal_error(&runs, "full_11dof", "f64").is_empty());
    }
}
