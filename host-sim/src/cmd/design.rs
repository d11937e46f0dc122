//! `camsim design`: what must be built, found by search on the model.
//!
//! `camsim design spring`: the smallest return-spring rate (at the scene's preload length;
//! its mass follows the rate by the wire-and-coil model, core's `HelicalSpring`) that
//! holds contact with a margin: on the theoretical cam, contact in steady state at
//! `(1 + margin/100)` times the operating speed ([`crate::sim::jumps_at`], the jump
//! predicate of `camsim jump-speed`); with `--actual`, the upper end of the 95 % Wilson
//! interval of P(jump) at the operating speed over `--samples` actual cams at most
//! `--p-max` (the Monte Carlo of `camsim montecarlo`, on the quasi-static-cantilever
//! follower that docs/RESULTS.md "Reduced scenes" shows adequate on actual cams). The search is
//! core's [`OnsetSearch`] (doubling from [`START_RATE`], then bisection to
//! `--resolution`): bounded, and deterministic (the same cams, seeded, at every rate,
//! collected by index whatever the thread count).

use std::time::Instant;

use anyhow::{anyhow, bail, Result};
use camsim_core::{Onset, OnsetSearch, Start};
use serde::Serialize;

use crate::actual::{intervals_for, ActualArgs};
use crate::args::{spec_from, SceneArgs};
use crate::report::Report;
use crate::sim::{self, RunSpec};
use crate::stats::Probability;
use crate::study::coil_spring::{candidates, CoilChoice, CoilQuery, Rejections};
use crate::study::montecarlo::{threads, ProfileSettings, Study};
use crate::units;

/// Command-line options of `camsim design`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// What to design.
    #[command(subcommand)]
    pub what: What,
}

/// The design searches.
#[derive(clap::Subcommand, Debug)]
pub enum What {
    /// The smallest return-spring rate that holds contact with a margin (theoretical cam),
    /// or with P(jump) <= --p-max on actual cams (--actual).
    Spring(SpringArgs),
    /// The highest cam speed at which P(jump) on actual cams is <= --p-max (its upper 95 %
    /// bound), beside the theoretical cam's jump onset.
    Speed(McArgs),
    /// The loosest cam and roller tolerance (a factor on VI.1's ±0.0005/±0.0001 in) at
    /// which P(jump) on actual cams at the operating speed is <= --p-max.
    Tolerance(McArgs),
}

