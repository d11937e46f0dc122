//! `camsim sweep`: the operating map. The response of the mechanism at every speed of a
//! grid: revolution 2 from the static start (the steady state `camsim jump-speed` judges),
//! on the theoretical cam and, with actual cams, as a distribution over machined cams.
//!
//! Per speed: whether the follower separates (the predicate of [`crate::sim::jumps_at`]:
//! a separation in revolution 2, or a run that leaves the model's valid range after the
//! follower left the cam), the smallest and largest contact force, the RMS deviation of
//! the load's acceleration from the program over the revolution (the residual vibration),
//! the peak cam torque, the peak Hertz stress and the peak drive power. On actual cams:
//! P(jump) with its 95 % Wilson interval, and the median and the 5-95 % band of each
//! quantity. Every speed and every cam is an independent run; the runs go in parallel on
//! a local pool and are collected by index, so the result does not depend on the thread
//! count. The actual cams are the same at every speed (sample i of the master seed).

use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context, Result};
use camsim_core::{jump_verdict, JumpWatch, Observer, Sample};
use camsim_scene_file::units::Unit;
use rayon::prelude::*;
use serde::Serialize;

use crate::actual::Cams;
use crate::report::Report;
use crate::sim::{self, HostDeviation, RunSpec};
use crate::stats::Probability;
use crate::units::{self, Acceleration, Force, Kind, Measure, Power, Stress, Torque, Units};

/// The most speeds a grid may have.
pub const MAX_POINTS: u32 = 1000;

/// The default number of actual cams a speed (P(jump)'s Wilson interval about ±0.1 wide
/// at p = 1/2, ±0.04 at p = 0.05).
pub const DEFAULT_SAMPLES: u64 = 100;

/// A grid of cam speeds: `points` equally spaced speeds from `from` to `to`, rpm.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RpmGrid {
    /// First speed, rpm.
    pub from_rpm: f64,
    /// Last speed, rpm.
    pub to_rpm: f64,
    /// Number of speeds (at least 2).
    pub points: u32,
}

impl RpmGrid {
    /// Spacing of the speeds, rpm.
    pub fn step_rpm(&self) -> f64 {
        (self.to_rpm - self.from_rpm) / f64::from(self.points.max(2) - 1)
    }

    /// The speeds, rpm, rising (the last is exactly `to_rpm`).
    pub fn speeds(&self) -> Vec<f64> {
        let n = self.points.max(2);
        (0..n)
            .map(|k| {
                if k + 1 == n {
                    self.to_rpm
                } else {
                    self.from_rpm + f64::from(k) * self.step_rpm()
                }
            })
            .collect()
    }
}

/// `--rpm FROM:TO:N`: N (2 to [`MAX_POINTS`]) equally spaced speeds from FROM to TO,
/// rpm, FROM below TO, both within a cam speed's plausibility range.
pub fn parse_rpm_grid(s: &str) -> Result<RpmGrid, String> {
    let parts: Vec<&str> = s.split(':').map(str::trim).collect();
    let [a, b, n] = parts.as_slice() else {
        return Err("must be FROM:TO:N (rpm, rpm, number of speeds), e.g. 300:1200:19".into());
    };
    let from = crate::args::rpm(a).map_err(|e| format!("FROM {a}: {e}"))?;
    let to = crate::args::rpm(b).map_err(|e| format!("TO {b}: {e}"))?;
    let points: u32 = n
        .parse()
        .map_err(|_| format!("N {n}: must be a whole number of speeds (2 to {MAX_POINTS})"))?;
    if !(2..=MAX_POINTS).contains(&points) {
        return Err(format!(
            "N {n}: must be 2 to {MAX_POINTS} speeds (a sweep needs at least its two ends)"
        ));
    }
    if from >= to {
        return Err(format!("FROM {a} must be below TO {b} (speeds rise)"));
    }
    Ok(RpmGrid {
        from_rpm: from,
        to_rpm: to,
        points,
    })
}

