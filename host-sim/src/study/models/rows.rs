//! The rows of the models study: the reference (the full model at a tight tolerance)
//! and each scene's work, stiffness and errors against it.

use std::time::Instant;

use anyhow::{Context, Result};
use camsim_core::{
    simulate, steady_state, timing_points, CamModel, Design, DofSet, DriveKind, England,
    FollowerModel, RegulatedFull, Scene, SceneId, SceneVisitor, SolverSettings, SteadyState,
    SteadyStateObserver, TheoreticalLift,
};

use super::{enough, scene_settings, SceneReference, SceneRow, CONVERGED_RTOL, REFERENCE_RTOL};
use crate::bench::methods::{self, Method, Work};
use crate::bench::sample::{Sampler, Samples};
use crate::bench::stability;
use crate::bench::{design_at, median, onset_by_bisection, scene_jumps_at, ONSET_BRACKET};
use crate::units::{Acceleration, Force};

/// The reference's values and what the rows are compared with.
pub(super) struct Truth {
    pub(super) reference: SceneReference,
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

/// One row of the table to measure: `follower`'s scene at `rtol`, against `truth`, at
/// `rpm`, timed `repeat` times.
#[derive(Clone, Copy)]
pub(super) struct Row<'a> {
    pub(super) follower: FollowerModel,
    pub(super) rtol: f64,
    pub(super) truth: &'a Truth,
    pub(super) rpm: f64,
    pub(super) repeat: usize,
}

impl SceneVisitor for Row<'_> {
    type Output = Result<SceneRow>;
    fn visit<S: Scene, const N: usize>(self) -> Self::Output {
        row::<S, N>(self)
    }
}

/// The row of scene `S` (`N` states).
pub(super) fn row<S: Scene, const N: usize>(at: Row) -> Result<SceneRow> {
    let Row {
        follower,
        rtol,
        truth,
        rpm,
        repeat,
    } = at;
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
        fmin_lb: Force::inch(steady.min_contact_force),
        fmin_err_lb: Force::inch(fmin_err_lb),
        timing_err_deg,
        acc_rms_err: Acceleration::inch(acc_rms_err),
        acc_rms_rel: acc_rms_err / r.acc_rms.in_inch(),
        ok_onset: onset_err_pct.abs().max(model_onset_err_pct.abs()) <= 100.0 * enough::ONSET_REL,
        ok_fmin: fmin_err_lb.abs() <= enough::FMIN_LB,
        ok_timing: timing_err_deg <= enough::TIMING_DEG,
        ok_acc: acc_rms_err / r.acc_rms.in_inch() <= enough::ACC_REL,
    })
}

/// The full model (the reference's scene) and its state count.
pub(super) type Full = RegulatedFull;
pub(super) const NF: usize = <RegulatedFull as Scene>::N;

/// The reference: the full model's run, steady state and onset at [`REFERENCE_RTOL`].
pub(super) fn reference_truth(rpm: f64, resolution: f64) -> Result<Truth> {
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
            fmin_lb: Force::inch(steady.min_contact_force),
            timing_deg: steady.timing_deg,
            acc_rms: Acceleration::inch(Samples::rms(&samples.acc)),
        },
        samples,
        steady,
        resolution,
    })
}

/// The row of the vertical regulated scene with `at.follower`'s model (camsim-core's
/// SceneId).
pub(super) fn follower_row(at: Row) -> Result<SceneRow> {
    let id = SceneId::find(
        DriveKind::Regulated,
        DofSet::VERTICAL,
        at.follower.quasi_static(),
    )
    .with_context(|| format!("no vertical regulated scene for {}", at.follower.name()))?;
    id.visit(at)
}
