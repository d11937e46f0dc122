//! What `camsim montecarlo` prints: the study's report (text and JSON), a shard's, and
//! the run time.

use std::path::PathBuf;

use serde::Serialize;

use super::{Columns, Probability, Shard, StudySettings, Summary, TwoLevelSummary};
use crate::report::Report;
use crate::stats::two_level::Estimate;
use crate::units::{Length, Units, LENGTH};

/// Run time of a study on this machine (not part of the result).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Timing {
    /// Worker threads.
    pub threads: usize,
    /// Wall-clock time, s.
    pub wall_s: f64,
    /// Samples per second.
    pub samples_per_s: f64,
    /// Samples per second per thread.
    pub samples_per_s_per_thread: f64,
}

/// What `camsim montecarlo` (and `merge`) prints.
#[derive(Clone, Debug, Serialize)]
pub struct MonteCarloReport {
    /// The study.
    pub study: StudySettings<Length>,
    /// The result (of the reduced model, on every cam, in a two-level study).
    pub summary: Summary,
    /// A two-level study's estimate of the full model.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub two_level: Option<TwoLevelSummary>,
    /// Run time (absent for a merge).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub timing: Option<Timing>,
}

/// What `camsim montecarlo --shard K/N` prints.
#[derive(Clone, Debug, Serialize)]
pub struct ShardReport {
    /// The shard.
    pub shard: Shard,
    /// Samples it ran.
    pub samples: u64,
    /// The shard file.
    pub out: PathBuf,
    /// Run time.
    pub timing: Timing,
}

impl Report for ShardReport {
    fn text(&self, _units: Units) -> String {
        format!(
            "camsim montecarlo: shard {} ({} samples) written to {} in {:.1} s on {} threads\n",
            self.shard,
            self.samples,
            self.out.display(),
            self.timing.wall_s,
            self.timing.threads
        )
    }
}

/// Short column labels of the text table: the name and the unit, in `units`.
pub fn label(col: &str, units: Units) -> String {
    use crate::units::{ACCELERATION, FORCE, SPEED, STRESS, TORQUE};
    let (name, unit) = match col {
        "rms_displacement" => ("rms_y", Some((LENGTH, "in"))),
        "rms_velocity" => ("rms_v", Some((SPEED, "in/s"))),
        "rms_acceleration" => ("rms_a", Some((ACCELERATION, "in/s2"))),
        "torque_avg" => ("T_avg", Some((TORQUE, "lb in"))),
        "torque_max" => ("T_max", Some((TORQUE, "lb in"))),
        "torque_min" => ("T_min", Some((TORQUE, "lb in"))),
        "contact_force_min" => ("Fc_min", Some((FORCE, "lb"))),
        "contact_force_max" => ("Fc_max", Some((FORCE, "lb"))),
        "contact_force_avg" => ("Fc_avg", Some((FORCE, "lb"))),
        "contact_stress_max" => ("stress", Some((STRESS, "psi"))),
        "aord_motor" => ("aord_m", None),
        "aord_coupling" => ("aord_cp", None),
        "aord_cam" => ("aord_c", None),
        "acc_rms_sum" => ("sum rms_a", Some((ACCELERATION, "in/s2"))),
        "fpr" => ("FPR", None),
        "rms_deviation_in" => ("rms lift dev", Some((LENGTH, "in"))),
        other => (other, None),
    };
    match unit {
        Some((unit, inch)) => format!("{name}, {}", units.label(unit, inch)),
        None => name.to_string(),
    }
}

/// A column's unit (`None`: dimensionless or a count).
fn column_unit(col: &str) -> Option<camsim_scene_file::units::Unit> {
    crate::stats::columns::column_dimension(col).map(|d| d.unit())
}

/// A table of columns' moments and percentiles, in `units`.
fn moments_table(out: &mut String, columns: &Columns, units: Units) {
    use std::fmt::Write;
    let _ = writeln!(
        out,
        "  {:<17} {:>11} {:>11} {:>11} {:>11} {:>11}",
        "", "mean", "sd", "p5", "p50", "p95"
    );
    for (name, m) in &columns.0 {
        let v = |x: f64| column_unit(name).map_or(x, |unit| units.value(unit, x));
        let _ = writeln!(
            out,
            "  {:<17} {:>11.4e} {:>11.4e} {:>11.4e} {:>11.4e} {:>11.4e}",
            label(name, units),
            v(m.mean),
            v(m.sd),
            v(m.p5),
            v(m.p50),
            v(m.p95)
        );
    }
}

