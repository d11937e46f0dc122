//! `camsim models` (formerly `camsim scenes`): which scene is accurate enough for which
//! question. Every scene of the regulated drive (the full 22-state model, the vertical one, and the reduced followers
//! of docs/MODEL.md §10) at the chip's tolerance, against the full model at a tight one:
//! state size, memory, work and time per revolution, the stiffest eigenvalue left (what
//! bounds the step), and the errors on the jump-onset speed, the timing at the
//! firmware's lift points, the smallest contact force and the load's acceleration.

use std::fmt::Write;
use std::time::Instant;

use anyhow::{Context, Result};
use camsim_core::{
    simulate, steady_state, timing_points, CamModel, Design, DofSet, DriveKind, England,
    FollowerModel, RegulatedFull, Scene, SceneId, SceneVisitor, SolverSettings, Start, SteadyState,
    SteadyStateObserver, StepRule, TheoreticalLift, TIMING_POINTS,
};
use serde::Serialize;

use crate::bench::methods::{self, Method, Work};
use crate::bench::sample::{Sampler, Samples};
use crate::bench::stability;
use crate::bench::{design_at, median, onset_by_bisection, scene_jumps_at, ONSET_BRACKET};
use crate::report::{sorted_pretty_json, Report};

/// Command-line options of `camsim models`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Cam speed of the work, time and error columns, rpm.
    #[arg(long, default_value_t = 800.0, allow_hyphen_values = true, value_parser = crate::args::rpm)]
    pub rpm: f64,
    /// Fewer timed repetitions and a coarser jump-onset bisection (CI).
    #[arg(long)]
    pub quick: bool,
    /// Print JSON: {"rows": [...], ...}.
    #[arg(long)]
    pub json: bool,
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
    /// The scene's own onset, converged (rtol [`CONVERGED_RTOL`]): the model's error
    /// without the solver's, rpm.
    pub model_onset_rpm: f64,
    /// Its error against the reference's, %.
    pub model_onset_err_pct: f64,
    /// Smallest contact force of revolution 2, lb.
    pub fmin_lb: f64,
    /// Its error, lb.
    pub fmin_err_lb: f64,
    /// Largest timing error difference at the 6 lift points, degrees of cam angle.
    pub timing_err_deg: f64,
    /// RMS error of the load acceleration over revolution 2 (every 0.5°), in/s².
    pub acc_rms_err: f64,
    /// ... over the signal's RMS.
    pub acc_rms_rel: f64,
    /// Accurate enough for the jump-onset speed ([`enough::ONSET_REL`]).
    pub ok_onset: bool,
    /// ... for the smallest contact force ([`enough::FMIN_LB`]).
    pub ok_fmin: bool,
    /// ... for the timing at the lift points ([`enough::TIMING_DEG`]).
    pub ok_timing: bool,
    /// ... for the acceleration waveform ([`enough::ACC_REL`]).
    pub ok_acc: bool,
}

/// The reference (the full model at [`REFERENCE_RTOL`]).
#[derive(Clone, Debug, Serialize)]
pub struct SceneReference {
    /// Relative tolerance.
    pub rtol: f64,
    /// Jump-onset speed, rpm.
    pub onset_rpm: f64,
    /// Smallest contact force of revolution 2, lb.
    pub fmin_lb: f64,
    /// Timing errors at the lift points against the program, degrees.
    pub timing_deg: [f64; TIMING_POINTS],
    /// RMS of the load acceleration over revolution 2, in/s².
    pub acc_rms: f64,
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

struct Truth {
    reference: SceneReference,
    samples: Samples,
    steady: SteadyState<f64>,
    resolution: f64,
}

/// The jump-onset speed of scene `S` with `settings` by bisection in the bench's bracket
/// to `resolution`.
fn onset<S: Scene, const N: usize>(settings: &SolverSettings<f64>, resolution: f64) -> Result<f64> {
    let design = Design::reference();
    onset_by_bisection(ONSET_BRACKET, resolution, |rpm| {
        scene_jumps_at::<f64, S, N>(Method::England, &design, rpm, settings)
    })
}

/// Revolution 2's samples (and states) and work of England on scene `S`.
fn sampled<S: Scene, const N: usize>(
    model: &CamModel<f64, S, N>,
    settings: &SolverSettings<f64>,
) -> Result<(Samples, Work)> {
    let mut sampler = Sampler::new(model, 2, Some(2)).keep_states();
    let work = methods::run(Method::England, model, settings, 2, &mut sampler)?;
    anyhow::ensure!(sampler.complete(), "revolution 2 was not sampled whole");
    Ok((sampler.samples, work))
}

/// A scene's name in the table: `full`, `vertical` or its follower model's.
fn scene_name<S: Scene>(follower: FollowerModel) -> &'static str {
    if S::QUASI_STATIC.is_empty() {
        if S::DOFS == camsim_core::DofSet::ALL {
            "full"
        } else {
            "vertical"
        }
    } else {
        follower.name()
    }
}

