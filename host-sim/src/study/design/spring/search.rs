//! The search over the searched value (the rate, or with --preload the preload length):
//! core's [`OnsetSearch`] doubling from its first value, then bisecting, on the
//! theoretical cam's contact at the margin's speed or on P(jump) over actual cams.

use std::time::Instant;

use anyhow::{bail, Result};
use camsim_core::{Onset, OnsetSearch};

use super::part::{choose_part, choose_part_holding_contact};
use super::report::{answered, Found};
use super::{Searched, SpringReport, SpringSpec};
use crate::actual::intervals_for;
use crate::sim::{self, RunSpec};
use crate::study::design::{
    check_search_time, describe, p_jump_on_actual_cams, p_max_and_samples, search_steps,
};
use crate::study::montecarlo::{threads, ProfileSettings};

/// A spring search's answer: the passing value of what it searched (lb/in or in) and the
/// failing value below it (absent: the first value tried passed).
#[derive(Clone, Copy, Debug)]
pub(super) struct Answer {
    pub(super) searched: Searched,
    pub(super) value: f64,
    pub(super) failing: Option<f64>,
}

impl Answer {
    /// The bracket width, in the answer's unit (0 when the first value tried passed).
    pub(super) fn bracket(self) -> f64 {
        self.failing.map_or(0.0, |b| self.value - b)
    }
}
/// `base` with the searched value `x`: its rate (its mass following it by the wire model),
/// or its preload length at the rate held; validated.
pub(super) fn with_value(base: &RunSpec, x: f64, preload: bool) -> Result<RunSpec> {
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
/// `design spring --actual`: the search on P(jump) over the same actual cams at every
/// value, then the part at the answer (judged at the rate found).
pub(super) fn spring_on_actual_cams(
    args: &SpringSpec,
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
    let (part, _) = choose_part(
        &with_value(spec, ans.value, args.preload)?,
        None,
        &mut runs,
        args.units,
    )?;
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
                model: describe(&mc, args.units),
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
pub(super) fn spring_on_theoretical_cam(
    args: &SpringSpec,
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
    let (part, chosen) =
        choose_part_holding_contact(&at, ans.value, what, at_rpm, &mut runs, args.units)?;
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
                model: describe(spec, args.units),
                tried,
                part,
                model_runs: runs,
            },
            spec,
            t0,
        )?
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