/// The response of one run (revolution 2 from the static start).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Response {
    /// The follower separated from the cam in revolution 2 (or the run left the model's
    /// valid range after it had separated).
    pub jump: bool,
    /// The run ended early, outside the model's valid range, after the follower had left
    /// the cam: only the contact force (0) is known.
    pub left_model_range: bool,
    /// Smallest contact force in revolution 2, lb (0 when the follower leaves the cam).
    pub min_contact_force_lb: Force,
    /// Largest contact force in revolution 2, lb.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_contact_force_lb: Option<Force>,
    /// RMS of the load acceleration's deviation from the program over revolution 2
    /// (time-weighted over its periods), in/s².
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rms_acceleration_deviation_in_per_s2: Option<Acceleration>,
    /// Largest |output torque on the cam| in revolution 2, lb·in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_cam_torque_lb_in: Option<Torque>,
    /// Largest Hertz contact stress in revolution 2, psi.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_contact_stress_psi: Option<Stress>,
    /// Largest drive power (drive torque × motor speed) in revolution 2, hp.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_drive_power_hp: Option<Power>,
}

/// The extremes of revolution 2 and whether the follower left the cam, sample by sample
/// (core's [`JumpWatch`], the one jump rule).
#[derive(Default)]
struct Watch {
    jump: JumpWatch<f64>,
    force_min: Option<f64>,
    force_max: Option<f64>,
    torque: Option<f64>,
    stress: Option<f64>,
    power: Option<f64>,
}

fn max_into(slot: &mut Option<f64>, v: f64) {
    if v.is_finite() {
        *slot = Some(slot.map_or(v, |o| o.max(v)));
    }
}

impl Observer<f64> for Watch {
    fn needs_stress(&self) -> bool {
        true
    }
    fn observe(&mut self, s: &Sample<f64>) -> ControlFlow<()> {
        let p = &s.point;
        // The watch would stop the run at the first steady-state separation; the sweep
        // goes on to take revolution 2's extremes.
        let _ = self.jump.note_sample(s);
        if s.revolution < 2 {
            return ControlFlow::Continue(());
        }
        if p.in_contact {
            if p.contact_force.is_finite() {
                self.force_min = Some(
                    self.force_min
                        .map_or(p.contact_force, |o| o.min(p.contact_force)),
                );
            }
            max_into(&mut self.force_max, p.contact_force);
        }
        max_into(&mut self.torque, p.torque_out.abs());
        max_into(&mut self.stress, s.contact_stress);
        max_into(&mut self.power, p.torque_drive * p.omega_m);
        ControlFlow::Continue(())
    }
}

/// Whether an error is the model leaving its valid range (docs/MODEL.md §3.20).
pub(crate) fn out_of_model(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        matches!(
            c.downcast_ref::<camsim_core::Error>(),
            Some(camsim_core::Error::OutOfModel { .. })
        )
    }) || format!("{e:#}").contains("left its valid range")
}

/// The response of `spec` (2 revolutions) at `rpm`. A run that fails after the follower
/// left the cam is a jump ([`sim::jumps_at`]'s rule); one that leaves the model's valid
/// range with the follower on the cam is a jump when `out_of_range_jumps` (the design
/// searches' rule on actual cams), an error otherwise.
pub fn respond(spec: &RunSpec, rpm: f64, out_of_range_jumps: bool) -> Result<Response> {
    let mut s = spec.clone();
    s.revolutions = 2;
    s.design.set_speed_rpm(rpm)?;
    let mut w = Watch::default();
    let run = sim::run(&s, &mut w);
    // Core's rule decides; the run itself is kept for its statistics.
    let verdict = jump_verdict(run.as_ref().map(|_| ()).map_err(|_| ()), &w.jump);
    let left_range = Response {
        jump: true,
        left_model_range: true,
        ..Response::default()
    };
    let (r, jump) = match run {
        Ok(r) => (r, verdict.is_ok_and(|v| v.jumped())),
        // A failure after the follower left the cam: a jump.
        Err(_) if verdict.is_ok() => return Ok(left_range),
        Err(e) if out_of_range_jumps && out_of_model(&e) => return Ok(left_range),
        Err(e) => return Err(e.context(format!("simulation at {rpm:.1} rpm failed"))),
    };
    let names = sim::period_names(&s.design);
    let (mut t, mut sum) = (0.0, 0.0);
    for i in 0..names.len() {
        if let Some(p) = r.stats.period(2, i) {
            t += p.duration;
            sum += p.duration * p.rms_acceleration().powi(2);
        }
    }
    Ok(Response {
        jump,
        left_model_range: false,
        min_contact_force_lb: Force::inch(if jump {
            0.0
        } else {
            w.force_min.unwrap_or(0.0)
        }),
        peak_contact_force_lb: w.force_max.map(Force::inch),
        rms_acceleration_deviation_in_per_s2: (t > 0.0)
            .then(|| Acceleration::inch((sum / t).sqrt())),
        peak_cam_torque_lb_in: w.torque.map(Torque::inch),
        peak_contact_stress_psi: w.stress.map(Stress::inch),
        peak_drive_power_hp: w
            .power
            .map(|p| Power::inch(p / crate::verdict::HP_LB_IN_PER_S)),
    })
}