fn probability_text(p: &Probability, n: u64) -> String {
    format!(
        "{} of {n}, p = {:.4}, 95 % interval [{:.4}, {:.4}] (Wilson)",
        p.count, p.p, p.lo95, p.hi95
    )
}

/// `value [lo, hi] = reduced + correction` of a probability.
fn estimate_text(e: &Estimate) -> String {
    format!(
        "p = {:.4}, 95 % interval [{:.4}, {:.4}] = reduced {:.4} {} correction {:.4}",
        e.value,
        e.lo95,
        e.hi95,
        e.reduced,
        if e.correction < 0.0 { "-" } else { "+" },
        e.correction.abs()
    )
}

/// The header of a two-level estimate: the subsample is the study's cams 0 to
/// `subsample` − 1 (the same cams whatever the shards ran), of which `pairs` have both
/// verdicts (the rest were not workable on a model).
pub fn two_level_header(estimator: &str, subsample: u64, pairs: u64) -> String {
    let cams = match subsample {
        1 => "cam 0".to_string(),
        n => format!("cams 0-{}", n.saturating_sub(1)),
    };
    let paired = if pairs == subsample {
        String::new()
    } else {
        format!(" ({pairs} of them workable on both models: the pairs)")
    };
    format!(
        "\nfull model, two-level estimate ({estimator}): every cam on the reduced model, {cams} on the full model too{paired}"
    )
}

/// The full model's estimate of a two-level study, in words; `subsample` the cams
/// asked to run on the full model too; in `units`.
fn two_level_text(out: &mut String, t: &TwoLevelSummary, subsample: u64, units: Units) {
    use std::fmt::Write;
    let _ = writeln!(
        out,
        "{}",
        two_level_header(t.estimator, subsample, t.full_samples)
    );
    let d = &t.disagreements;
    let _ = writeln!(
        out,
        "  of the {} pairs, {} jump on the full model only and {} on the reduced only; the full model alone: {}",
        t.full_samples,
        d.full_only,
        d.reduced_only,
        probability_text(&t.subsample_full_jump, t.full_samples)
    );
    two_level_left_range_text(out, t);
    for p in &t.periods {
        let _ = writeln!(out, "  {}: jump {}", p.period, estimate_text(&p.jump));
    }
    if !t.whole_revolution.is_empty() {
        let _ = writeln!(
            out,
            "  {:<17} {:>11} {:>11} {:>11} {:>11} {:>11}",
            "mean", "estimate", "lo95", "hi95", "reduced", "correction"
        );
    }
    for c in &t.whole_revolution {
        let v = |x: f64| column_unit(&c.column).map_or(x, |unit| units.value(unit, x));
        let m = &c.mean;
        let _ = writeln!(
            out,
            "  {:<17} {:>11.4e} {:>11.4e} {:>11.4e} {:>11.4e} {:>11.4e}",
            label(&c.column, units),
            v(m.value),
            v(m.lo95),
            v(m.hi95),
            v(m.reduced),
            v(m.correction)
        );
    }
    let _ = writeln!(
        out,
        "  full-model jump anywhere: {}",
        estimate_text(&t.jump)
    );
}

/// A two-level study's full-model estimate, or why it has none.
fn full_model_text(out: &mut String, r: &MonteCarloReport, units: Units) {
    use std::fmt::Write;
    match (&r.two_level, &r.study.two_level) {
        (Some(t), Some(s)) => {
            two_level_text(out, t, s.full_samples.min(r.study.samples), units);
        }
        (Some(t), None) => two_level_text(out, t, t.full_samples, units),
        (None, Some(_)) => {
            let _ = writeln!(
                out,
                "\nfull model, two-level estimate: none, fewer than 2 of the subsample's cams are workable on the full model (the tables are the reduced model's)"
            );
        }
        (None, None) => {}
    }
}

/// The subsample cams that left a model's valid range (docs/MODEL.md §3.20).
fn two_level_left_range_text(out: &mut String, t: &TwoLevelSummary) {
    use std::fmt::Write;
    if t.jump_only_pairs > 0 {
        let _ = writeln!(
            out,
            "  of which {} left a model's valid range after the follower separated: counted as jumps there, in P(jump) only (the periods and means are over the other pairs)",
            t.jump_only_pairs
        );
    }
    if let Some(why) = &t.full_not_workable_reason {
        let _ = writeln!(
            out,
            "  not workable on the full model: {} cams left its valid range with the follower on the cam and have no pair (first: {why})",
            t.full_not_workable
        );
    }
}