/// The steady state of `repeat` timed runs of 2 revolutions of `model` (checked equal to
/// `steady_state`'s, the chip's pipeline) and their times, ms.
fn timed_steady_state<S: Scene, const N: usize>(
    model: &CamModel<f64, S, N>,
    design: &Design<f64>,
    settings: &SolverSettings<f64>,
    rpm: f64,
    repeat: usize,
    name: &str,
) -> Result<(SteadyState<f64>, Vec<f64>)> {
    let mut times = Vec::new();
    let mut steady = None;
    let points = timing_points(&design.program);
    for _ in 0..repeat {
        // The simulation of 2 revolutions alone (the model is built once, beforehand):
        // what `steady_state` runs after building it.
        let mut obs = SteadyStateObserver::new(2, points);
        let t0 = Instant::now();
        simulate(model, settings, 2, &mut obs)?;
        times.push(t0.elapsed().as_secs_f64() * 1e3);
        steady = Some(obs.result);
    }
    // The same as the chip's pipeline computes it.
    anyhow::ensure!(
        steady
            == Some(steady_state::<f64, S, N, _>(
                design,
                TheoreticalLift,
                rpm,
                settings
            )?),
        "{name}: the timed runs differ from steady_state"
    );
    Ok((steady.context("no timed run")?, times))
}

/// One row of the table: scene `S` with `follower` at `rtol`, against `truth`.
fn row<S: Scene, const N: usize>(
    follower: FollowerModel,
    rtol: f64,
    truth: &Truth,
    rpm: f64,
    repeat: usize,
) -> Result<SceneRow> {
    let name = scene_name::<S>(follower);
    let settings = scene_settings(rtol);
    let design = design_at(rpm)?;
    let model = CamModel::<f64, S, N>::new(design.clone())?;
    let (samples, work) = sampled(&model, &settings).with_context(|| name.to_string())?;
    let stab = stability::analyse(&model, &settings, &samples.t, &samples.states, 4)?;
    let (steady, mut times) = timed_steady_state(&model, &design, &settings, rpm, repeat, name)?;
    let onset_rpm = onset::<S, N>(&settings, truth.resolution)?;
    let model_onset_rpm = onset::<S, N>(&scene_settings(CONVERGED_RTOL), truth.resolution)?;
    let r = &truth.reference;
    let model_onset_err_pct = 100.0 * (model_onset_rpm - r.onset_rpm) / r.onset_rpm;
    let timing_err_deg = steady
        .timing_deg
        .iter()
        .zip(&truth.steady.timing_deg)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let acc_rms_err = Samples::rms_diff(&samples.acc, &truth.samples.acc);
    let onset_err_pct = 100.0 * (onset_rpm - r.onset_rpm) / r.onset_rpm;
    let fmin_err_lb = steady.min_contact_force - truth.steady.min_contact_force;
    let attempted = (work.accepted + work.rejected).max(1) as f64;
    Ok(SceneRow {
        scene: name.to_string(),
        follower: follower.name(),
        dofs: S::LAYOUT.degrees_of_freedom(),
        states: N,
        model_bytes: size_of::<CamModel<f64, S, N>>(),
        solver_bytes: size_of::<England<f64, N>>(),
        model_f32_bytes: size_of::<CamModel<f32, S, N>>(),
        solver_f32_bytes: size_of::<England<f32, N>>(),
        rtol,
        steps_per_rev: work.accepted as f64 / 2.0,
        rejected_pct: 100.0 * work.rejected as f64 / attempted,
        rhs_evals_per_rev: work.evals as f64 / 2.0,
        ms_2rev: median(&mut times),
        stiffest_rad_s: stab.rho_max,
        stiffest_eigenvalue: stab.stiffest_eigenvalue,
        limit_steps_per_rev: stab.england_double_steps_per_rev,
        onset_rpm,
        onset_err_pct,
        model_onset_rpm,
        model_onset_err_pct,
        fmin_lb: steady.min_contact_force,
        fmin_err_lb,
        timing_err_deg,
        acc_rms_err,
        acc_rms_rel: acc_rms_err / r.acc_rms,
        ok_onset: onset_err_pct.abs().max(model_onset_err_pct.abs()) <= 100.0 * enough::ONSET_REL,
        ok_fmin: fmin_err_lb.abs() <= enough::FMIN_LB,
        ok_timing: timing_err_deg <= enough::TIMING_DEG,
        ok_acc: acc_rms_err / r.acc_rms <= enough::ACC_REL,
    })
}

