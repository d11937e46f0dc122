//! The comparison's runs: every law on the theoretical and on the actual cam, in
//! parallel (`run_every_law`), each measured over its revolutions 1 and 2
//! (`cam_study`), then grouped by law into the workable laws' studies and the laws not
//! workable (`law_studies`).

use std::sync::Arc;

use anyhow::{anyhow, Context, Result};
use camsim_core::{MotionLaw, SegmentKind};
use rayon::prelude::*;

use super::{segment_kinds, CamStudy, LawPeriod, LawStudy, NotWorkable, Ranks};
use crate::actual::{self, Cams, ProfileStats};
use crate::sim::{self, PeriodRow, RunSpec};
use crate::units::{Force, Stress, Torque};

/// One run's study, and the actual cam's profile.
type Run = (CamStudy, Option<ProfileStats>);
/// One run, or why it failed.
pub(super) type Job = Result<Run>;

/// One period's cycle I and cycle II rows as the report gives them.
fn law_period(name: &str, one: &PeriodRow, two: &PeriodRow) -> LawPeriod {
    LawPeriod {
        period: name.to_string(),
        acc_rms_cycle1: one.rms_acceleration,
        acc_rms_cycle2: two.rms_acceleration,
        torque_avg: two.torque_avg,
        torque_max: two.torque_max,
        torque_min: two.torque_min,
        contact_force_min: two.contact_force_min,
        contact_force_max: two.contact_force_max,
        contact_stress_max: two.contact_stress_max,
        jump: two.jump,
    }
}

/// The measures of one run's revolutions 1 and 2.
fn cam_study(spec: &RunSpec, rows: &[PeriodRow], steps: u32) -> Result<CamStudy> {
    let names = sim::period_names(&spec.design);
    let kinds = segment_kinds(spec);
    let row = |rev: u32, k: usize| {
        rows.iter()
            .filter(|r| r.revolution == rev)
            .nth(k)
            .filter(|r| r.period == names[k])
            .ok_or_else(|| anyhow!("revolution {rev} has no {} period", names[k]))
    };
    let mut per_period = Vec::new();
    let (mut sens, mut shock) = (0.0, 0.0);
    let (mut t_rise, mut t_return) = (f64::NEG_INFINITY, f64::INFINITY);
    let (mut t_max, mut f_min, mut f_max, mut s_max) =
        (0.0f64, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY);
    let mut jump = false;
    for (k, name) in names.iter().enumerate() {
        let (one, two) = (row(1, k)?, row(2, k)?);
        sens += two.rms_acceleration.in_inch();
        match kinds[k] {
            SegmentKind::Rise(_) => {
                shock += (one.rms_acceleration.in_inch() - two.rms_acceleration.in_inch())
                    / one.rms_acceleration.in_inch();
                t_rise = t_rise.max(two.torque_avg.in_inch());
            }
            SegmentKind::Return(_) => {
                shock += (one.rms_acceleration.in_inch() - two.rms_acceleration.in_inch())
                    / one.rms_acceleration.in_inch();
                t_return = t_return.min(two.torque_avg.in_inch());
            }
            SegmentKind::Dwell => {}
        }
        t_max = t_max
            .max(two.torque_max.in_inch().abs())
            .max(two.torque_min.in_inch().abs());
        f_min = f_min.min(two.contact_force_min.in_inch());
        f_max = f_max.max(two.contact_force_max.in_inch());
        s_max = s_max.max(two.contact_stress_max.in_inch());
        jump |= two.jump;
        per_period.push(law_period(name, one, two));
    }
    for (what, v) in [
        ("sensitivity", sens),
        ("shock index", shock),
        ("rise torque", t_rise),
        ("return torque", t_return),
        ("largest torque", t_max),
        ("smallest contact force", f_min),
        ("largest contact force", f_max),
        ("largest contact stress", s_max),
    ] {
        anyhow::ensure!(v.is_finite(), "the {what} is {v}");
    }
    Ok(CamStudy {
        per_period,
        sensitivity: sens,
        shock_index: shock,
        torque_avg_rise: Torque::inch(t_rise),
        torque_avg_return: Torque::inch(t_return),
        torque_max: Torque::inch(t_max),
        contact_force_min: Force::inch(f_min),
        contact_force_max: Force::inch(f_max),
        contact_stress_max: Stress::inch(s_max),
        jump,
        steps,
    })
}

/// Simulates `spec` (two revolutions) and measures it.
fn simulate(spec: &RunSpec) -> Result<CamStudy> {
    let r = sim::run(spec, &mut sim::Nothing)?;
    cam_study(
        spec,
        &sim::period_rows(&spec.design, &r.stats),
        r.solver.accepted,
    )
}

/// One law's run on the theoretical cam, or (`is_actual`) on the actual cam (sample 0
/// of `actual_args`) with that cam's profile.
fn run_one(spec: &RunSpec, actual_args: &Cams, is_actual: bool) -> Job {
    if !is_actual {
        return Ok((simulate(spec)?, None));
    }
    let (dev, stats) = actual::build_profile(&spec.design, actual_args, 0)?;
    let mut s = spec.clone();
    s.profile = Some(Arc::new(dev));
    Ok((simulate(&s)?, Some(stats)))
}