/// Command-line options of the Monte Carlo searches (`design speed`, `design tolerance`).
#[derive(clap::Args, Debug)]
#[command(mut_arg("actual", |a| a.hide(true)))]
pub struct McArgs {
    /// The scene and its overrides (the operating speed is its --rpm).
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Largest acceptable P(jump) (its upper 95 % Wilson bound) (0-1).
    #[arg(long, default_value_t = 0.01, allow_hyphen_values = true, value_parser = crate::args::unit_interval)]
    pub p_max: f64,
    /// Actual cams a step (default: the fewest whose upper bound can be at most --p-max
    /// with no jump, 381 for 0.01).
    #[arg(long, value_parser = crate::args::whole_u64::<1, 1_000_000>)]
    pub samples: Option<u64>,
    /// Worker threads (default: every core). The answer does not depend on it.
    #[arg(long, value_parser = crate::args::whole_u32::<1, 1024>)]
    pub threads: Option<u32>,
    /// The actual cams, as montecarlo's (the same cams at every step; the waviness
    /// matters: the tolerance that passes depends strongly on it). `design tolerance`
    /// searches the cam tolerance, holds the roller and eccentricity tolerances as given,
    /// and takes a list of FPRs.
    #[command(flatten)]
    pub actual: ActualArgs,
    /// `design tolerance` only: search the roughest waviness instead, the highest FPR
    /// (the shortest waves: the acceleration a wave imposes grows as FPR², docs/MODEL.md
    /// §9.6) that passes at the tolerance --tolerance-factor.
    #[arg(long, conflicts_with = "waviness_fpr")]
    pub waviness: bool,
    /// With --waviness: the tolerances held, a factor on VI.1's (default 1).
    #[arg(long, value_name = "FACTOR", allow_hyphen_values = true, value_parser = tolerance_factor, requires = "waviness")]
    pub tolerance_factor: Option<f64>,
    /// CI's quick mode: a coarse bracket and --p-max at least 0.1 (35 cams a step).
    #[arg(long)]
    pub quick: bool,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// The P(jump) limit of a Monte Carlo search (at least [`QUICK_P_MAX`] in the quick mode)
/// and its actual cams a step (`samples`, or the fewest that can pass).
/// A `--p-max` that needs more cams than any study may take is refused
/// ([`crate::study_limits::check_p_max`]).
fn p_max_and_samples(p_max: f64, quick: bool, samples: Option<u64>) -> Result<(f64, u64)> {
    use crate::study_limits::{check_p_max, MAX_STUDY_SAMPLES};
    let p = if quick { p_max.max(QUICK_P_MAX) } else { p_max };
    if samples.is_none() {
        let smallest = Probability::of(0, MAX_STUDY_SAMPLES).hi95;
        check_p_max(p, samples_for(p), smallest)?;
    }
    Ok((p, samples.unwrap_or_else(|| samples_for(p))))
}

/// Times one actual cam of `mc` and refuses a search of up to `steps` steps of `n` cams
/// past the study time limit ([`crate::study_limits::check_search`]), before it starts.
fn check_search_time(
    mc: &RunSpec,
    actual: &ActualArgs,
    n: u64,
    steps: u64,
    nthreads: usize,
) -> Result<()> {
    let t = Instant::now();
    // Only its time is wanted: a cam that leaves the model's range is a jump to the search.
    let _ = Study::from_spec(mc.clone(), actual, 1)?.run(&[0], 1, false);
    crate::study_limits::check_search(t.elapsed().as_secs_f64(), n, steps, nthreads)?;
    Ok(())
}

/// The most steps of a search from `start` doubling to `max`, then halving its bracket to
/// `resolution`.
fn search_steps(start: f64, max: f64, resolution: f64) -> u64 {
    let up = (max / start).log2().ceil().max(0.0);
    let down = (max / resolution).log2().ceil().max(0.0);
    (up + down) as u64 + 1
}

/// P(jump) in revolution 2 over `n` actual cams of `mc` (`actual`'s tolerances and seed).
/// When the perfect cam already separates every cam counts as jumping, without its Monte
/// Carlo; a cam thrown out of the model's valid range did not hold contact. Adds the model
/// runs to `runs`.
fn p_jump_on_actual_cams(
    mc: &RunSpec,
    actual: &ActualArgs,
    n: u64,
    nthreads: usize,
    runs: &mut u64,
) -> Result<Probability> {
    let op_rpm = camsim_core::rad_per_s_to_rpm(mc.design.omega0);
    *runs += 1;
    if sim::jumps_at(mc, op_rpm)? {
        return Ok(Probability::of(n, n));
    }
    let study = Study::from_spec(mc.clone(), actual, n)?;
    let indices: Vec<u64> = (0..n).collect();
    *runs += n;
    match study.run(&indices, nthreads, true) {
        Ok(recs) => Ok(Probability::of(
            recs.iter().filter(|r| r.jump()).count() as u64,
            n,
        )),
        Err(e) if format!("{e:#}").contains("left its valid range") => Ok(Probability::of(n, n)),
        Err(e) => Err(e),
    }
}

/// What a Monte Carlo design search found.
#[derive(Clone, Debug, Serialize)]
pub struct McSearchReport {
    /// `speed` or `tolerance`.
    pub search: String,
    /// The answer: the highest passing speed (rpm) or the loosest passing tolerance factor.
    pub answer: f64,
    /// Its unit: `rpm`, `factor on VI.1's tolerances` or `FPR`.
    pub unit: String,
    /// With `design tolerance --waviness`: the factor on VI.1's tolerances held.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tolerance_factor: Option<f64>,
    /// The nearest value tried that fails (absent: none failed up to the search's limit).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failing: Option<f64>,
    /// Width of the final bracket, in the answer's unit.
    pub bracket: f64,
    /// With `design tolerance`: the cam profile tolerance at the answer, ± in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cam_tolerance_in: Option<f64>,
    /// With `design tolerance`: the roller tolerance (held), ± in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub roller_tolerance_in: Option<f64>,
    /// With `design tolerance`: the eccentricity tolerance (held), ± in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub eccentricity_tolerance_in: Option<f64>,
    /// With `design tolerance` (not --waviness): the cams' waviness, FPR.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub waviness_fpr: Option<u32>,
    /// How the actual cams at the answer are made (their method, normal deviates,
    /// tolerances and interval).
    pub profile: ProfileSettings,
    /// With `design speed`: the theoretical cam's jump onset (full model), rpm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub theoretical_onset_rpm: Option<f64>,
    /// The operating speed, rpm.
    pub operating_rpm: f64,
    /// P(jump) at the answer with its 95 % Wilson interval.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub p_jump: Option<Probability>,
    /// The criterion.
    pub criterion: String,
    /// Actual cams a step.
    pub samples: u64,
    /// Master seed.
    pub seed: u64,
    /// The model that produced the answer.
    pub model: String,
    /// Every value tried and whether it passed (its JSON key names the unit:
    /// [`Self::tried_key`]).
    pub tried: Vec<(f64, bool)>,
    /// Model runs (2 revolutions each).
    pub model_runs: u64,
    /// Wall time, s.
    pub wall_s: f64,
}

/// `design speed` and `design tolerance`: core's [`OnsetSearch`] for the first value
/// (rising speed, rising tolerance) at which the upper Wilson bound exceeds --p-max; the
/// answer is the largest value tried below it that passes. P(jump) is assumed to rise
/// with the speed and the tolerance (the report says so).
pub fn mc_search(args: &McArgs, speed: bool) -> Result<McSearchReport> {
    let command = if speed {
        "design speed"
    } else {
        "design tolerance"
    };
    args.actual.refuse_actual_flag(command)?;
    let fpr = args.actual.fpr()?;
    mc_search_at(args, speed, fpr)?.map_err(|n| anyhow!("{}", n.error_line()))
}

/// `design tolerance`: the loosest cam tolerance for each FPR of --waviness-fpr (the
/// default FPR when none is given), one search each; --waviness searches the FPR.
pub fn tolerance_table(args: &McArgs) -> Result<ToleranceTable> {
    let a = &args.actual;
    a.refuse_actual_flag("design tolerance")?;
    if a.interval_deg.is_some() || a.interval == crate::actual::IntervalRule::Criteria {
        return Err(crate::args::usage(
            "--interval-deg and --interval criteria fix the profile's interval: `design tolerance` sets it from the waviness (--waviness-fpr)",
        ));
    }
    if let Some(t) = a.cam_tolerance {
        return Err(crate::args::usage(format!(
            "--cam-tolerance {t}: `design tolerance` searches the cam tolerance (with --waviness it is --tolerance-factor times VI.1's; hold the roller and eccentricity tolerances with --roller-tolerance and --eccentricity-tolerance)"
        )));
    }
    if args.waviness {
        return Ok(ToleranceTable(vec![ToleranceRow::Answer(mc_search(
            args, false,
        )?)]));
    }
    let fprs = if a.waviness_fpr.is_empty() {
        vec![crate::actual::DEFAULT_FPR]
    } else {
        a.waviness_fpr.clone()
    };
    let rows = fprs
        .iter()
        .map(|&f| {
            let r =
                mc_search_at(args, false, Some(f)).map_err(|e| e.context(format!("FPR {f}")))?;
            Ok(r.map_or_else(ToleranceRow::NothingPasses, ToleranceRow::Answer))
        })
        .collect::<Result<Vec<_>>>()?;
    // The command fails only when no FPR has an answer.
    if let Some(n) = rows
        .iter()
        .map(ToleranceRow::nothing_passes)
        .collect::<Option<Vec<_>>>()
    {
        let why: Vec<String> = n.iter().map(|n| n.error_line()).collect();
        bail!("{}", why.join("; "));
    }
    Ok(ToleranceTable(rows))
}

/// (start, max, resolution) of the search over the value that makes it fail (growth 2).
fn search_range(speed: bool, waviness: bool, quick: bool) -> (f64, f64, f64) {
    if speed {
        (
            100.0,
            crate::study::jump_speed::MAX_RPM,
            if quick { 100.0 } else { 5.0 },
        )
    } else if waviness {
        // FPR: from 8 doubling to the finest waviness the profile can be given (720
        // points a revolution, about FPR 570), to one wave.
        (8.0, 512.0, if quick { 16.0 } else { 1.0 })
    } else {
        (0.1, 20.0, if quick { 0.5 } else { 0.05 })
    }
}

/// The search's answer (the last passing value) and the first failing one, if bracketed.
fn answer_of(
    onset: Onset<f64>,
    speed: bool,
    waviness: bool,
    p_max: f64,
) -> Result<(f64, Option<f64>)> {
    Ok(match onset {
        Onset::Bracketed { below, at } if waviness => (below.round(), Some(at.round())),
        Onset::Bracketed { below, at } => (below, Some(at)),
        Onset::Beyond(m) => (m, None),
        Onset::AtStart(x) => bail!(
            "P(jump) is above --p-max {p_max} already at the search's first value {x} ({}): nothing passes",
            if speed {
                "rpm"
            } else if waviness {
                "FPR: a tighter --tolerance-factor"
            } else {
                "times VI.1's tolerances"
            }
        ),
    })
}

/// `--tolerance-factor`: positive, and VI.1's largest tolerance times it within the
/// tolerance options' own limit ([`crate::args::MAX_TOLERANCE_IN`]): a larger factor
/// asks for a different cam, not a tolerance (issue 33: `1e300` reached the profile
/// builder and was reported as a waviness).
fn tolerance_factor(s: &str) -> Result<f64, String> {
    let r = camsim_core::Tolerances::<f64>::reference();
    let largest = r.cam.max(r.roller).max(r.eccentricity);
    let max = crate::args::MAX_TOLERANCE_IN / largest;
    match crate::args::positive_finite(s)? {
        x if x <= max => Ok(x),
        _ => Err(format!(
            "must be at most {max} (VI.1's largest tolerance, {largest} in, times {max} is the tolerances' limit of {} in: a larger error is a different cam)",
            crate::args::MAX_TOLERANCE_IN
        )),
    }
}

/// The pass criterion of a search, in words.
fn criterion(
    args: &McArgs,
    speed: bool,
    fpr: Option<u32>,
    n: u64,
    p_max: f64,
    op_rpm: f64,
) -> String {
    let (waviness, factor) = (args.waviness, args.tolerance_factor.unwrap_or(1.0));
    format!(
        "upper 95 % Wilson bound of P(jump) in revolution 2 over {n} actual cams (seed {}, waviness {}) at most {p_max}{}; P(jump) assumed to rise with the {}",
        args.actual.seed(),
        if waviness {
            format!("searched, tolerances {factor} x VI.1's")
        } else {
            fpr
                .map_or_else(|| "FPR 17 (default)".to_string(), |f| format!("FPR {f}"))
        },
        if speed { String::new() } else { format!(" at {op_rpm:.1} rpm") },
        if speed {
            "speed"
        } else if waviness {
            "FPR (the acceleration a wave imposes grows as FPR², docs/MODEL.md §9.6)"
        } else {
            "tolerance"
        }
    )
}

/// The actual cams of a search's step at `x` (its speed, cam-tolerance factor or FPR):
/// the options given, at the waviness `fpr`, the searched tolerance or FPR set.
fn step_cams(args: &McArgs, speed: bool, fpr: Option<u32>, x: f64) -> ActualArgs {
    let reference = camsim_core::Tolerances::<f64>::reference();
    let mut actual = args.actual.at_fpr(fpr);
    actual.actual = true;
    let roller = args.actual.roller_tolerance;
    if args.waviness {
        let factor = args.tolerance_factor.unwrap_or(1.0);
        actual.waviness_fpr = vec![x.round() as u32];
        actual.cam_tolerance = Some(reference.cam * factor);
        actual.roller_tolerance = Some(roller.unwrap_or(reference.roller * factor));
    } else if !speed {
        actual.cam_tolerance = Some(reference.cam * x);
    }
    actual
}

/// One Monte Carlo search at the waviness `fpr` (None: the default); a tolerance search
/// in which nothing passes, even the smallest tolerance, is its [`NothingPasses`].
fn mc_search_at(
    args: &McArgs,
    speed: bool,
    fpr: Option<u32>,
) -> Result<std::result::Result<McSearchReport, NothingPasses>> {
    let t0 = Instant::now();
    anyhow::ensure!(
        !(speed && args.waviness),
        "--waviness: only `design tolerance` searches the waviness"
    );
    let waviness = args.waviness;
    let factor = args.tolerance_factor.unwrap_or(1.0);
    let mut spec = spec_from(&args.scene)?;
    spec.solver.start = Start::Static;
    spec.revolutions = 2;
    let op_rpm = camsim_core::rad_per_s_to_rpm(spec.design.omega0);
    let mc = crate::study::montecarlo::monte_carlo_model(&spec);
    let (p_max, n) = p_max_and_samples(args.p_max, args.quick, args.samples)?;
    let nthreads = threads(args.threads);
    let mut runs = 0u64;
    let mut tried: Vec<(f64, bool)> = Vec::new();
    let mut probs: Vec<(f64, Probability)> = Vec::new();
    let (start, max, resolution) = search_range(speed, waviness, args.quick);
    let search = OnsetSearch::new(start, Some(2.0), max, resolution)?;
    let steps = search_steps(start, max, resolution);
    let at = |x: f64| step_cams(args, speed, fpr, x);
    check_search_time(&mc, &at(start), n, steps, nthreads)?;
    let onset = search.find(|x| -> Result<bool> {
        let mut s = mc.clone();
        // A waviness is a whole number of waves.
        let x = if waviness { x.round() } else { x };
        if speed {
            s.design.set_speed_rpm(x)?;
        }
        let actual = at(x);
        let p = p_jump_on_actual_cams(&s, &actual, n, nthreads, &mut runs)
            .map_err(|e| e.context(format!("at {x}")))?;
        let ok = p.hi95 <= p_max;
        tried.push((x, ok));
        probs.push((x, p));
        Ok(!ok)
    })?;
    let p_at = |v: f64| probs.iter().find(|(x, _)| *x == v).map(|(_, p)| *p);
    if let (Onset::AtStart(x), false, false) = (onset, speed, waviness) {
        let cams = at(x);
        let log = SearchLog {
            profile: ProfileSettings::of(&cams, intervals_for(&mc.design, &cams)?)?,
            criterion: criterion(args, speed, fpr, n, p_max, op_rpm),
            model: describe(&mc),
            tried,
            model_runs: runs,
            wall_s: t0.elapsed().as_secs_f64(),
        };
        return Ok(Err(NothingPasses::new(args, fpr, (x, p_at(x)), n, log)));
    }
    let (answer, failing) = answer_of(onset, speed, waviness, p_max)?;
    let p_jump = p_at(answer);
    let cams = at(answer);
    let profile = ProfileSettings::of(&cams, intervals_for(&mc.design, &cams)?)?;
    let theoretical_onset_rpm = if speed {
        let js = crate::study::jump_speed::find(&spec, 1.0, crate::study::jump_speed::MAX_RPM)?;
        runs += u64::from(js.simulations);
        js.jump_rpm
    } else {
        None
    };
    let (search, unit) = search_labels(speed, waviness);
    let report = McSearchReport {
        search: search.into(),
        answer,
        unit,
        tolerance_factor: waviness.then_some(factor),
        failing,
        bracket: failing.map_or(0.0, |f| f - answer),
        cam_tolerance_in: (!speed).then_some(profile.cam_tolerance_in),
        roller_tolerance_in: (!speed).then_some(profile.roller_tolerance_in),
        eccentricity_tolerance_in: (!speed).then_some(profile.eccentricity_tolerance_in),
        waviness_fpr: if waviness {
            None
        } else {
            Some(fpr.unwrap_or(crate::actual::DEFAULT_FPR))
        },
        theoretical_onset_rpm,
        operating_rpm: op_rpm,
        p_jump,
        criterion: criterion(args, speed, fpr, n, p_max, op_rpm),
        samples: n,
        seed: args.actual.seed(),
        profile,
        model: describe(&mc),
        tried,
        model_runs: runs,
        wall_s: t0.elapsed().as_secs_f64(),
    };
    crate::report::ensure_finite(&report)?;
    Ok(Ok(report))
}

/// A search's name and its answer's unit.
fn search_labels(speed: bool, waviness: bool) -> (&'static str, String) {
    if speed {
        ("speed", "rpm".into())
    } else if waviness {
        ("waviness", "FPR".into())
    } else {
        let unit = format!(
            "factor on VI.1's cam tolerance ({} {})",
            units::given(units::LENGTH, 0.0005),
            units::symbol(units::LENGTH)
        );
        ("tolerance", unit)
    }
}

/// What a search that found nothing passing ran, for its report.
struct SearchLog {
    profile: ProfileSettings,
    criterion: String,
    model: String,
    tried: Vec<(f64, bool)>,
    model_runs: u64,
    wall_s: f64,
}

/// A `design tolerance` FPR at which nothing passes: P(jump)'s upper bound is above
/// --p-max already at the search's smallest cam tolerance (a row of the table, not the
/// command's failure while another FPR has an answer).
#[derive(Clone, Debug, Serialize)]
pub struct NothingPasses {
    /// `tolerance`.
    pub search: String,
    /// The cams' waviness, FPR.
    pub waviness_fpr: u32,
    /// Why, in words: P(jump) at the smallest tolerance against --p-max.
    pub nothing_passes: String,
    /// The smallest factor on VI.1's cam tolerance tried (the search's first).
    pub smallest_factor_tried: f64,
    /// The cam profile tolerance there, ± in.
    pub smallest_cam_tolerance_in: f64,
    /// The roller tolerance (held), ± in.
    pub roller_tolerance_in: f64,
    /// The eccentricity tolerance (held), ± in.
    pub eccentricity_tolerance_in: f64,
    /// P(jump) at the smallest tolerance with its 95 % Wilson interval.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub p_jump: Option<Probability>,
    /// The criterion.
    pub criterion: String,
    /// Actual cams a step.
    pub samples: u64,
    /// Master seed.
    pub seed: u64,
    /// The model.
    pub model: String,
    /// Every factor tried and whether it passed.
    pub tolerance_factors_tried: Vec<(f64, bool)>,
    /// Model runs (2 revolutions each).
    pub model_runs: u64,
    /// Wall time, s.
    pub wall_s: f64,
}

impl NothingPasses {
    fn new(
        args: &McArgs,
        fpr: Option<u32>,
        (x, p): (f64, Option<Probability>),
        n: u64,
        log: SearchLog,
    ) -> Self {
        let lu = units::symbol(units::LENGTH);
        let cam = units::q(units::LENGTH, log.profile.cam_tolerance_in, 5);
        let why = match p {
            Some(p) => format!(
                "P(jump) there {} of {n}, upper 95 % bound {:.3} above --p-max {}",
                p.count, p.hi95, args.p_max
            ),
            None => format!("P(jump) there is above --p-max {}", args.p_max),
        };
        NothingPasses {
            search: "tolerance".into(),
            waviness_fpr: fpr.unwrap_or(crate::actual::DEFAULT_FPR),
            nothing_passes: format!(
                "nothing passes down to ±{cam} {lu} ({x} x VI.1's cam tolerance): {why}"
            ),
            smallest_factor_tried: x,
            smallest_cam_tolerance_in: log.profile.cam_tolerance_in,
            roller_tolerance_in: log.profile.roller_tolerance_in,
            eccentricity_tolerance_in: log.profile.eccentricity_tolerance_in,
            p_jump: p,
            criterion: log.criterion,
            samples: n,
            seed: args.actual.seed(),
            model: log.model,
            tolerance_factors_tried: log.tried,
            model_runs: log.model_runs,
            wall_s: log.wall_s,
        }
    }