/// The theoretical cam at one speed.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TheoryPoint {
    /// Cam speed, rpm.
    pub rpm: f64,
    /// The response.
    #[serde(flatten)]
    pub response: Response,
}

/// The 5 %, 50 % and 95 % quantiles of a quantity over the actual cams (type 7), over
/// the cams whose run gave it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Band {
    /// 5 % quantile.
    pub p05: f64,
    /// Median.
    pub median: f64,
    /// 95 % quantile.
    pub p95: f64,
    /// Cams that gave the quantity.
    pub cams: u64,
}

impl Band {
    /// The band of `values` (None when empty).
    pub fn of(mut values: Vec<f64>) -> Option<Band> {
        values.retain(|v| v.is_finite());
        values.sort_by(f64::total_cmp);
        let q = |p| crate::study::jump_speed_actual::quantile(&values, p);
        Some(Band {
            p05: q(0.05)?,
            median: q(0.5)?,
            p95: q(0.95)?,
            cams: values.len() as u64,
        })
    }
}

/// The actual cams at one speed.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ActualPoint {
    /// Cam speed, rpm.
    pub rpm: f64,
    /// P(jump) in revolution 2 with its 95 % Wilson interval.
    pub p_jump: Probability,
    /// Runs that left the model's valid range (counted as jumps; their other quantities
    /// are missing from the bands).
    pub left_model_range: u64,
    /// Smallest contact force, lb (0 for a cam whose follower jumps).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_contact_force_lb: Option<Band>,
    /// Largest contact force, lb.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_contact_force_lb: Option<Band>,
    /// RMS acceleration deviation over the revolution, in/s².
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rms_acceleration_deviation_in_per_s2: Option<Band>,
    /// Peak |cam torque|, lb·in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_cam_torque_lb_in: Option<Band>,
    /// Peak Hertz stress, psi.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_contact_stress_psi: Option<Band>,
    /// Peak drive power, hp.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_drive_power_hp: Option<Band>,
}

impl ActualPoint {
    fn of(rpm: f64, rs: &[Response]) -> Self {
        let n = rs.len() as u64;
        let band = |f: fn(&Response) -> Option<f64>| Band::of(rs.iter().filter_map(f).collect());
        ActualPoint {
            rpm,
            p_jump: Probability::of(rs.iter().filter(|r| r.jump).count() as u64, n),
            left_model_range: rs.iter().filter(|r| r.left_model_range).count() as u64,
            min_contact_force_lb: band(|r| Some(r.min_contact_force_lb.in_inch())),
            peak_contact_force_lb: band(|r| r.peak_contact_force_lb.map(Force::in_inch)),
            rms_acceleration_deviation_in_per_s2: band(|r| {
                r.rms_acceleration_deviation_in_per_s2
                    .map(Acceleration::in_inch)
            }),
            peak_cam_torque_lb_in: band(|r| r.peak_cam_torque_lb_in.map(Torque::in_inch)),
            peak_contact_stress_psi: band(|r| r.peak_contact_stress_psi.map(Stress::in_inch)),
            peak_drive_power_hp: band(|r| r.peak_drive_power_hp.map(Power::in_inch)),
        }
    }
}

/// Where the jumps begin on the grid.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct GridOnset {
    /// The highest speed of the grid below the first jump, rpm (absent: the first speed
    /// jumps).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub holds_at_rpm: Option<f64>,
    /// The first speed of the grid that jumps, rpm.
    pub jumps_at_rpm: f64,
    /// The first speed above it where contact holds again (a resonance window), rpm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub holds_again_above_rpm: Option<f64>,
}

/// The first jump of a rising list of (rpm, jumps).
pub fn grid_onset(points: &[(f64, bool)]) -> Option<GridOnset> {
    let k = points.iter().position(|p| p.1)?;
    let at = points.get(k)?.0;
    Some(GridOnset {
        holds_at_rpm: k.checked_sub(1).and_then(|j| points.get(j)).map(|p| p.0),
        jumps_at_rpm: at,
        holds_again_above_rpm: points.iter().skip(k + 1).find(|p| !p.1).map(|p| p.0),
    })
}