/// Every law's run on the theoretical and on the actual cam (sample 0 of `actual_args`),
/// in parallel on `threads`, in order: law 0 theoretical, law 0 actual, law 1 ...
pub(super) fn run_every_law(
    specs: &[(MotionLaw, RunSpec)],
    actual_args: &Cams,
    threads: usize,
) -> Result<Vec<Job>> {
    // Every (law, cam) pair, in order: law 0 theoretical, law 0 actual, law 1 ...
    let jobs: Vec<(usize, bool)> = (0..specs.len())
        .flat_map(|i| [(i, false), (i, true)])
        .collect();
    let pool = crate::study::pool(threads)?;
    let bar = crate::study_limits::progress_bar(
        jobs.len() as u64,
        true,
        "{elapsed_precise} [{bar:40}] {pos}/{len} runs (every law, theoretical and actual), eta {eta}",
    );
    let results: Vec<Job> = pool.install(|| {
        jobs.par_iter()
            .map(|&(i, is_actual)| {
                let (law, spec) = &specs[i];
                let r = run_one(spec, actual_args, is_actual).with_context(|| {
                    format!(
                        "{} on the {} cam",
                        law.name(),
                        if is_actual { "actual" } else { "theoretical" }
                    )
                });
                bar.inc(1);
                r
            })
            .collect()
    });
    bar.finish_and_clear();
    Ok(results)
}

/// The studies of the workable laws, and the laws whose run on either cam left the
/// model's valid range, from the runs in [`run_every_law`]'s order.
pub(super) fn law_studies(
    base: &RunSpec,
    specs: &[(MotionLaw, RunSpec)],
    results: Vec<Job>,
) -> Result<(Vec<LawStudy>, Vec<NotWorkable>)> {
    let mut it = results.into_iter();
    let mut laws = Vec::new();
    let mut not_workable = Vec::new();
    for (law, _) in specs {
        let flex = it.next().ok_or_else(|| anyhow!("missing run"))?;
        let cam = it.next().ok_or_else(|| anyhow!("missing run"))?;
        let ((flex, _), (cam, profile)) = match workable(law.name(), flex, cam)? {
            Ok(pair) => pair,
            Err(n) => {
                not_workable.push(n);
                continue;
            }
        };
        let profile = profile.ok_or_else(|| anyhow!("missing profile"))?;
        laws.push(law_study(base, *law, flex, cam, profile)?);
    }
    Ok((laws, not_workable))
}

/// One workable law's study: its runs on the theoretical and the actual cam, the
/// periods it jumps in, and the values it is ranked by.
fn law_study(
    base: &RunSpec,
    law: MotionLaw,
    flex: CamStudy,
    cam: CamStudy,
    profile: ProfileStats,
) -> Result<LawStudy> {
    let names = sim::period_names(&base.design);
    let kinds = segment_kinds(base);
    let jump_in = |rise: bool| {
        cam.per_period.iter().zip(&kinds).any(|(p, k)| {
            p.jump
                && matches!(
                    (k, rise),
                    (SegmentKind::Rise(_), true) | (SegmentKind::Return(_), false)
                )
        })
    };
    debug_assert_eq!(names.len(), cam.per_period.len());
    let sensitivity_to_tolerance = cam.sensitivity - flex.sensitivity;
    anyhow::ensure!(
        sensitivity_to_tolerance.is_finite(),
        "{}: the sensitivity to tolerance is not finite",
        law.name()
    );
    let values = Ranks {
        sensitivity_to_flexibility: flex.sensitivity,
        sensitivity_to_tolerance,
        shock_index: flex.shock_index,
        torque_avg: flex.torque_avg_rise.in_inch(),
        torque_max: flex.torque_max.in_inch(),
        contact_force_min: flex.contact_force_min.in_inch(),
        contact_force_max: flex.contact_force_max.in_inch(),
        contact_stress_max: flex.contact_stress_max.in_inch(),
        overall: 0.0,
    };
    Ok(LawStudy {
        name: law.name().to_string(),
        jump_rise: jump_in(true),
        jump_return: jump_in(false),
        flexibility: flex,
        actual: super::ActualStudy {
            cam,
            sensitivity_to_tolerance,
            profile,
        },
        values,
        ranks: Ranks::default(),
    })
}

/// One law's two runs (theoretical, actual): both, or the law not workable when a run
/// left the model's valid range (the theoretical cam's reason first). Any other failure
/// is an error.
fn workable(
    law: &str,
    flex: Job,
    cam: Job,
) -> Result<std::result::Result<(Run, Run), NotWorkable>> {
    let not = |which: &str, e: anyhow::Error| {
        if !crate::study::sweep::out_of_model(&e) {
            return Err(e);
        }
        Ok(Err(NotWorkable {
            name: law.to_string(),
            cam: which.to_string(),
            reason: format!("{}", e.root_cause()),
        }))
    };
    match (flex, cam) {
        (Ok(f), Ok(c)) => Ok(Ok((f, c))),
        (Err(e), _) => not("theoretical", e),
        (_, Err(e)) => not("actual", e),
    }
}