    /// The row as the command's one-line error: `FPR 57: nothing passes down to ...`.
    pub fn error_line(&self) -> String {
        format!("FPR {}: {}", self.waviness_fpr, self.nothing_passes)
    }
}

/// A row of `design tolerance`'s table: the search's answer, or nothing passes.
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
pub enum ToleranceRow {
    /// The loosest passing cam tolerance.
    Answer(McSearchReport),
    /// Nothing passes at this FPR.
    NothingPasses(NothingPasses),
}

impl ToleranceRow {
    /// The answer, if the row has one.
    pub fn answer(&self) -> Option<&McSearchReport> {
        match self {
            ToleranceRow::Answer(r) => Some(r),
            ToleranceRow::NothingPasses(_) => None,
        }
    }

    fn model_runs(&self) -> u64 {
        self.answer().map_or_else(
            || self.nothing_passes().map_or(0, |n| n.model_runs),
            |r| r.model_runs,
        )
    }

    fn wall_s(&self) -> f64 {
        self.answer().map_or_else(
            || self.nothing_passes().map_or(0.0, |n| n.wall_s),
            |r| r.wall_s,
        )
    }

    /// Why nothing passes, if so.
    pub fn nothing_passes(&self) -> Option<&NothingPasses> {
        match self {
            ToleranceRow::Answer(_) => None,
            ToleranceRow::NothingPasses(n) => Some(n),
        }
    }

    fn json_value(&self) -> serde_json::Result<serde_json::Value> {
        match self {
            ToleranceRow::Answer(r) => r.json_value(),
            ToleranceRow::NothingPasses(n) => serde_json::to_value(n),
        }
    }
}

/// The first lines of a search's text: its answer in the user's words.
fn search_headline(r: &McSearchReport, out: &mut String) {
    use std::fmt::Write;
    if r.search == "speed" {
        let _ = writeln!(
            out,
            "camsim design speed: {:.1} rpm on actual cams",
            r.answer
        );
        if let Some(t) = r.theoretical_onset_rpm {
            let _ = writeln!(
                out,
                "  theoretical cam's jump onset: {t:.1} rpm (full model)"
            );
        }
    } else if r.search == "waviness" {
        let _ = writeln!(
            out,
            "camsim design tolerance --waviness: FPR {:.0} is the roughest waviness that passes at {} x VI.1's tolerances (cam ±{} {lu}, roller ±{} {lu})",
            r.answer,
            r.tolerance_factor.unwrap_or(1.0),
            units::q(units::LENGTH, r.cam_tolerance_in.unwrap_or(0.0), 5),
            units::q(units::LENGTH, r.roller_tolerance_in.unwrap_or(0.0), 6),
            lu = units::symbol(units::LENGTH)
        );
        let _ = writeln!(
            out,
            "  roughest = the highest FPR, the shortest waves (the acceleration a wave imposes grows as FPR², docs/MODEL.md §9.6)"
        );
    } else {
        let _ = writeln!(
            out,
            "camsim design tolerance: cam ±{} {lu} ({:.3} x VI.1's) at FPR {}; held: roller ±{} {lu}, eccentricity ±{} {lu}",
            units::q(units::LENGTH, r.cam_tolerance_in.unwrap_or(0.0), 5),
            r.answer,
            r.waviness_fpr.unwrap_or(crate::actual::DEFAULT_FPR),
            units::q(units::LENGTH, r.roller_tolerance_in.unwrap_or(0.0), 6),
            units::q(units::LENGTH, r.eccentricity_tolerance_in.unwrap_or(0.0), 5),
            lu = units::symbol(units::LENGTH)
        );
    }
}

impl McSearchReport {
    /// The JSON key of the values tried, naming their unit: `speeds_tried_rpm`,
    /// `tolerance_factors_tried` (factors on VI.1's tolerances) or `waviness_fprs_tried`.
    pub fn tried_key(&self) -> &'static str {
        match self.search.as_str() {
            "speed" => "speeds_tried_rpm",
            "waviness" => "waviness_fprs_tried",
            _ => "tolerance_factors_tried",
        }
    }