/// The actual cams of a sweep.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ActualSweep {
    /// Actual cams a speed (the same cams at every speed).
    pub samples: u64,
    /// Master seed.
    pub seed: u64,
    /// How the cams are made (tolerances, waviness, interval).
    pub profile: crate::study::montecarlo::ProfileSettings,
    /// The model the actual cams ran on.
    pub model: String,
    /// Per speed.
    pub points: Vec<ActualPoint>,
    /// The first speed at which any actual cam jumps.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub first_jump: Option<GridOnset>,
}

/// What `camsim sweep` reports.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SweepReport {
    /// The speeds.
    pub grid: RpmGrid,
    /// The grid's step, rpm.
    pub step_rpm: f64,
    /// The scene's operating speed, rpm.
    pub operating_rpm: f64,
    /// The model of the theoretical cam's runs.
    pub model: String,
    /// The theoretical cam, per speed.
    pub theoretical: Vec<TheoryPoint>,
    /// The theoretical cam's jump onset on the grid.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub theoretical_onset: Option<GridOnset>,
    /// The actual cams (with `--actual`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub actual: Option<ActualSweep>,
    /// Model runs (2 revolutions each).
    pub model_runs: u64,
    /// Worker threads.
    pub threads: usize,
    /// Wall time, s.
    pub wall_s: f64,
}

/// What a sweep runs.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// The scene (its speed is the operating speed; the solver's start is taken as given).
    pub spec: RunSpec,
    /// The speeds.
    pub grid: RpmGrid,
    /// Actual cams: their options and their number a speed.
    pub actual: Option<(Cams, u64)>,
    /// Worker threads.
    pub threads: usize,
    /// A progress bar on a terminal.
    pub progress: bool,
}

/// A model in words (its tolerance in `units`).
pub fn describe(spec: &RunSpec, units: Units) -> String {
    format!(
        "{} follower model, {} DOFs, rtol {:e}, atol {:e} {}, largest step {} rev, {} start, revolution 2 of 2",
        spec.dofs.follower.name(),
        spec.dofs.set().name(),
        spec.solver.rtol,
        units.given(units::LENGTH, spec.solver.atol),
        units.symbol(units::LENGTH),
        spec.solver.max_step_fraction,
        format!("{:?}", spec.solver.start).to_lowercase()
    )
}

/// The actual cams of a sweep: their model, the study's settings and every cam's profile.
struct ActualCams {
    /// The Monte Carlo model of the design searches.
    model: RunSpec,
    /// The study's settings (seed, tolerances, interval).
    settings: crate::study::montecarlo::StudySettings,
    /// Every cam, built once and ridden at every speed.
    profiles: Vec<Arc<HostDeviation>>,
}

/// Runs the sweep (its model described in `units`).
pub fn run(sw: &Sweep, units: Units) -> Result<SweepReport> {
    let t0 = Instant::now();
    let speeds = sw.grid.speeds();
    let nspeeds = speeds.len();
    let op_rpm = camsim_core::rad_per_s_to_rpm(sw.spec.design.omega0);
    let mut spec = sw.spec.clone();
    spec.revolutions = 2;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(sw.threads.max(1))
        // A profile (three arrays of 3601 f64) is built on the stack.
        .stack_size(16 << 20)
        .build()
        .context("cannot start the worker threads")?;
    let actual = match &sw.actual {
        Some((args, n)) => Some(actual_cams(&spec, args, *n, &pool)?),
        None => None,
    };
    let per_speed = actual.as_ref().map_or(0, |a| a.profiles.len());
    // Jobs: every speed's theoretical run, then every (speed, cam).
    let total = nspeeds * (1 + per_speed);
    let responses = respond_all(sw, &pool, &spec, &speeds, actual.as_ref(), op_rpm)?;
    let theoretical: Vec<TheoryPoint> = speeds
        .iter()
        .zip(&responses)
        .map(|(&rpm, &response)| TheoryPoint { rpm, response })
        .collect();
    let theoretical_onset = grid_onset(
        &theoretical
            .iter()
            .map(|p| (p.rpm, p.response.jump))
            .collect::<Vec<_>>(),
    );
    let rest = responses.get(nspeeds..).unwrap_or(&[]);
    let report = SweepReport {
        grid: sw.grid,
        step_rpm: sw.grid.step_rpm(),
        operating_rpm: op_rpm,
        model: describe(&spec, units),
        theoretical,
        theoretical_onset,
        actual: actual.map(|a| actual_sweep(a, &speeds, rest, units)),
        model_runs: total as u64,
        threads: sw.threads.max(1),
        wall_s: t0.elapsed().as_secs_f64(),
    };
    crate::report::ensure_finite(&report)?;
    Ok(report)
}