/// The whole revolution's and the profiles' statistics, or why there are none.
fn revolution_text(out: &mut String, sm: &Summary, units: Units) {
    use std::fmt::Write;
    if sm.samples == 0 {
        let _ = writeln!(
            out,
            "\nno statistics: every workable cam jumped and then left the model's valid range (docs/MODEL.md §3.20)"
        );
        return;
    }
    let _ = writeln!(out, "\nwhole revolution {}:", sm.revolution);
    moments_table(out, &sm.whole_revolution, units);
    let _ = writeln!(out, "profiles:");
    moments_table(out, &sm.profile, units);
}

impl Report for MonteCarloReport {
    fn text(&self, units: Units) -> String {
        use std::fmt::Write;
        let s = &self.study;
        let sm = &self.summary;
        let mut out = String::new();
        let _ = writeln!(
            out,
            "camsim montecarlo: {} actual cams, seed {}, {} revolutions; statistics of revolution {}",
            s.samples, s.seed, s.revolutions, sm.revolution
        );
        let p = &s.profile;
        let _ = writeln!(
            out,
            "profile: {} ({} normal deviates), tolerances cam {} / roller {} / eccentricity {} {}, {} intervals ({:.4} deg, {})",
            p.method,
            p.normal,
            units.given(LENGTH, p.cam_tolerance_in.in_inch()),
            units.given(LENGTH, p.roller_tolerance_in.in_inch()),
            units.given(LENGTH, p.eccentricity_tolerance_in.in_inch()),
            units.symbol(LENGTH),
            p.intervals,
            360.0 / p.intervals as f64,
            p.interval_source
        );
        if let Some(t) = &s.two_level {
            let _ = writeln!(
                out,
                "two-level: the tables are the reduced model's (quasi-static cantilever, vertical, rtol 1e-4) on every cam; the full model's estimate follows them ({} cams on both)",
                t.full_samples.min(s.samples)
            );
        }
        if let Some(why) = &s.one_model {
            let _ = writeln!(out, "one model: {why}");
        }
        let _ = writeln!(
            out,
            "percentiles: linear between order statistics (type 7); sd with n - 1"
        );
        for period in &sm.periods {
            let _ = writeln!(
                out,
                "\n{}: jump {}",
                period.period,
                probability_text(&period.jump, sm.samples)
            );
            moments_table(&mut out, &period.columns, units);
        }
        revolution_text(&mut out, sm, units);
        let _ = writeln!(
            out,
            "\njump anywhere in revolution {}: {}",
            sm.revolution,
            probability_text(&sm.jump, sm.samples + sm.left_range_jumps)
        );
        left_range_text(&mut out, sm);
        full_model_text(&mut out, self, units);
        if let Some(steps) = &sm.steps {
            let _ = writeln!(
                out,
                "solver: {:.0} accepted steps per sample on average",
                steps.mean
            );
        }
        if let Some(t) = &self.timing {
            let _ = writeln!(
                out,
                "run time: {:.2} s on {} threads ({:.1} samples/s, {:.1} per thread)",
                t.wall_s, t.threads, t.samples_per_s, t.samples_per_s_per_thread
            );
        }
        out
    }
}

/// The samples that left the model's valid range (docs/MODEL.md §3.20): jumps after a
/// separation, not workable before one.
fn left_range_text(out: &mut String, sm: &Summary) {
    use std::fmt::Write;
    if sm.left_range_jumps > 0 {
        let _ = writeln!(
            out,
            "  of which {} left the model's valid range after the follower separated: counted as jumps, without statistics",
            sm.left_range_jumps
        );
    }
    if let Some(why) = &sm.not_workable_reason {
        let _ = writeln!(
            out,
            "not workable: {} samples left the model's valid range with the follower on the cam and are excluded from every statistic (first: {why})",
            sm.not_workable
        );
    }
}

#[cfg(test)]
mod tests {
    use super::two_level_header;

    /// The header names the subsample's cams (0 to --two-level − 1), not the pairs: with
    /// 1000 cams asked and 997 paired it says cams 0-999 and 997 pairs.
    #[test]
    fn the_two_level_header_counts_the_subsamples_cams() {
        let h = two_level_header("e", 1000, 997);
        assert!(h.contains(", cams 0-999 on the full model too ("), "{h}");
        assert!(h.contains("(997 of them workable on both models"), "{h}");
        let h = two_level_header("e", 3, 3);
        assert!(h.ends_with("cams 0-2 on the full model too"), "{h}");
        assert!(two_level_header("e", 1, 1).ends_with("cam 0 on the full model too"));
    }
}