    /// The report as JSON, the values tried under [`Self::tried_key`].
    fn json_value(&self) -> serde_json::Result<serde_json::Value> {
        let mut v = serde_json::to_value(self)?;
        if let Some(o) = v.as_object_mut() {
            if let Some(t) = o.remove("tried") {
                o.insert(self.tried_key().into(), t);
            }
        }
        Ok(v)
    }
}

impl Report for McSearchReport {
    fn json(&self) -> serde_json::Result<String> {
        crate::report::sorted_pretty_json(&self.json_value()?)
    }
    fn text(&self) -> String {
        use std::fmt::Write;
        let mut out = String::new();
        search_headline(self, &mut out);
        let d = if self.search == "waviness" { 0 } else { 4 };
        match self.failing {
            Some(f) => {
                let _ = writeln!(
                    out,
                    "  bracket: passes at {:.d$}, fails at {f:.d$} (width {:.d$} {})",
                    self.answer, self.bracket, self.unit
                );
            }
            None => {
                let _ = writeln!(
                    out,
                    "  nothing failed up to the search's limit {:.4}",
                    self.answer
                );
            }
        }
        if let Some(p) = &self.p_jump {
            let _ = writeln!(
                out,
                "  P(jump) at the answer: {} of {}: {} (95 % Wilson)",
                p.count,
                self.samples,
                p.text(4)
            );
        }
        let _ = writeln!(out, "  criterion: {}", self.criterion);
        let _ = writeln!(out, "  model: {}", self.model);
        let tried: Vec<String> = self
            .tried
            .iter()
            .map(|(x, ok)| {
                let d = if self.search == "waviness" { 0 } else { 3 };
                format!("{x:.d$}{}", if *ok { "+" } else { "-" })
            })
            .collect();
        let _ = writeln!(out, "  values tried (+ passes): {}", tried.join(" "));
        let _ = writeln!(
            out,
            "  {} model runs of 2 revolutions, {:.1} s",
            self.model_runs, self.wall_s
        );
        out
    }
}

/// `design tolerance`'s answers, one a waviness (JSON: an array of the searches).
#[derive(Clone, Debug, Serialize)]
#[serde(transparent)]
pub struct ToleranceTable(pub Vec<ToleranceRow>);

impl Report for ToleranceTable {
    fn json(&self) -> serde_json::Result<String> {
        let rows = self
            .0
            .iter()
            .map(ToleranceRow::json_value)
            .collect::<serde_json::Result<Vec<_>>>()?;
        crate::report::sorted_pretty_json(&rows)
    }
    fn text(&self) -> String {
        use std::fmt::Write;
        let answers: Vec<&McSearchReport> =
            self.0.iter().filter_map(ToleranceRow::answer).collect();
        if self.0.len() == 1 || answers.iter().any(|r| r.search != "tolerance") {
            return answers.iter().map(|r| r.text()).collect();
        }
        let lu = units::symbol(units::LENGTH);
        let mut out = String::new();
        let _ = writeln!(
            out,
            "camsim design tolerance: the loosest cam tolerance at each waviness"
        );
        let _ = writeln!(
            out,
            "  {:>5}  {:>12}  {:>14}  {:>22}  {:>9}",
            "FPR",
            "x VI.1's cam",
            format!("cam ± {lu}"),
            "P(jump) there",
            "fails at"
        );
        for row in &self.0 {
            let r = match row {
                ToleranceRow::Answer(r) => r,
                ToleranceRow::NothingPasses(n) => {
                    let _ = writeln!(out, "  {:>5}  {}", n.waviness_fpr, n.nothing_passes);
                    continue;
                }
            };
            let p = r.p_jump.map_or_else(|| "-".to_string(), |p| p.text(3));
            let fails = r
                .failing
                .map_or_else(|| "none".to_string(), |f| format!("{f:.3}"));
            let _ = writeln!(
                out,
                "  {:>5}  {:>12.3}  {:>14}  {:>22}  {:>9}",
                r.waviness_fpr.unwrap_or(0),
                r.answer,
                units::q(units::LENGTH, r.cam_tolerance_in.unwrap_or(0.0), 5).to_string(),
                p,
                fails
            );
        }
        if let Some(r) = answers.first() {
            let _ = writeln!(
                out,
                "  held: roller ±{} {lu}, eccentricity ±{} {lu}",
                units::q(units::LENGTH, r.roller_tolerance_in.unwrap_or(0.0), 6),
                units::q(units::LENGTH, r.eccentricity_tolerance_in.unwrap_or(0.0), 5),
            );
            let fpr = format!("waviness FPR {}", r.waviness_fpr.unwrap_or(0));
            let criterion = r.criterion.replace(&fpr, "waviness the row's FPR");
            let _ = writeln!(out, "  criterion: {criterion}");
            let _ = writeln!(out, "  model: {}", r.model);
        }
        let runs: u64 = self.0.iter().map(ToleranceRow::model_runs).sum();
        let wall: f64 = self.0.iter().map(ToleranceRow::wall_s).sum();
        let _ = writeln!(out, "  {runs} model runs of 2 revolutions, {wall:.1} s");
        out
    }
}

/// Command-line options of `camsim design spring`.
#[derive(clap::Args, Debug)]
#[command(mut_arg("actual", |a| a.help("Judge on actual cams instead (made by the options below, as montecarlo's; the same cams at every rate): the upper 95 % bound of P(jump) at the operating speed must be at most --p-max")))]
pub struct SpringArgs {
    /// The scene and its overrides (the operating speed is its --rpm).
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Speed margin on the theoretical cam, percent: contact must hold at (1 + margin/100)
    /// times the operating speed (0-100).
    #[arg(long, default_value_t = 15.0, allow_hyphen_values = true, value_parser = margin_percent)]
    pub margin: f64,
    /// The actual cams of --actual.
    #[command(flatten)]
    pub actual: ActualArgs,
    /// Largest acceptable P(jump) (its upper 95 % Wilson bound), with --actual (0-1).
    #[arg(long, default_value_t = 0.01, allow_hyphen_values = true, value_parser = crate::args::unit_interval, requires = "actual")]
    pub p_max: f64,
    /// Actual cams per rate, with --actual (default: the fewest whose upper bound can be
    /// at most --p-max with no jump, 381 for 0.01).
    #[arg(long, value_parser = crate::args::whole_u64::<1, 1_000_000>, requires = "actual")]
    pub samples: Option<u64>,
    /// Worker threads (default: every core). The answer does not depend on it.
    #[arg(long, value_parser = crate::args::whole_u32::<1, 1024>)]
    pub threads: Option<u32>,
    /// Bracket width the search stops at, lb/in, or with its unit (0.2N/mm).
    #[arg(long, default_value_t = 1.0, value_name = "LB_PER_IN", allow_hyphen_values = true, value_parser = crate::args::rate_resolution)]
    pub resolution: f64,
    /// Largest rate searched, lb/in, or with its unit (N/mm).
    #[arg(long, default_value_t = MAX_RATE, value_name = "LB_PER_IN", allow_hyphen_values = true, value_parser = crate::args::spring_rate)]
    pub max_rate: f64,
    /// Search the spring's preload length δ_rs instead of its rate: the shortest
    /// compression at assembly (at the scene's or --spring-rate's rate) that passes.
    #[arg(long)]
    pub preload: bool,
    /// Largest preload length searched with --preload, in, or with its unit (mm).
    #[arg(long, default_value_t = MAX_PRELOAD_LENGTH, value_name = "IN", allow_hyphen_values = true, value_parser = crate::args::positive_length, requires = "preload")]
    pub max_preload_length: f64,
    /// CI's quick mode: resolution 10 lb/in (0.1 in with --preload); with --actual,
    /// --p-max at least 0.1 (35 cams).
    #[arg(long)]
    pub quick: bool,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// The preload search's first length, in: a tenth of the reference's 0.5 in.
pub const START_PRELOAD_LENGTH: f64 = 0.05;
/// The default largest preload length, in: 20 times the reference's 0.5 in, beyond any
/// compression the reference spring's coils could take.
pub const MAX_PRELOAD_LENGTH: f64 = 10.0;
/// The preload search's bracket width, in (0.1 in the quick mode).
pub const PRELOAD_RESOLUTION: f64 = 0.005;

/// The quick mode's least --p-max (35 actual cams a rate).
pub const QUICK_P_MAX: f64 = 0.1;

/// The search's first rate, lb/in.
pub const START_RATE: f64 = 10.0;
/// The default largest rate, lb/in: the reference wire's stiffest spring of two active
/// coils (G d⁴ / (8 D³ · 2) = 274 lb/in) is well below it.
pub const MAX_RATE: f64 = 1000.0;

fn margin_percent(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if (0.0..=100.0).contains(&x) => Ok(x),
        Ok(_) => Err("must be between 0 and 100 (percent)".into()),
        Err(_) => Err("not a number".into()),
    }
}