/// The actual cams: the Monte Carlo model of the design searches, the interval chosen
/// once, every one of the `n` cams built once (on `pool`) to be ridden at every speed.
fn actual_cams(
    spec: &RunSpec,
    args: &Cams,
    n: u64,
    pool: &rayon::ThreadPool,
) -> Result<ActualCams> {
    let mc = crate::study::montecarlo::monte_carlo_model(spec);
    let study = crate::study::montecarlo::Study::from_spec(mc.clone(), args, n)?;
    let profiles: Vec<Result<Arc<HostDeviation>>> = pool.install(|| {
        (0..n)
            .into_par_iter()
            .map(|i| {
                crate::actual::build_profile(&mc.design, &study.actual, i)
                    .map(|(d, _)| Arc::new(d))
                    .with_context(|| format!("actual cam {i}"))
            })
            .collect()
    });
    let profiles = profiles.into_iter().collect::<Result<Vec<_>>>()?;
    Ok(ActualCams {
        model: mc,
        settings: study.settings,
        profiles,
    })
}

/// Every run of the sweep on `pool`, in job order: every speed's theoretical run of `spec`,
/// then every (speed, actual cam). The first failure stops the runs not yet started and is
/// returned.
fn respond_all(
    sw: &Sweep,
    pool: &rayon::ThreadPool,
    spec: &RunSpec,
    speeds: &[f64],
    actual: Option<&ActualCams>,
    op_rpm: f64,
) -> Result<Vec<Response>> {
    let nspeeds = speeds.len();
    let per_speed = actual.map_or(0, |a| a.profiles.len());
    let total = nspeeds * (1 + per_speed);
    let bar = crate::study_limits::progress_bar(
        total as u64,
        sw.progress,
        "{elapsed_precise} [{bar:40}] {pos}/{len} runs, {per_sec}, eta {eta}",
    );
    let stop = AtomicBool::new(false);
    let results: Vec<Option<Result<Response>>> = pool.install(|| {
        (0..total)
            .into_par_iter()
            .map(|j| {
                if stop.load(Ordering::Relaxed) {
                    return None;
                }
                let r = if j < nspeeds {
                    let rpm = speeds.get(j).copied().unwrap_or(op_rpm);
                    respond(spec, rpm, false).context("the theoretical cam")
                } else {
                    let k = (j - nspeeds) / per_speed.max(1);
                    let i = (j - nspeeds) % per_speed.max(1);
                    let rpm = speeds.get(k).copied().unwrap_or(op_rpm);
                    respond_actual(actual, i, rpm)
                };
                if r.is_err() {
                    stop.store(true, Ordering::Relaxed);
                }
                bar.inc(1);
                Some(r)
            })
            .collect()
    });
    bar.finish_and_clear();
    let mut responses = Vec::with_capacity(total);
    for r in results {
        match r {
            Some(r) => responses.push(r?),
            None => anyhow::bail!("a run failed"),
        }
    }
    Ok(responses)
}

/// The response of actual cam `i` at `rpm`.
fn respond_actual(actual: Option<&ActualCams>, i: usize, rpm: f64) -> Result<Response> {
    match actual {
        Some(a) => {
            let mut s = a.model.clone();
            s.profile = a.profiles.get(i).cloned();
            respond(&s, rpm, true).with_context(|| format!("actual cam {i}"))
        }
        None => Err(anyhow::anyhow!("no actual cams")),
    }
}