/// The full model (the reference's scene) and its state count.
type Full = RegulatedFull;
const NF: usize = <RegulatedFull as Scene>::N;

/// The reference: the full model's run, steady state and onset at [`REFERENCE_RTOL`].
fn reference_truth(rpm: f64, resolution: f64) -> Result<Truth> {
    let tight = scene_settings(REFERENCE_RTOL);
    let design = design_at(rpm)?;
    let model = CamModel::<f64, Full, NF>::new(design.clone())?;
    let (samples, _) = sampled(&model, &tight).context("the reference run")?;
    let steady = steady_state::<f64, Full, NF, _>(&design, TheoreticalLift, rpm, &tight)?;
    let onset_rpm = onset::<Full, NF>(&tight, resolution)?;
    Ok(Truth {
        reference: SceneReference {
            rtol: REFERENCE_RTOL,
            onset_rpm,
            fmin_lb: steady.min_contact_force,
            timing_deg: steady.timing_deg,
            acc_rms: Samples::rms(&samples.acc),
        },
        samples,
        steady,
        resolution,
    })
}

/// The row of the vertical regulated scene with `follower`'s model (camsim-core's
/// SceneId).
fn follower_row(
    follower: FollowerModel,
    rtol: f64,
    truth: &Truth,
    rpm: f64,
    repeat: usize,
) -> Result<SceneRow> {
    struct Row<'a> {
        follower: FollowerModel,
        rtol: f64,
        truth: &'a Truth,
        rpm: f64,
        repeat: usize,
    }
    impl SceneVisitor for Row<'_> {
        type Output = Result<SceneRow>;
        fn visit<S: Scene, const N: usize>(self) -> Self::Output {
            row::<S, N>(self.follower, self.rtol, self.truth, self.rpm, self.repeat)
        }
    }
    let id = SceneId::find(
        DriveKind::Regulated,
        DofSet::VERTICAL,
        follower.quasi_static(),
    )
    .with_context(|| format!("no vertical regulated scene for {}", follower.name()))?;
    id.visit(Row {
        follower,
        rtol,
        truth,
        rpm,
        repeat,
    })
}