/// The fewest samples whose Wilson upper bound with no jump is at most `p`.
pub fn samples_for(p: f64) -> u64 {
    let mut n = 1u64;
    while n < 10_000_000 && Probability::of(0, n).hi95 > p {
        n = (n + 1).max(n + n / 8);
    }
    // Back down to the least such n.
    while n > 1 && Probability::of(0, n - 1).hi95 <= p {
        n -= 1;
    }
    n
}

/// What was checked at the chosen rate.
#[derive(Clone, Debug, Serialize)]
pub struct SpringReport {
    /// What the search varied: `spring rate` (at the preload length) or `preload length`
    /// (at the rate, with --preload).
    pub searched: Searched,
    /// The smallest rate found that passes, lb/in (with --preload: the rate held).
    pub spring_rate_lb_per_in: f64,
    /// The largest rate tried that fails, lb/in (absent: the first rate tried passed).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failing_rate_lb_per_in: Option<f64>,
    /// Bracket width, lb/in (the answer is within it of the true smallest rate; 0 with
    /// --preload, where the rate is held).
    pub bracket_lb_per_in: f64,
    /// With --preload: the longest preload length tried that fails, in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failing_preload_length_in: Option<f64>,
    /// With --preload: the bracket width, in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub preload_bracket_in: Option<f64>,
    /// The spring's preload at assembly, lb.
    pub preload_lb: f64,
    /// Preload length, in.
    pub preload_length_in: f64,
    /// Its mass by the wire-and-coil model, lb.
    pub spring_mass_lb: f64,
    /// Its active coils.
    pub active_coils: f64,
    /// Its surge frequency, Hz.
    pub surge_hz: f64,
    /// Operating speed, rpm.
    pub operating_rpm: f64,
    /// The criterion, in words.
    pub criterion: String,
    /// Theoretical cam: the speed contact was required at, rpm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub checked_at_rpm: Option<f64>,
    /// Theoretical cam: the jump onset of the chosen spring, rpm (a second search).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump_onset_rpm: Option<f64>,
    /// Its bracket, rpm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump_onset_bracket_rpm: Option<f64>,
    /// Actual cams: P(jump) at the chosen rate with its 95 % interval.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub p_jump: Option<Probability>,
    /// Actual cams: samples per rate.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub samples: Option<u64>,
    /// Actual cams: the master seed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// Actual cams: how they are made (method, normal deviates, tolerances, interval).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub profile: Option<ProfileSettings>,
    /// Which model produced the answer.
    pub model: String,
    /// Rates tried (lb/in; with --preload lengths, in) in order, each with whether it
    /// passed. Its JSON key names the unit (`rates_tried_lb_per_in`,
    /// `preload_lengths_tried_in`, or their SI names).
    #[serde(skip)]
    pub tried: Vec<(f64, bool)>,
    /// The spring to build: wire, coil and coils that pass every check of the verdict.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub part: Option<PartReport>,
    /// Model runs of the search (each of 2 revolutions), and of the onset check.
    pub model_runs: u64,
    /// Wall time, s.
    pub wall_s: f64,
}

/// The spring `design spring` answers with ([`crate::study::coil_spring`]).
#[derive(Clone, Debug, Serialize)]
pub struct PartReport {
    /// The spring.
    pub spring: CoilChoice,
    /// The wire (`chrome-silicon wire, ASTM A401`).
    pub wire: String,
    /// The wire's scene name.
    pub material: &'static str,
    /// End type.
    pub ends: &'static str,
    /// The rule that binds: the one closest to its limit (`limit_rule`), or contact when
    /// the rate had to be raised for it.
    pub binding: String,
    /// The rule of stress, surge and coil count closest to its limit.
    pub limit_rule: String,
    /// `limit_rule`'s use of its limit, percent.
    pub binding_percent: f64,
    /// Candidates each rule turned away.
    pub rejected: Rejections,
    /// Whether contact was checked with this spring's own rate and mass (a simulation);
    /// with --actual it is judged at the rate found, with the wire model's mass.
    pub contact_checked: bool,
    /// The preload length the part is built and judged at, in: the scene's, or with
    /// --preload the length found (raised with the part when its own mass asked for more).
    pub preload_length_in: f64,
}

/// The candidates' contact checks a search runs at most before it gives up.
const MAX_PART_CHECKS: usize = 12;

/// The spring to build for `spec` at its rate and preload length: the lightest standard
/// candidate that passes stress and surge and, with `at_rpm`, holds contact at that speed
/// with its own rate and mass. Returns it and the spec with its rate and mass.
fn choose_part(
    spec: &RunSpec,
    at_rpm: Option<f64>,
    runs: &mut u64,
) -> Result<(PartReport, RunSpec)> {
    let part = spec.spring.as_ref();
    let wire = part
        .and_then(|p| p.wire)
        .unwrap_or(camsim_core::ASSUMED_SPRING_WIRE);
    let q = CoilQuery {
        rate: spec.design.k_rs,
        full_compression: spec.design.delta_rs + spec.design.program.max_lift(),
        cam_hz: camsim_core::rad_per_s_to_rpm(spec.design.omega0) / 60.0,
        wire,
        ends: part.map_or(camsim_core::CoilEnds::SquaredGround, |p| p.coil.ends),
        fixed: part.map(|p| (p.coil.wire_diameter, p.coil.mean_diameter)),
    };
    let (found, rejected) = candidates(&q);
    let lu = units::symbol(units::LENGTH);
    if found.is_empty() {
        bail!(
            "no {} spring of {} {} passes: of the wire and coil sizes tried, {} need fewer than {} active coils, {} exceed the allowable stress at full compression ({} {lu}), {} surge below {} x the cam's {:.2} Hz: a longer preload length with a softer spring, a gentler program or a lower speed",
            wire.title,
            units::q(units::STIFFNESS, q.rate, 1),
            units::symbol(units::STIFFNESS),
            rejected.too_stiff,
            crate::study::coil_spring::MIN_ACTIVE_COILS,
            rejected.stress,
            units::q(units::LENGTH, q.full_compression, 3),
            rejected.surge,
            camsim_core::SURGE_HARMONIC_MARGIN,
            q.cam_hz
        );
    }
    let (c, s) = lightest_in_contact(spec, &found, at_rpm, runs)?;
    let (rule, use_) = c.binding(&q);
    let mut s = s;
    s.spring = Some(camsim_scene_file::spring::SpringPart {
        coil: c.coil(&q),
        wire: Some(wire),
        free_length: Some(c.free_length_in),
    });
    Ok((
        PartReport {
            spring: c,
            wire: wire.title.to_string(),
            material: wire.name,
            ends: q.ends.name(),
            binding: rule.to_string(),
            limit_rule: rule.to_string(),
            binding_percent: 100.0 * use_,
            rejected,
            contact_checked: at_rpm.is_some(),
            preload_length_in: s.design.delta_rs,
        },
        s,
    ))
}

/// The lightest of the first springs `found` that holds contact at `at_rpm` (counting the
/// runs; any passes without a speed), with the spec carrying its rate and mass.
fn lightest_in_contact(
    spec: &RunSpec,
    found: &[CoilChoice],
    at_rpm: Option<f64>,
    runs: &mut u64,
) -> Result<(CoilChoice, RunSpec)> {
    let with = |c: &CoilChoice| {
        let mut s = spec.clone();
        s.design.k_rs = c.rate_lb_per_in;
        s.design.m_spring = c.mass_lb / camsim_core::GRAVITY_IN_PER_S2;
        s
    };
    let mut chosen = None;
    for c in found.iter().take(MAX_PART_CHECKS) {
        let s = with(c);
        let ok = match at_rpm {
            Some(rpm) => {
                *runs += 1;
                !sim::jumps_at(&s, rpm)?
            }
            None => true,
        };
        if ok {
            chosen = Some((*c, s));
            break;
        }
    }
    let Some(chosen) = chosen else {
        return Err(NoPartHoldsContact(MAX_PART_CHECKS.min(found.len())).into());
    };
    Ok(chosen)
}

/// None of the lightest springs that pass stress and surge holds contact with its own
/// mass (their count): [`choose_part_holding_contact`] then asks for a stiffer rate.
#[derive(Debug)]
struct NoPartHoldsContact(usize);