/// The actual cams' report: at every speed of `speeds`, the distribution over its cams'
/// `responses` (the cams' runs of every speed in turn), and the first speed any cam jumps.
fn actual_sweep(
    a: ActualCams,
    speeds: &[f64],
    responses: &[Response],
    units: Units,
) -> ActualSweep {
    let per_speed = a.profiles.len();
    let points: Vec<ActualPoint> = speeds
        .iter()
        .zip(responses.chunks(per_speed.max(1)))
        .map(|(&rpm, rs)| ActualPoint::of(rpm, rs))
        .collect();
    let first_jump = grid_onset(
        &points
            .iter()
            .map(|p| (p.rpm, p.p_jump.count > 0))
            .collect::<Vec<_>>(),
    );
    ActualSweep {
        samples: per_speed as u64,
        seed: a.settings.seed,
        profile: a.settings.profile,
        model: describe(&a.model, units),
        points,
        first_jump,
    }
}

/// `v` (in `unit`'s inch member, printed with `prec` decimals in inch) in `units`, or
/// `-`.
/// `m` for the text ([`Units::show`]), `-` if the run did not give it.
fn shown<K: Kind>(units: Units, m: Option<Measure<K>>, prec: usize) -> String {
    m.map_or_else(|| "-".to_string(), |m| units.show(m, prec).to_string())
}

fn band_text(units: Units, unit: Unit, b: Option<&Band>, prec: usize) -> String {
    b.map_or_else(
        || "-".to_string(),
        |b| {
            let q = |x| units.q(unit, x, prec);
            format!("{} [{}, {}]", q(b.median), q(b.p05), q(b.p95))
        },
    )
}

fn onset_text(o: &GridOnset, step: f64, narrow: &str) -> String {
    let mut s = match o.holds_at_rpm {
        Some(h) => format!(
            "between {h:.1} and {:.1} rpm (the grid's step {step:.1} rpm; `{narrow}` narrows it)",
            o.jumps_at_rpm
        ),
        None => format!(
            "at or below {:.1} rpm, the grid's first speed",
            o.jumps_at_rpm
        ),
    };
    if let Some(a) = o.holds_again_above_rpm {
        s.push_str(&format!(
            "; contact holds again at {a:.1} rpm (a window between resonances)"
        ));
    }
    s
}

impl Report for SweepReport {
    fn json(&self) -> serde_json::Result<String> {
        crate::report::sorted_pretty_json(self)
    }
    fn text(&self, units: Units) -> String {
        use std::fmt::Write;
        let mut out = String::new();
        let _ = writeln!(
            out,
            "camsim sweep: {} speeds from {:.1} to {:.1} rpm (step {:.1} rpm); revolution 2 of each run; operating speed {:.1} rpm",
            self.grid.points, self.grid.from_rpm, self.grid.to_rpm, self.step_rpm, self.operating_rpm
        );
        let _ = writeln!(out, "\ntheoretical cam ({}):", self.model);
        theory_lines(&mut out, self, units);
        if let Some(a) = &self.actual {
            actual_lines(&mut out, a, self.step_rpm, units);
        }
        let _ = writeln!(
            out,
            "\n{} model runs of 2 revolutions on {} threads, {:.1} s",
            self.model_runs, self.threads, self.wall_s
        );
        out
    }
}

/// The text's force, acceleration and torque column units in `units` (the
/// acceleration's inch label is the inch table's own, `in/s2`).
fn column_units(units: Units) -> (&'static str, &'static str, &'static str) {
    (
        units.symbol(units::FORCE),
        units.label(units::ACCELERATION, "in/s2"),
        units.symbol(units::TORQUE),
    )
}

/// The theoretical cam's table: a row per speed (contact, forces, vibration, torque, stress,
/// power) and its jump onset on the grid.
fn theory_lines(out: &mut String, r: &SweepReport, units: Units) {
    use std::fmt::Write;
    let (f, acc, t) = column_units(units);
    let _ = writeln!(
        out,
        "  {:>8}  {:<7} {:>10} {:>10} {:>13} {:>13} {:>11} {:>9}",
        "rpm",
        "contact",
        format!("Fc min {f}"),
        format!("Fc max {f}"),
        format!("a rms {acc}"),
        format!("T peak {t}"),
        format!("stress {}", units.symbol(units::STRESS)),
        format!("power {}", units.symbol(units::POWER))
    );
    for p in &r.theoretical {
        let _ = writeln!(out, "{}", theory_row(p, units));
    }
    match &r.theoretical_onset {
        Some(o) => {
            let _ = writeln!(
                out,
                "  jump onset {}",
                onset_text(o, r.step_rpm, "camsim jump-speed")
            );
        }
        None => {
            let _ = writeln!(out, "  contact holds at every speed of the grid");
        }
    }
    if r.theoretical.iter().any(|p| p.response.left_model_range) {
        let _ = writeln!(
            out,
            "  (-: the run left the model's valid range after the follower left the cam)"
        );
    }
}

