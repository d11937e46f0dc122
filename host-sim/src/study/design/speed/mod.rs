//! `design speed` (and each search of `design tolerance`): core's [`OnsetSearch`] over a
//! speed, a cam-tolerance factor or a waviness for the first value whose upper Wilson
//! bound of P(jump) on actual cams exceeds the limit. The report's text and JSON are in
//! text.rs.

mod text;

use std::time::Instant;

use anyhow::{anyhow, bail, Result};
use camsim_core::{Onset, OnsetSearch, Start};
use serde::Serialize;

use super::tolerance::{NothingPasses, SearchLog};
use super::{
    check_search_time, describe, p_jump_on_actual_cams, p_max_and_samples, search_steps, McSpec,
};
use crate::actual::{intervals_for, Cams};
use crate::sim::RunSpec;
use crate::stats::Probability;
use crate::study::montecarlo::{threads, ProfileSettings};
use crate::units::{self, Length, Units};

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
    pub cam_tolerance_in: Option<Length>,
    /// With `design tolerance`: the roller tolerance (held), ± in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub roller_tolerance_in: Option<Length>,
    /// With `design tolerance`: the eccentricity tolerance (held), ± in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub eccentricity_tolerance_in: Option<Length>,
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
pub fn mc_search(args: &McSpec, speed: bool) -> Result<McSearchReport> {
    let command = if speed {
        "design speed"
    } else {
        "design tolerance"
    };
    args.actual.refuse_actual_flag(command)?;
    let fpr = args.actual.fpr()?;
    mc_search_at(args, speed, fpr)?.map_err(|n| anyhow!("{}", n.error_line()))
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

/// The pass criterion of a search, in words.
fn criterion(
    args: &McSpec,
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
fn step_cams(args: &McSpec, speed: bool, fpr: Option<u32>, x: f64) -> Cams {
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
pub(crate) fn mc_search_at(
    args: &McSpec,
    speed: bool,
    fpr: Option<u32>,
) -> Result<std::result::Result<McSearchReport, NothingPasses>> {
    let t0 = Instant::now();
    anyhow::ensure!(
        !(speed && args.waviness),
        "--waviness: only `design tolerance` searches the waviness"
    );
    let mut spec = args.run.clone();
    spec.solver.start = Start::Static;
    spec.revolutions = 2;
    let (p_max, n) = p_max_and_samples(args.p_max, args.quick, args.samples)?;
    let setup = Setup {
        op_rpm: camsim_core::rad_per_s_to_rpm(spec.design.omega0),
        mc: crate::study::montecarlo::monte_carlo_model(&spec),
        p_max,
        n,
        nthreads: threads(args.threads),
    };
    let (onset, mut steps) = walk(args, speed, fpr, &setup)?;
    if let (Onset::AtStart(x), false, false) = (onset, speed, args.waviness) {
        return nothing_passes(args, fpr, x, &setup, steps, t0).map(Err);
    }
    let (answer, failing) = answer_of(onset, speed, args.waviness, p_max)?;
    let cams = step_cams(args, speed, fpr, answer);
    let profile = ProfileSettings::of(&cams, intervals_for(&setup.mc.design, &cams)?)?;
    let theoretical_onset_rpm = if speed {
        theoretical_onset(&spec, &mut steps.runs)?
    } else {
        None
    };
    let found = Found {
        answer,
        failing,
        profile,
        theoretical_onset_rpm,
    };
    let report = report_of(args, (speed, fpr), &setup, found, steps, t0);
    crate::report::ensure_finite(&report)?;
    Ok(Ok(report))
}

/// What every step of a Monte Carlo search shares: the operating speed (rpm), the Monte
/// Carlo model, the P(jump) limit, the actual cams a step and the worker threads.
struct Setup {
    op_rpm: f64,
    mc: RunSpec,
    p_max: f64,
    n: u64,
    nthreads: usize,
}

/// What a search's steps ran: each value tried with whether it passed, its P(jump), and
/// the model runs.
#[derive(Default)]
struct Steps {
    tried: Vec<(f64, bool)>,
    probs: Vec<(f64, Probability)>,
    runs: u64,
}

impl Steps {
    /// P(jump) at the value `v` tried.
    fn p_at(&self, v: f64) -> Option<Probability> {
        self.probs.iter().find(|(x, _)| *x == v).map(|(_, p)| *p)
    }
}

/// The search itself: core's [`OnsetSearch`] from the search's range (refused first if it
/// would take too long), each step P(jump) over the actual cams at its value.
fn walk(
    args: &McSpec,
    speed: bool,
    fpr: Option<u32>,
    setup: &Setup,
) -> Result<(Onset<f64>, Steps)> {
    let (start, max, resolution) = search_range(speed, args.waviness, args.quick);
    let search = OnsetSearch::new(start, Some(2.0), max, resolution)?;
    let most = search_steps(start, max, resolution);
    let at = |x: f64| step_cams(args, speed, fpr, x);
    check_search_time(&setup.mc, &at(start), setup.n, most, setup.nthreads)?;
    let mut steps = Steps::default();
    let onset = search.find(|x| -> Result<bool> {
        let mut s = setup.mc.clone();
        // A waviness is a whole number of waves.
        let x = if args.waviness { x.round() } else { x };
        if speed {
            s.design.set_speed_rpm(x)?;
        }
        let p = p_jump_on_actual_cams(&s, &at(x), setup.n, setup.nthreads, &mut steps.runs)
            .map_err(|e| e.context(format!("at {x}")))?;
        let ok = p.hi95 <= setup.p_max;
        steps.tried.push((x, ok));
        steps.probs.push((x, p));
        Ok(!ok)
    })?;
    Ok((onset, steps))
}

/// A tolerance search that fails already at its first factor `x`: the row that says so.
fn nothing_passes(
    args: &McSpec,
    fpr: Option<u32>,
    x: f64,
    setup: &Setup,
    steps: Steps,
    t0: Instant,
) -> Result<NothingPasses> {
    let cams = step_cams(args, false, fpr, x);
    let p = steps.p_at(x);
    let log = SearchLog {
        profile: ProfileSettings::of(&cams, intervals_for(&setup.mc.design, &cams)?)?,
        criterion: criterion(args, false, fpr, setup.n, setup.p_max, setup.op_rpm),
        model: describe(&setup.mc, args.units),
        tried: steps.tried,
        model_runs: steps.runs,
        wall_s: t0.elapsed().as_secs_f64(),
    };
    Ok(NothingPasses::new(args, fpr, (x, p), setup.n, log))
}

/// A search's answer with what was worked out at it: the failing value above it, how its
/// actual cams are made, and with `design speed` the theoretical cam's onset.
struct Found {
    answer: f64,
    failing: Option<f64>,
    profile: ProfileSettings,
    theoretical_onset_rpm: Option<f64>,
}

/// The report of a search (`design speed` when `speed`, at the waviness `fpr`) that found
/// `found`.
fn report_of(
    args: &McSpec,
    (speed, fpr): (bool, Option<u32>),
    setup: &Setup,
    found: Found,
    steps: Steps,
    t0: Instant,
) -> McSearchReport {
    let Found {
        answer,
        failing,
        profile,
        theoretical_onset_rpm,
    } = found;
    let (search, unit) = search_labels(speed, args.waviness, args.units);
    let held = |t: f64| (!speed).then_some(Length::inch(t));
    McSearchReport {
        search: search.into(),
        answer,
        unit,
        tolerance_factor: args
            .waviness
            .then_some(args.tolerance_factor.unwrap_or(1.0)),
        failing,
        bracket: failing.map_or(0.0, |f| f - answer),
        cam_tolerance_in: held(profile.cam_tolerance_in),
        roller_tolerance_in: held(profile.roller_tolerance_in),
        eccentricity_tolerance_in: held(profile.eccentricity_tolerance_in),
        waviness_fpr: (!args.waviness).then(|| fpr.unwrap_or(crate::actual::DEFAULT_FPR)),
        theoretical_onset_rpm,
        operating_rpm: setup.op_rpm,
        p_jump: steps.p_at(answer),
        criterion: criterion(args, speed, fpr, setup.n, setup.p_max, setup.op_rpm),
        samples: setup.n,
        seed: args.actual.seed(),
        profile,
        model: describe(&setup.mc, args.units),
        tried: steps.tried,
        model_runs: steps.runs,
        wall_s: t0.elapsed().as_secs_f64(),
    }
}

/// The theoretical cam's jump onset (`design speed`'s check), its runs added to `runs`.
fn theoretical_onset(spec: &crate::sim::RunSpec, runs: &mut u64) -> Result<Option<f64>> {
    let js = crate::study::jump_speed::find(spec, 1.0, crate::study::jump_speed::MAX_RPM)?;
    *runs += u64::from(js.simulations);
    Ok(js.jump_rpm)
}

/// A search's name and its answer's unit.
fn search_labels(speed: bool, waviness: bool, units: Units) -> (&'static str, String) {
    if speed {
        ("speed", "rpm".into())
    } else if waviness {
        ("waviness", "FPR".into())
    } else {
        let unit = format!(
            "factor on VI.1's cam tolerance ({} {})",
            units.given(units::LENGTH, 0.0005),
            units.symbol(units::LENGTH)
        );
        ("tolerance", unit)
    }
}