impl std::fmt::Display for NoPartHoldsContact {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "none of the {} lightest springs that pass stress and surge holds contact with its own mass, up to {} % above the rate found: a larger --margin on the rate, or a lighter program",
            self.0,
            ((1.0 + RATE_RAISE).powi(MAX_RATE_RAISES) * 100.0 - 100.0).round()
        )
    }
}

impl std::error::Error for NoPartHoldsContact {}

/// How much [`choose_part_holding_contact`] raises the rate each time no buildable spring
/// of it holds contact with its own mass (a real spring is heavier than the massless
/// search assumed, so its rate must be a little higher), and how many times at most.
const RATE_RAISE: f64 = 0.05;
const MAX_RATE_RAISES: i32 = 10;

/// [`choose_part`] on `spec_at(rate)` (the searched value, `what`: the rate, or the
/// preload length at the rate held), raised by [`RATE_RAISE`] while no buildable spring of
/// it holds contact at `at_rpm` with its own mass; the part's binding rule says so when
/// it was raised.
fn choose_part_holding_contact(
    spec_at: &dyn Fn(f64) -> Result<RunSpec>,
    rate: f64,
    what: &str,
    at_rpm: f64,
    runs: &mut u64,
) -> Result<(PartReport, RunSpec)> {
    let (mut asked, mut raises) = (rate, 0);
    loop {
        match choose_part(&spec_at(asked)?, Some(at_rpm), runs) {
            Ok((mut part, chosen)) => {
                if raises > 0 {
                    part.binding = format!(
                        "contact with the spring's own mass (the {what} raised {:.0} % above the one found, in {} step(s) of {:.0} %)",
                        (asked / rate - 1.0) * 100.0,
                        raises,
                        RATE_RAISE * 100.0
                    );
                }
                return Ok((part, chosen));
            }
            Err(e) if e.is::<NoPartHoldsContact>() && raises < MAX_RATE_RAISES => {
                asked *= 1.0 + RATE_RAISE;
                raises += 1;
            }
            Err(e) => return Err(e),
        }
    }
}

fn describe(spec: &RunSpec) -> String {
    format!(
        "{} follower, {} DOFs, rtol {:e}, atol {:e} {}, largest step {} rev, static start, 2 revolutions",
        spec.dofs.follower.name(),
        spec.dofs.set().name(),
        spec.solver.rtol,
        units::given(units::LENGTH, spec.solver.atol),
        units::symbol(units::LENGTH),
        spec.solver.max_step_fraction
    )
}

/// (start, max, resolution) of `design spring`'s search: over the rate, or over the
/// preload length with --preload.
fn spring_search_range(args: &SpringArgs) -> Result<(f64, f64, f64)> {
    Ok(if args.preload {
        let res = if args.quick { 0.1 } else { PRELOAD_RESOLUTION };
        if args.max_preload_length <= START_PRELOAD_LENGTH {
            bail!(
                "--max-preload-length {}: must be above the search's first length {START_PRELOAD_LENGTH} in",
                args.max_preload_length
            );
        }
        (START_PRELOAD_LENGTH, args.max_preload_length, res)
    } else {
        let res = if args.quick {
            args.resolution.max(10.0)
        } else {
            args.resolution
        };
        if args.max_rate <= START_RATE {
            bail!(
                "--max-rate {}: must be above the search's first rate {START_RATE} lb/in",
                args.max_rate
            );
        }
        (START_RATE, args.max_rate, res)
    })
}

/// The spring search.
pub fn spring(args: &SpringArgs) -> Result<SpringReport> {
    let t0 = Instant::now();
    let mut spec = spec_from(&args.scene)?;
    spec.solver.start = Start::Static;
    spec.revolutions = 2;
    let range = spring_search_range(args)?;
    args.actual.ensure_actual_if_options()?;
    let report = if args.actual.actual {
        spring_on_actual_cams(args, &spec, range, t0)?
    } else {
        spring_on_theoretical_cam(args, &spec, range, t0)?
    };
    crate::report::ensure_finite(&report)?;
    Ok(report)
}

/// What `design spring` varies: the rate (at the preload length), or with --preload the
/// preload length (at the rate held).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Searched {
    /// The spring rate, lb/in.
    #[serde(rename = "spring rate")]
    Rate,
    /// The preload length δ_rs, in.
    #[serde(rename = "preload length")]
    PreloadLength,
}

impl Searched {
    fn of(preload: bool) -> Self {
        if preload {
            Searched::PreloadLength
        } else {
            Searched::Rate
        }
    }

    /// Its name and unit: `spring rate` lb/in or `preload length` in.
    fn words(self) -> (&'static str, &'static str) {
        match self {
            Searched::PreloadLength => ("preload length", "in"),
            Searched::Rate => ("spring rate", "lb/in"),
        }
    }
}

impl PartialEq<&str> for Searched {
    fn eq(&self, other: &&str) -> bool {
        self.words().0 == *other
    }
}

/// A spring search's answer: the passing value of what it searched (lb/in or in) and the
/// failing value below it (absent: the first value tried passed).
#[derive(Clone, Copy, Debug)]
struct Answer {
    searched: Searched,
    value: f64,
    failing: Option<f64>,
}

impl Answer {
    /// The bracket width, in the answer's unit (0 when the first value tried passed).
    fn bracket(self) -> f64 {
        self.failing.map_or(0.0, |b| self.value - b)
    }
}

/// What a spring search found, before the answer's spring is worked out.
struct Found {
    answer: Answer,
    criterion: String,
    model: String,
    tried: Vec<(f64, bool)>,
    part: PartReport,
    model_runs: u64,
}

/// `base` with the searched value `x`: its rate (its mass following it by the wire model),
/// or its preload length at the rate held; validated.
fn with_value(base: &RunSpec, x: f64, preload: bool) -> Result<RunSpec> {
    let mut s = base.clone();
    if preload {
        s.design.delta_rs = x;
    } else {
        s.design.set_spring_rate(x)?;
    }
    s.design
        .validate()
        .map_err(|e| camsim_scene_file::refusal("design", e))?;
    Ok(s)
}

/// The report of a search's answer on `spec` (the rate or the preload length in their own
/// fields, the other held at the scene's), with the answer's spring ([`spring_of_answer`]);
/// what only one criterion gives is absent.
fn answered(found: Found, spec: &RunSpec, t0: Instant) -> Result<SpringReport> {
    let Found {
        answer,
        criterion,
        model,
        tried,
        part,
        model_runs,
    } = found;
    let spring = spring_of_answer(spec, answer, &part)?;
    let (rate, failing_rate, bracket, failing_length, length_bracket) = match answer.searched {
        Searched::Rate => (answer.value, answer.failing, answer.bracket(), None, None),
        Searched::PreloadLength => (
            spec.design.k_rs,
            None,
            0.0,
            answer.failing,
            Some(answer.bracket()),
        ),
    };
    Ok(SpringReport {
        searched: answer.searched,
        spring_rate_lb_per_in: rate,
        failing_rate_lb_per_in: failing_rate,
        bracket_lb_per_in: bracket,
        failing_preload_length_in: failing_length,
        preload_bracket_in: length_bracket,
        preload_lb: spring.preload_lb,
        preload_length_in: spring.preload_length_in,
        spring_mass_lb: spring.mass_lb,
        active_coils: spring.active_coils,
        surge_hz: spring.surge_hz,
        operating_rpm: camsim_core::rad_per_s_to_rpm(spec.design.omega0),
        criterion,
        checked_at_rpm: None,
        jump_onset_rpm: None,
        jump_onset_bracket_rpm: None,
        p_jump: None,
        samples: None,
        seed: None,
        profile: None,
        model,
        tried,
        part: Some(part),
        model_runs,
        wall_s: t0.elapsed().as_secs_f64(),
    })
}

/// `design spring --actual`: the search on P(jump) over the same actual cams at every
/// value, then the part at the answer (judged at the rate found).
fn spring_on_actual_cams(
    args: &SpringArgs,
    spec: &RunSpec,
    (start, max, resolution): (f64, f64, f64),
    t0: Instant,
) -> Result<SpringReport> {
    let (what, unit) = Searched::of(args.preload).words();
    let mc = crate::study::montecarlo::monte_carlo_model(spec);
    let (p_max, n) = p_max_and_samples(args.p_max, args.quick, args.samples)?;
    let actual = args.actual.resolve(&mc.design)?;
    let nthreads = threads(args.threads);
    let steps = search_steps(start, max, resolution);
    check_search_time(
        &with_value(&mc, start, args.preload)?,
        &actual,
        n,
        steps,
        nthreads,
    )?;
    let (mut tried, mut runs, mut last_p) = (Vec::new(), 0, None);
    let onset = OnsetSearch::new(start, Some(2.0), max, resolution)?.find(|k| -> Result<bool> {
        let s = with_value(&mc, k, args.preload)?;
        let p = p_jump_on_actual_cams(&s, &actual, n, nthreads, &mut runs)
            .map_err(|e| e.context(format!("{what} {k} {unit}")))?;
        let ok = p.hi95 <= p_max;
        if ok {
            last_p = Some((k, p));
        }
        tried.push((k, ok));
        Ok(ok)
    })?;
    let ans = answer(onset, max, args.preload, "P(jump) above --p-max")?;
    let (part, _) = choose_part(&with_value(spec, ans.value, args.preload)?, None, &mut runs)?;
    let criterion = format!(
        "upper 95 % Wilson bound of P(jump) in revolution 2 at {:.1} rpm over {n} actual cams (seed {}) at most {p_max}",
        camsim_core::rad_per_s_to_rpm(spec.design.omega0),
        actual.seed()
    );
    Ok(SpringReport {
        p_jump: last_p.filter(|(k, _)| *k == ans.value).map(|(_, p)| p),
        samples: Some(n),
        seed: Some(actual.seed()),
        profile: Some(ProfileSettings::of(
            &actual,
            intervals_for(&mc.design, &actual)?,
        )?),
        ..answered(
            Found {
                answer: ans,
                criterion,
                model: describe(&mc),
                tried,
                part,
                model_runs: runs,
            },
            spec,
            t0,
        )?
    })
}