/// The theoretical cam's row of one speed.
fn theory_row(p: &TheoryPoint, units: Units) -> String {
    let r = &p.response;
    format!(
        "  {:>8.1}  {:<7} {:>10} {:>10} {:>13} {:>13} {:>11} {:>9}",
        p.rpm,
        if r.jump { "JUMPS" } else { "holds" },
        units.show(r.min_contact_force_lb, 2),
        shown(units, r.peak_contact_force_lb, 2),
        shown(units, r.rms_acceleration_deviation_in_per_s2, 1),
        shown(units, r.peak_cam_torque_lb_in, 2),
        shown(units, r.peak_contact_stress_psi, 0),
        shown(units, r.peak_drive_power_hp, 3)
    )
}

/// The actual cams' table: how they are made, a row per speed (P(jump) and the bands of
/// force, vibration and torque), the first speed any cam jumps (on a grid of `step` rpm)
/// and the runs that left the model's valid range.
fn actual_lines(out: &mut String, a: &ActualSweep, step: f64, units: Units) {
    use std::fmt::Write;
    let (f, acc, t) = column_units(units);
    let pr = &a.profile;
    let _ = writeln!(
        out,
        "\n{} actual cams a speed, the same at every speed (seed {}; cam ±{} {lu}, roller ±{} {lu}, eccentricity ±{} {lu}; {} profile, {}) on the {}:",
        a.samples,
        a.seed,
        units.given(units::LENGTH, pr.cam_tolerance_in),
        units.given(units::LENGTH, pr.roller_tolerance_in),
        units.given(units::LENGTH, pr.eccentricity_tolerance_in),
        pr.method,
        pr.interval_source,
        a.model,
        lu = units.symbol(units::LENGTH)
    );
    let _ = writeln!(
        out,
        "  median [5 %, 95 %] over the cams; P(jump) with its 95 % Wilson interval"
    );
    let _ = writeln!(
        out,
        "  {:>8}  {:<24} {:<26} {:<26} T peak {t}",
        "rpm",
        "P(jump)",
        format!("Fc min {f}"),
        format!("a rms {acc}")
    );
    for p in &a.points {
        let _ = writeln!(
            out,
            "  {:>8.1}  {:<24} {:<26} {:<26} {}",
            p.rpm,
            p.p_jump.text(3),
            band_text(units, units::FORCE, p.min_contact_force_lb.as_ref(), 2),
            band_text(
                units,
                units::ACCELERATION,
                p.rms_acceleration_deviation_in_per_s2.as_ref(),
                0
            ),
            band_text(units, units::TORQUE, p.peak_cam_torque_lb_in.as_ref(), 1)
        );
    }
    match &a.first_jump {
        Some(o) => {
            let _ = writeln!(
                out,
                "  first actual cam jumps {}",
                onset_text(o, step, "camsim jump-speed --actual")
            );
        }
        None => {
            let _ = writeln!(out, "  no actual cam jumps on the grid");
        }
    }
    let lost: u64 = a.points.iter().map(|p| p.left_model_range).sum();
    if lost > 0 {
        let _ = writeln!(
            out,
            "  {lost} runs left the model's valid range: counted as jumps, left out of the bands"
        );
    }
}