/// Measures every scene, with a progress bar on a terminal (`progress`).
pub fn measure(rpm: f64, quick: bool, progress: bool) -> Result<ScenesReport> {
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
        rows.push(row::<Full, NF>(
            FollowerModel::Full,
            rtol,
            &truth,
            rpm,
            repeat,
        )?);
        bar.inc(1);
        for follower in FollowerModel::ALL {
            rows.push(follower_row(follower, rtol, &truth, rpm, repeat)?);
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

/// Runs the command.
pub fn run(args: Args, units: crate::units::Units) -> Result<()> {
    let report = measure(args.rpm, args.quick, true)?;
    crate::report::print(&report, args.json, units)
}

/// A stated value in at most 3 significant digits: `1` lb, `4.45` N.
fn short(x: f64) -> String {
    let v: f64 = format!("{x:.2e}").parse().unwrap_or(x);
    format!("{v}")
}

/// A stated tolerance in at most 3 significant digits, scientific: `1e-8` in,
/// `2.54e-7` mm.
fn short_e(x: f64) -> String {
    let v: f64 = format!("{x:.2e}").parse().unwrap_or(x);
    format!("{v:e}")
}

fn yes(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}

impl Report for ScenesReport {
    fn json(&self) -> serde_json::Result<String> {
        sorted_pretty_json(self)
    }

    fn text(&self, _units: crate::units::Units) -> String {
        let acc = crate::units::axis(crate::units::ACCELERATION).1;
        let mut s = self.heading();
        self.error_table(&mut s);
        self.verdict_table(&mut s);
        let _ = writeln!(
            s,
            "model/solver: size_of in f64, bytes; steps/r: accepted double steps per revolution; limit/r: the fewest the scene's\n\
             Jacobian eigenvalues allow England (stiffest: largest spectral radius, 1/s); ms/2rev: the 2 revolutions of one\n\
             steady-state evaluation (the chip's pipeline; the model built beforehand), median; onset%: at the row's rtol; model%: the scene converged (rtol 1e-6), the model's own\n\
             error; the onset verdict needs both; acc err: RMS over revolution 2 every 0.5°, {acc}; {:.1} s in all",
            self.seconds
        );
        s
    }
}

impl ScenesReport {
    /// What was run, and the reference's values.
    fn heading(&self) -> String {
        use crate::units::{axis, q, symbol, value, ACCELERATION, FORCE, LENGTH};
        let mut s = String::new();
        let r = &self.reference;
        // Forces, lengths and accelerations in the output's family (`--units`).
        let (lb, acc) = (symbol(FORCE), axis(ACCELERATION).1);
        let _ = writeln!(
            s,
            "camsim models{}: the reference design at {} rpm, regulated drive, static start, 2 revolutions; every scene at\n\
             rtol 1e-3 (the chip's) and 1e-2, atol {} {}, largest step 1/100 revolution, England as `run` uses it; errors\n\
             against the full model at rtol {:.0e}: jump onset {:.2} rpm, smallest contact force {} {lb}, load acceleration\n\
             RMS {:.4e} {acc}",
            if self.quick { " --quick" } else { "" },
            self.rpm,
            short_e(value(LENGTH, scene_settings(ROW_RTOLS[0]).atol)),
            symbol(LENGTH),
            r.rtol,
            r.onset_rpm,
            q(FORCE, r.fmin_lb, 3),
            value(ACCELERATION, r.acc_rms)
        );
        s
    }

    /// Each row's cost and its errors against the reference.
    fn error_table(&self, s: &mut String) {
        use crate::units::{q, value, ACCELERATION, FORCE};
        let _ = writeln!(
            s,
            "{:<24} {:>5} {:>4} {:>3} {:>6} {:>6} {:>7} {:>5} {:>8} {:>7} {:>9} {:>7} {:>8} {:>8} {:>8} {:>8} {:>9} {:>8}",
            "scene", "rtol", "N", "dof", "model", "solver", "steps/r", "rej%", "evals/r", "ms/2rev", "stiffest", "limit/r",
            "onset", "onset%", "model%", "Fmin err", "timing°", "acc err"
        );
        for w in &self.rows {
            let _ = writeln!(
                s,
                "{:<24} {:>5.0e} {:>4} {:>3} {:>6} {:>6} {:>7.0} {:>5.1} {:>8.0} {:>7.2} {:>9.3e} {:>7.0} {:>8.2} {:>+8.3} {:>+8.3} {:>+8} {:>9.2e} {:>8.2e}",
                w.scene,
                w.rtol,
                w.states,
                w.dofs,
                w.model_bytes,
                w.solver_bytes,
                w.steps_per_rev,
                w.rejected_pct,
                w.rhs_evals_per_rev,
                w.ms_2rev,
                w.stiffest_rad_s,
                w.limit_steps_per_rev,
                w.onset_rpm,
                w.onset_err_pct,
                w.model_onset_err_pct,
                q(FORCE, w.fmin_err_lb, 3),
                w.timing_err_deg,
                value(ACCELERATION, w.acc_rms_err)
            );
        }
    }

    /// Which rows are accurate enough, and their f32 bytes.
    fn verdict_table(&self, s: &mut String) {
        use crate::units::{symbol, value, FORCE};
        let lb = symbol(FORCE);
        let _ = writeln!(
            s,
            "\naccurate enough for (onset within {:.0} %, Fmin within {} {lb}, timing within {}°, acceleration RMS error within {:.0} % of the signal):",
            100.0 * enough::ONSET_REL,
            short(value(FORCE, enough::FMIN_LB)),
            enough::TIMING_DEG,
            100.0 * enough::ACC_REL
        );
        let _ = writeln!(
            s,
            "{:<24} {:>5} {:>6} {:>6} {:>7} {:>13} {:>9}",
            "scene", "rtol", "onset", "Fmin", "timing", "acceleration", "f32 bytes"
        );
        for w in &self.rows {
            let _ = writeln!(
                s,
                "{:<24} {:>5.0e} {:>6} {:>6} {:>7} {:>13} {:>9}",
                w.scene,
                w.rtol,
                yes(w.ok_onset),
                yes(w.ok_fmin),
                yes(w.ok_timing),
                yes(w.ok_acc),
                w.model_f32_bytes + w.solver_f32_bytes
            );
        }
    }
}