/// `design spring` on the theoretical cam: the search on steady-state contact at the
/// margin's speed, the part that holds it with its own rate and mass, and that part's own
/// jump onset (the margin it really has).
fn spring_on_theoretical_cam(
    args: &SpringArgs,
    spec: &RunSpec,
    (start, max, resolution): (f64, f64, f64),
    t0: Instant,
) -> Result<SpringReport> {
    let op_rpm = camsim_core::rad_per_s_to_rpm(spec.design.omega0);
    let at_rpm = op_rpm * (1.0 + args.margin / 100.0);
    camsim_core::key::SPEED_RPM
        .check(camsim_core::key::RPM, at_rpm)
        .map_err(|e| anyhow::anyhow!("--margin {}: {e}", args.margin))?;
    let (mut tried, mut runs) = (Vec::new(), 0);
    let onset = OnsetSearch::new(start, Some(2.0), max, resolution)?.find(|k| -> Result<bool> {
        let s = with_value(spec, k, args.preload)?;
        runs += 1;
        let ok = !sim::jumps_at(&s, at_rpm)?;
        tried.push((k, ok));
        Ok(ok)
    })?;
    let ans = answer(onset, max, args.preload, "separates")?;
    let at = |x: f64| with_value(spec, x, args.preload); // contact with its own mass
    let what = ans.searched.words().0;
    let (part, chosen) = choose_part_holding_contact(&at, ans.value, what, at_rpm, &mut runs)?;
    let js = crate::study::jump_speed::find(&chosen, 1.0, crate::study::jump_speed::MAX_RPM)?;
    runs += u64::from(js.simulations);
    let criterion = format!(
        "steady-state contact (revolution 2, static start) at {at_rpm:.1} rpm = {op_rpm:.1} rpm + {} %, theoretical cam",
        args.margin
    );
    Ok(SpringReport {
        checked_at_rpm: Some(at_rpm),
        jump_onset_rpm: js.jump_rpm,
        jump_onset_bracket_rpm: js.jump_rpm.map(|j| j - js.no_jump_rpm),
        ..answered(
            Found {
                answer: ans,
                criterion,
                model: describe(spec),
                tried,
                part,
                model_runs: runs,
            },
            spec,
            t0,
        )?
    })
}

/// The spring of a search's answer: its preload, and the part's own preload length, mass,
/// coils and surge.
struct AnswerSpring {
    preload_lb: f64,
    preload_length_in: f64,
    mass_lb: f64,
    active_coils: f64,
    surge_hz: f64,
}

/// The answer's spring: `spec` at the answer (validated), built as `part` (its own rate and
/// preload length), and its preload.
fn spring_of_answer(spec: &RunSpec, answer: Answer, part: &PartReport) -> Result<AnswerSpring> {
    let mut chosen = with_value(
        spec,
        answer.value,
        answer.searched == Searched::PreloadLength,
    )?;
    chosen.design.k_rs = part.spring.rate_lb_per_in;
    chosen.design.delta_rs = part.preload_length_in;
    Ok(AnswerSpring {
        preload_lb: chosen.design.preload()?,
        preload_length_in: part.preload_length_in,
        mass_lb: part.spring.mass_lb,
        active_coils: part.spring.active_coils,
        surge_hz: part.spring.surge_hz,
    })
}

/// The passing value (rate or preload length) and the failing one below it from the
/// search's outcome.
fn answer(onset: Onset<f64>, max: f64, preload: bool, fails: &str) -> Result<Answer> {
    let searched = Searched::of(preload);
    match onset {
        Onset::AtStart(k) => Ok(Answer {
            searched,
            value: k,
            failing: None,
        }),
        Onset::Bracketed { below, at } => Ok(Answer {
            searched,
            value: at,
            failing: Some(below),
        }),
        Onset::Beyond(_) if preload => bail!(
            "no preload length up to --max-preload-length {max} in passes (the follower {fails} at every length tried): a stiffer spring, a gentler program or a lower speed"
        ),
        Onset::Beyond(_) => bail!(
            "no spring up to --max-rate {max} lb/in passes (the follower {fails} at every rate tried): a larger preload length, a gentler program or a lower speed"
        ),
    }
}

impl Report for SpringReport {
    fn json(&self) -> serde_json::Result<String> {
        // The tried values under a key that names their unit (`--units` converts it).
        let mut v = serde_json::to_value(self)?;
        let key = if self.searched == Searched::PreloadLength {
            "preload_lengths_tried_in"
        } else {
            "rates_tried_lb_per_in"
        };
        if let Some(o) = v.as_object_mut() {
            o.insert(key.into(), serde_json::to_value(&self.tried)?);
        }
        crate::report::sorted_pretty_json(&v)
    }
    fn text(&self) -> String {
        use std::fmt::Write;
        let mut out = String::new();
        spring_headline(self, &mut out);
        let _ = writeln!(out, "  criterion: {}", self.criterion);
        if let (Some(j), Some(b)) = (self.jump_onset_rpm, self.jump_onset_bracket_rpm) {
            let _ = writeln!(
                out,
                "  check: its jump onset is {j:.1} rpm (bracket {b:.1} rpm), {:+.1} % over {:.1} rpm",
                100.0 * (j / self.operating_rpm - 1.0),
                self.operating_rpm
            );
        }
        if let (Some(p), Some(n)) = (&self.p_jump, self.samples) {
            let _ = writeln!(
                out,
                "  P(jump) at the chosen rate: {} of {n}: {} (95 % Wilson)",
                p.count,
                p.text(4)
            );
        }
        if let Some(p) = &self.part {
            part_lines(&mut out, p);
            if self.searched == Searched::PreloadLength {
                let _ = writeln!(
                    out,
                    "    and in [design]: spring_preload_length_{} = {}",
                    units::key_suffix(units::LENGTH),
                    units::q(units::LENGTH, p.preload_length_in, 4)
                );
            }
        }
        let _ = writeln!(out, "  model: {}", self.model);
        let tried: Vec<String> = self
            .tried
            .iter()
            .map(|(k, ok)| {
                if self.searched == Searched::PreloadLength {
                    format!(
                        "{}{}",
                        units::q(units::LENGTH, *k, 3),
                        if *ok { "+" } else { "-" }
                    )
                } else {
                    format!(
                        "{}{}",
                        units::q(units::STIFFNESS, *k, 1),
                        if *ok { "+" } else { "-" }
                    )
                }
            })
            .collect();
        if self.searched == Searched::PreloadLength {
            let _ = writeln!(
                out,
                "  preload lengths tried ({}, + passes): {}",
                units::symbol(units::LENGTH),
                tried.join(" ")
            );
        } else {
            let _ = writeln!(
                out,
                "  rates tried ({}, + passes): {}",
                units::symbol(units::STIFFNESS),
                tried.join(" ")
            );
        }
        let _ = writeln!(
            out,
            "  {} model runs of 2 revolutions, {:.1} s",
            self.model_runs, self.wall_s
        );
        out
    }
}

/// The first lines of the spring search's text: the answer and its bracket. The rate it
/// gives is the built spring's own (its wire, coil and coils: the `[design.spring]` lines
/// below), beside the least rate the search found.
fn spring_headline(r: &SpringReport, out: &mut String) {
    use std::fmt::Write;
    let ku = units::symbol(units::STIFFNESS);
    let rate = r
        .part
        .as_ref()
        .map_or(r.spring_rate_lb_per_in, |p| p.spring.rate_lb_per_in);
    if r.searched == Searched::PreloadLength {
        let _ = writeln!(
            out,
            "camsim design spring --preload: preload length {} {lu} at the rate held, {} {ku} {}",
            units::q(units::LENGTH, r.preload_length_in, 3),
            units::q(units::STIFFNESS, rate, 1),
            spring_summary(r),
            lu = units::symbol(units::LENGTH),
        );
        preload_bracket_line(r, out);
        return;
    }
    let found = match &r.part {
        Some(_) => format!(
            "; the least rate the search found: {} {ku}",
            units::q(units::STIFFNESS, r.spring_rate_lb_per_in, 1)
        ),
        None => String::new(),
    };
    let _ = writeln!(
        out,
        "camsim design spring: {} {ku} at preload length {} {} {}{found}",
        units::q(units::STIFFNESS, rate, 1),
        units::given(units::LENGTH, r.preload_length_in),
        units::symbol(units::LENGTH),
        spring_summary(r),
    );
    let _ = match r.failing_rate_lb_per_in {
        Some(b) => writeln!(
            out,
            "  bracket: fails at {} {ku}, passes at {} {ku} (width {} {ku})",
            units::q(units::STIFFNESS, b, 1),
            units::q(units::STIFFNESS, r.spring_rate_lb_per_in, 1),
            units::q(units::STIFFNESS, r.bracket_lb_per_in, 2),
        ),
        None => writeln!(
            out,
            "  the first rate tried passes: any rate up to it may do"
        ),
    };
}