/// The CSV header of [`csv_rows`] in `units`.
pub fn csv_header(actual: bool, units: Units) -> Vec<String> {
    let mut h: Vec<String> = [
        "rpm",
        "jump",
        "min_contact_force_lb",
        "peak_contact_force_lb",
        "rms_acceleration_deviation_in_per_s2",
        "peak_cam_torque_lb_in",
        "peak_contact_stress_psi",
        "peak_drive_power_hp",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    if actual {
        h.extend(
            ["actual_p_jump", "actual_p_jump_lo95", "actual_p_jump_hi95"]
                .iter()
                .map(|s| s.to_string()),
        );
        for q in BANDED {
            for s in ["p05", "median", "p95"] {
                h.push(format!("actual_{q}_{s}"));
            }
        }
    }
    // In the output's family: `min_contact_force_n`, `actual_peak_cam_torque_n_m_p95`.
    h.into_iter().map(|k| csv_key(&k, units).0).collect()
}

/// A CSV column's name and factor in `u` (a banded column's statistic, `_p05`,
/// `_median` or `_p95`, after its unit).
fn csv_key(k: &str, u: Units) -> (String, f64) {
    for s in ["_p05", "_median", "_p95"] {
        if let Some(stem) = k.strip_suffix(s) {
            let (key, factor) = units::key_in(stem, u);
            return (format!("{key}{s}"), factor);
        }
    }
    units::key_in(k, u)
}

/// The banded quantities' names, in CSV order.
const BANDED: [&str; 6] = [
    "min_contact_force_lb",
    "peak_contact_force_lb",
    "rms_acceleration_deviation_in_per_s2",
    "peak_cam_torque_lb_in",
    "peak_contact_stress_psi",
    "peak_drive_power_hp",
];

/// One CSV row per speed (empty fields for values a run did not give), in `units`.
pub fn csv_rows(r: &SweepReport, units: Units) -> Vec<Vec<String>> {
    // In `units` (times 1 in inch: the same digits). The factors by column name, as the
    // header's.
    let factor = |name: &str| csv_key(name, units).1;
    let (kf, ka, kt, ks, kp) = (
        factor("min_contact_force_lb"),
        factor("rms_acceleration_deviation_in_per_s2"),
        factor("peak_cam_torque_lb_in"),
        factor("peak_contact_stress_psi"),
        factor("peak_drive_power_hp"),
    );
    let g = |v: Option<f64>, k: f64| v.map_or_else(String::new, |x| format!("{}", x * k));
    r.theoretical
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let t = &p.response;
            let mut row = vec![
                format!("{}", p.rpm),
                u8::from(t.jump).to_string(),
                format!("{}", t.min_contact_force_lb.in_inch() * kf),
                g(t.peak_contact_force_lb.map(Force::in_inch), kf),
                g(
                    t.rms_acceleration_deviation_in_per_s2
                        .map(Acceleration::in_inch),
                    ka,
                ),
                g(t.peak_cam_torque_lb_in.map(Torque::in_inch), kt),
                g(t.peak_contact_stress_psi.map(Stress::in_inch), ks),
                g(t.peak_drive_power_hp.map(Power::in_inch), kp),
            ];
            if let Some(a) = r.actual.as_ref().and_then(|a| a.points.get(k)) {
                row.push(format!("{}", a.p_jump.p));
                row.push(format!("{}", a.p_jump.lo95));
                row.push(format!("{}", a.p_jump.hi95));
                for (b, k) in [
                    (&a.min_contact_force_lb, kf),
                    (&a.peak_contact_force_lb, kf),
                    (&a.rms_acceleration_deviation_in_per_s2, ka),
                    (&a.peak_cam_torque_lb_in, kt),
                    (&a.peak_contact_stress_psi, ks),
                    (&a.peak_drive_power_hp, kp),
                ] {
                    row.push(g(b.map(|b| b.p05), k));
                    row.push(g(b.map(|b| b.median), k));
                    row.push(g(b.map(|b| b.p95), k));
                }
            }
            row
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_parsing() {
        let g = parse_rpm_grid("300:1200:19").unwrap();
        assert_eq!(g.step_rpm(), 50.0);
        let s = g.speeds();
        assert_eq!((s.len(), s[0], s[1], s[18]), (19, 300.0, 350.0, 1200.0));
        for bad in [
            "300:1200:1",
            "1200:300:5",
            "a:b:c",
            "300:1200",
            "0:100:3",
            "300:1200:x",
        ] {
            assert!(parse_rpm_grid(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn onset_on_the_grid() {
        let p = [
            (1.0, false),
            (2.0, false),
            (3.0, true),
            (4.0, false),
            (5.0, true),
        ];
        let o = grid_onset(&p).unwrap();
        assert_eq!(o.holds_at_rpm, Some(2.0));
        assert_eq!(o.jumps_at_rpm, 3.0);
        assert_eq!(o.holds_again_above_rpm, Some(4.0));
        assert!(grid_onset(&[(1.0, false)]).is_none());
        let o = grid_onset(&[(1.0, true)]).unwrap();
        assert_eq!(o.holds_at_rpm, None);
    }

    #[test]
    fn band_quantiles() {
        let b = Band::of((0..=100).map(f64::from).collect()).unwrap();
        assert_eq!((b.p05, b.median, b.p95, b.cams), (5.0, 50.0, 95.0, 101));
        assert!(Band::of(vec![]).is_none());
    }
}