/// The answer's spring in brackets: its preload, coils, mass and surge.
fn spring_summary(r: &SpringReport) -> String {
    format!(
        "(preload {} {}; {:.2} active coils, {} {}, surge {:.0} Hz)",
        units::q(units::FORCE, r.preload_lb, 2),
        units::symbol(units::FORCE),
        r.active_coils,
        units::q(units::WEIGHT, r.spring_mass_lb, 4),
        units::symbol(units::WEIGHT),
        r.surge_hz,
    )
}

/// The preload search's bracket line.
fn preload_bracket_line(r: &SpringReport, out: &mut String) {
    use std::fmt::Write;
    let lu = units::symbol(units::LENGTH);
    let _ = match (r.failing_preload_length_in, r.preload_bracket_in) {
        (Some(b), Some(w)) => writeln!(
            out,
            "  searched: the preload length; bracket: fails at {} {lu}, passes at {} {lu} (width {} {lu})",
            units::q(units::LENGTH, b, 3),
            units::q(units::LENGTH, b + w, 3),
            units::q(units::LENGTH, w, 3),
        ),
        _ => writeln!(
            out,
            "  searched: the preload length; the first length tried passes: any length up to it may do"
        ),
    };
}

/// The binding rule as the part's text gives it: `binding` at `percent` of its limit; or,
/// when contact bound (`binding` is not `limit_rule`: the rate was raised until a buildable
/// spring held contact with its own mass, and `binding` says by how much), the part's
/// own stress and surge use of their limits, percent.
fn binding_text(p: &PartReport) -> String {
    if p.binding == p.limit_rule {
        return format!("{} ({:.0} % of its limit)", p.binding, p.binding_percent);
    }
    let c = &p.spring;
    format!(
        "{}; the part's stress at {:.0} % and surge at {:.0} % of their limits",
        p.binding,
        100.0 * c.shear_stress_psi / c.allowable_shear_psi,
        100.0 * camsim_core::SURGE_HARMONIC_MARGIN / c.surge_harmonic
    )
}

/// The spring to build: the part, its checks, the rule that binds, and the
/// `[design.spring]` lines that describe it in the output's family.
fn part_lines(out: &mut String, p: &PartReport) {
    use std::fmt::Write;
    let c = &p.spring;
    let (lu, su) = (units::symbol(units::LENGTH), units::symbol(units::STRESS));
    let _ = writeln!(
        out,
        "  spring to build: {}, wire {} {lu}, mean coil {} {lu} (index {:.1}), {:.2} active / {:.2} total coils, {} ends; rate {} {}, {} {}",
        p.wire,
        units::q(units::LENGTH, c.wire_diameter_in, 3),
        units::q(units::LENGTH, c.mean_diameter_in, 3),
        c.index,
        c.active_coils,
        c.total_coils,
        p.ends,
        units::q(units::STIFFNESS, c.rate_lb_per_in, 1),
        units::symbol(units::STIFFNESS),
        units::q(units::WEIGHT, c.mass_lb, 4),
        units::symbol(units::WEIGHT)
    );
    let _ = writeln!(
        out,
        "    checks: stress {} {su} at full compression, {:.0} % of the allowable {} {su}; surge {:.0} Hz = {:.1} x the cam (least {:.0}); free length {} {lu}, {} {lu} at full compression above the solid {} {lu}; contact {}",
        units::q(units::STRESS, c.shear_stress_psi, 0),
        100.0 * c.shear_stress_psi / c.allowable_shear_psi,
        units::q(units::STRESS, c.allowable_shear_psi, 0),
        c.surge_hz,
        c.surge_harmonic,
        camsim_core::SURGE_HARMONIC_MARGIN,
        units::q(units::LENGTH, c.free_length_in, 3),
        units::q(units::LENGTH, c.full_compression_length_in, 3),
        units::q(units::LENGTH, c.solid_height_in, 3),
        if p.contact_checked {
            "checked with its own rate and mass"
        } else {
            "judged at the rate found, with the wire model's mass"
        }
    );
    let _ = writeln!(
        out,
        "    binding: {}; turned away: {} too stiff for {} coils, {} over the stress, {} low surge",
        binding_text(p),
        p.rejected.too_stiff,
        crate::study::coil_spring::MIN_ACTIVE_COILS,
        p.rejected.stress,
        p.rejected.surge
    );
    let k = units::key_suffix(units::LENGTH);
    let _ = writeln!(
        out,
        "    as a scene (these lines in place of the spring rate):\n      [design.spring]\n      wire_diameter_{k} = {}\n      mean_diameter_{k} = {}\n      active_coils = {}\n      ends = \"{}\"\n      material = \"{}\"\n      free_length_{k} = {}",
        scene_length(c.wire_diameter_in),
        scene_length(c.mean_diameter_in),
        c.active_coils,
        p.ends,
        p.material,
        units::q(units::LENGTH, c.free_length_in, 4)
    );
}

/// A wire or coil diameter for the scene lines, to 6 significant digits in the output's
/// family: the standard wires are millimetre sizes, so an inch scene needs more than 4
/// decimals for the part it reads back to be the part printed (5.6 mm is 0.220472 in;
/// 0.2205 in would read back as a 0.221 in wire).
fn scene_length(inch: f64) -> f64 {
    let v = units::value(units::LENGTH, inch);
    format!("{v:.5e}").parse().unwrap_or(v)
}

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    match args.what {
        What::Spring(a) => {
            let r = spring(&a)?;
            crate::report::print(&r, a.json)
        }
        What::Speed(a) => {
            let r = mc_search(&a, true)?;
            crate::report::print(&r, a.json)
        }
        What::Tolerance(a) => {
            let r = tolerance_table(&a)?;
            crate::report::print(&r, a.json)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The binding text (issue 30): a part bound by contact after a raised rate gives its
    /// own stress and surge use (here 500/1000 psi and a surge harmonic of twice the
    /// least), not the stale use of the rule before the raise; an unraised part gives its
    /// rule's.
    #[test]
    fn a_raised_rates_binding_text_gives_the_parts_own_figures() {
        let c = crate::study::coil_spring::CoilChoice {
            wire_diameter_in: 0.1,
            mean_diameter_in: 1.0,
            index: 10.0,
            active_coils: 8.0,
            total_coils: 10.0,
            rate_lb_per_in: 20.0,
            mass_lb: 0.1,
            surge_hz: 100.0,
            surge_harmonic: 2.0 * camsim_core::SURGE_HARMONIC_MARGIN,
            shear_stress_psi: 500.0,
            allowable_shear_psi: 1000.0,
            solid_height_in: 1.0,
            free_length_in: 3.0,
            full_compression_length_in: 2.0,
        };
        let mut p = PartReport {
            spring: c,
            wire: "music wire".into(),
            material: "music-wire",
            ends: "squared-ground",
            binding: "contact with the spring's own mass (the rate raised 10 % above the one found, in 2 step(s) of 5 %)".into(),
            limit_rule: "contact (the rate asked)".into(),
            binding_percent: 99.0,
            rejected: Rejections::default(),
            contact_checked: true,
            preload_length_in: 0.5,
        };
        let t = binding_text(&p);
        assert!(
            t.ends_with("; the part's stress at 50 % and surge at 50 % of their limits"),
            "{t}"
        );
        assert!(!t.contains("99"), "{t}");
        p.binding = "stress".into();
        p.limit_rule = "stress".into();
        p.binding_percent = 87.0;
        assert_eq!(binding_text(&p), "stress (87 % of its limit)");
    }

    #[test]
    fn samples_for_is_the_least_n_whose_empty_upper_bound_is_p() {
        // 0 of n: Wilson's upper end is z²/(n + z²), so n >= z² (1 - p)/p.
        let z2 = crate::stats::Z95 * crate::stats::Z95;
        for p in [0.01, 0.05, 0.1] {
            let n = samples_for(p);
            assert!(Probability::of(0, n).hi95 <= p);
            assert!(Probability::of(0, n - 1).hi95 > p);
            assert_eq!(n, (z2 * (1.0 - p) / p).ceil() as u64, "{p}");
        }
        assert_eq!(samples_for(0.01), 381);
    }
}
