//! The two-level Monte Carlo estimate of `camsim montecarlo --two-level n`: every one of
//! the study's N cams runs on the reduced model, the first n of them on the full model as
//! well, and a full-model statistic is the reduced model's mean over the N cams plus the
//! mean full − reduced difference over the n (docs/MODEL.md §9.7).
//!
//! The estimator is the paired-difference (two-phase) one, a control variate with
//! coefficient 1: with R the reduced model's value of a cam, F the full model's and
//! Y = F − R,
//!
//! ```text
//! μ̂_F = mean_N(R) + mean_n(Y)
//! Var(μ̂_F) = Var(F)/N + (1/n − 1/N) Var(Y)
//! ```
//!
//! (the n cams are among the N: the exact variance of the sum of the two means; n = N
//! gives the full study's Var(F)/N). Var(F) and Var(Y) are the sample variances (n − 1)
//! of the n cams, and the 95 % interval is μ̂_F ± z·√Var (z = [`Z95`]; normal, for
//! large n), cut to [0, 1] for a probability. For a probability the two variances are
//! taken with pseudo-counts, so that a subsample without a jump or without a
//! disagreement does not claim a zero-width interval: Var(F) = p̃(1 − p̃) with
//! p̃ = (k + 2)/(n + 4) (Agresti and Coull), Var(Y) with ½ added to each of the four
//! cells of the pairs' 2 × 2 table (Agresti and Min); the estimate itself has none. Everything kept is an integer count or an
//! exact sum ([`Stream`]), so the estimate is the same bits for any thread count, order or
//! split into shards.

use anyhow::{ensure, Result};
use serde::{Deserialize, Serialize};

use crate::stats::stream::Stream;
use crate::stats::study::{revolution_value, StudyStats, REVOLUTION_COLUMNS};
use crate::stats::{Probability, Z95};
use crate::study::montecarlo::{Outcome, SampleRecord};

/// A full-model statistic estimated on two levels.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Estimate {
    /// The estimate: `reduced + correction`.
    pub value: f64,
    /// The reduced model's mean over the N cams.
    pub reduced: f64,
    /// The mean full − reduced difference over the n cams.
    pub correction: f64,
    /// Its standard error √Var.
    pub standard_error: f64,
    /// Lower end of the 95 % interval.
    pub lo95: f64,
    /// Upper end of the 95 % interval.
    pub hi95: f64,
}

/// The estimate from the reduced mean over `big_n` cams, the difference's mean and
/// variance and the full model's variance over `n` of them (`n` ≥ 2, `n` ≤ `big_n`),
/// within `bounds` (a probability's [0, 1]) if given.
pub fn estimate(
    reduced: f64,
    big_n: u64,
    n: u64,
    diff: (f64, f64),
    full_var: f64,
    bounds: Option<(f64, f64)>,
) -> Result<Estimate> {
    ensure!(
        n >= 2 && n <= big_n,
        "the two-level estimate needs 2 <= n <= N full-model cams (n = {n}, N = {big_n})"
    );
    let (correction, diff_var) = diff;
    let (nf, big) = (n as f64, big_n as f64);
    let var = full_var.max(0.0) / big + (1.0 / nf - 1.0 / big) * diff_var.max(0.0);
    let se = var.sqrt();
    let value = reduced + correction;
    let (mut lo, mut hi) = (value - Z95 * se, value + Z95 * se);
    let mut value_out = value;
    if let Some((a, b)) = bounds {
        (lo, hi, value_out) = (lo.clamp(a, b), hi.clamp(a, b), value.clamp(a, b));
    }
    let e = Estimate {
        value: value_out,
        reduced,
        correction,
        standard_error: se,
        lo95: lo,
        hi95: hi,
    };
    ensure!(
        [
            e.value,
            e.reduced,
            e.correction,
            e.standard_error,
            e.lo95,
            e.hi95
        ]
        .iter()
        .all(|v| v.is_finite()),
        "the two-level estimate is not finite ({e:?})"
    );
    Ok(e)
}

/// Two indicators' paired counts over n cams: where only the full model has the event,
/// where only the reduced one has it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Disagreements {
    /// The full model separated, the reduced one did not (Y = +1).
    pub full_only: u64,
    /// The reduced model separated, the full one did not (Y = −1).
    pub reduced_only: u64,
}

impl Disagreements {
    fn add(&mut self, full: bool, reduced: bool) {
        self.full_only += u64::from(full && !reduced);
        self.reduced_only += u64::from(reduced && !full);
    }

    fn merge(&mut self, o: &Disagreements) {
        self.full_only += o.full_only;
        self.reduced_only += o.reduced_only;
    }

    /// The mean and sample variance (n − 1) of Y ∈ {−1, 0, 1} over `n` cams (n ≥ 2).
    pub fn mean_var(&self, n: u64) -> (f64, f64) {
        let nf = n as f64;
        let (a, b) = (self.full_only as f64, self.reduced_only as f64);
        let mean = (a - b) / nf;
        // Σ(y − ȳ)² = Σy² − nȳ² with Σy² = a + b.
        (mean, ((a + b) - nf * mean * mean).max(0.0) / (nf - 1.0))
    }

    /// The variance of Y with ½ added to each cell of the 2 × 2 table (n + 2 pairs, one
    /// more disagreement: never 0).
    pub fn adjusted_var(&self, n: u64) -> f64 {
        let nf = n as f64 + 2.0;
        let (a, b) = (self.full_only as f64 + 0.5, self.reduced_only as f64 + 0.5);
        let mean = (a - b) / nf;
        ((a + b) - nf * mean * mean).max(0.0) / (nf - 1.0)
    }
}

/// The variance p̃(1 − p̃) of an indicator seen `count` times in `n`, with Agresti and
/// Coull's p̃ = (count + 2)/(n + 4) (never 0).
pub fn indicator_var_adjusted(count: u64, n: u64) -> f64 {
    let p = (count as f64 + 2.0) / (n as f64 + 4.0);
    p * (1.0 - p)
}

/// The sample variance (n − 1) of an indicator seen `count` times in `n` (n ≥ 2).
pub fn indicator_var(count: u64, n: u64) -> f64 {
    let (k, nf) = (count as f64, n as f64);
    let p = k / nf;
    (p * (1.0 - p) * nf / (nf - 1.0)).max(0.0)
}

/// What the full-model subsample adds to a study (a shard file holds it beside the reduced
/// model's [`StudyStats`]).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TwoLevelStats {
    /// The subsample on the full model.
    pub full: StudyStats,
    /// Jump anywhere in the revolution: the pairs that disagree.
    pub jump: Disagreements,
    /// Jump in each period of the program, in order.
    pub period_jumps: Vec<Disagreements>,
    /// Full − reduced of the [`REVOLUTION_COLUMNS`], in order.
    pub whole_revolution: Vec<Stream>,
    /// The pairs without statistics (docs/MODEL.md §3.20).
    #[serde(default)]
    pub jump_only: JumpOnlyPairs,
}

/// Subsample pairs in which a model's run left its valid range after the follower
/// separated (a jump on that model, docs/MODEL.md §3.20): both jump verdicts are known
/// (in [`TwoLevelStats::jump`]), neither period nor column statistics.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JumpOnlyPairs {
    /// Such pairs.
    pub pairs: u64,
    /// Of them, the pairs whose full model jumped.
    pub full_jumps: u64,
}

impl TwoLevelStats {
    /// Adds one cam's pair of outcomes, its reduced model workable (a record, or a jump
    /// that left the range): a full-model run that left the range with the follower on
    /// the cam is not workable (counted in `full`, no pair); a run that left it after a
    /// separation is a jump on its model (a [`JumpOnlyPairs`] pair).
    pub fn add_outcomes(&mut self, index: u64, reduced: &Outcome, full: &Outcome) -> Result<()> {
        match (reduced, full) {
            (Ok(r), Ok(f)) => return self.add(r, f),
            (_, Err(l)) if !l.separated => {
                self.full
                    .add_left_range(index, false, &format!("on the full model: {}", l.reason));
                return Ok(());
            }
            (Err(l), _) => ensure!(
                l.separated,
                "sample {index}: not workable on the reduced model, so not a pair"
            ),
            (Ok(_), Err(_)) => {}
        }
        let verdict = |o: &Outcome| o.as_ref().map_or(true, SampleRecord::jump);
        let (f, r) = (verdict(full), verdict(reduced));
        self.jump.add(f, r);
        self.jump_only.pairs += 1;
        self.jump_only.full_jumps += u64::from(f);
        Ok(())
    }

    /// The subsample's pairs with both jump verdicts (with statistics or not).
    pub fn pairs(&self) -> u64 {
        self.full.samples + self.jump_only.pairs
    }

    /// Adds one cam's pair of records (the same cam on both models).
    pub fn add(&mut self, reduced: &SampleRecord, full: &SampleRecord) -> Result<()> {
        ensure!(
            reduced.index == full.index && reduced.periods.len() == full.periods.len(),
            "sample {}: the reduced and the full model's records do not pair",
            full.index
        );
        self.full.add(full)?;
        if self.period_jumps.is_empty() {
            self.period_jumps = vec![Disagreements::default(); full.periods.len()];
            self.whole_revolution = vec![Stream::default(); REVOLUTION_COLUMNS.len()];
        }
        ensure!(
            self.period_jumps.len() == full.periods.len(),
            "sample {}: {} periods, the study {}",
            full.index,
            full.periods.len(),
            self.period_jumps.len()
        );
        self.jump.add(full.jump(), reduced.jump());
        for ((d, f), r) in self
            .period_jumps
            .iter_mut()
            .zip(&full.periods)
            .zip(&reduced.periods)
        {
            d.add(f.jump, r.jump);
        }
        for (c, s) in REVOLUTION_COLUMNS.iter().zip(&mut self.whole_revolution) {
            let y = revolution_value(full, c) - revolution_value(reduced, c);
            s.add(&format!("full - reduced {c}"), y)?;
        }
        Ok(())
    }

    /// Adds another set of pairs (of the same study).
    pub fn merge(&mut self, other: &TwoLevelStats) -> Result<()> {
        self.jump_only.pairs += other.jump_only.pairs;
        self.jump_only.full_jumps += other.jump_only.full_jumps;
        self.jump.merge(&other.jump);
        self.full.merge(&other.full)?;
        if other.period_jumps.is_empty() {
            return Ok(());
        }
        if self.period_jumps.is_empty() {
            self.period_jumps.clone_from(&other.period_jumps);
            self.whole_revolution.clone_from(&other.whole_revolution);
            return Ok(());
        }
        ensure!(
            self.period_jumps.len() == other.period_jumps.len()
                && self.whole_revolution.len() == other.whole_revolution.len(),
            "the full-model subsamples have different periods"
        );
        for (a, b) in self.period_jumps.iter_mut().zip(&other.period_jumps) {
            a.merge(b);
        }
        for (a, b) in self
            .whole_revolution
            .iter_mut()
            .zip(&other.whole_revolution)
        {
            a.merge(b);
        }
        Ok(())
    }

    /// The sanity checks of a file's subsample of `n` cams (a cam not workable on the
    /// reduced model has no pair: at most `n` are held).
    pub fn check(&self, n: u64) -> Result<()> {
        let held = self.full.accounted() + self.jump_only.pairs;
        ensure!(
            held <= n && self.jump_only.full_jumps <= self.jump_only.pairs,
            "{held} cams ({} jumps of {} without statistics) in a subsample of {n}",
            self.jump_only.full_jumps,
            self.jump_only.pairs
        );
        self.full.check(self.full.accounted())?;
        ensure!(
            self.jump.full_only + self.jump.reduced_only <= self.pairs(),
            "{} + {} disagreements in {} pairs",
            self.jump.full_only,
            self.jump.reduced_only,
            self.pairs()
        );
        let n = self.full.samples;
        if n == 0 {
            return Ok(());
        }
        ensure!(
            self.period_jumps.len() == self.full.periods.len()
                && self.whole_revolution.len() == REVOLUTION_COLUMNS.len(),
            "the full-model subsample does not have the study's columns"
        );
        for d in &self.period_jumps {
            ensure!(
                d.full_only + d.reduced_only <= n,
                "{} + {} disagreements in {n} pairs",
                d.full_only,
                d.reduced_only
            );
        }
        for (c, s) in REVOLUTION_COLUMNS.iter().zip(&self.whole_revolution) {
            s.check(&format!("full - reduced {c}"))?;
            ensure!(
                s.count() == n,
                "full - reduced {c}: {} of {n} pairs",
                s.count()
            );
        }
        Ok(())
    }

    /// The full model's estimates, with `reduced` the reduced model's statistics of the
    /// study's N cams: P(jump) over the pairs with both verdicts (a jump that left the
    /// range is a jump, docs/MODEL.md §3.20), the periods and columns over the pairs
    /// with statistics. `None` when fewer than 2 pairs have verdicts (the full model
    /// left its range with the follower on the cam on the rest of the subsample).
    pub fn summary(&self, reduced: &StudyStats) -> Result<Option<TwoLevelSummary>> {
        let (big_n, n) = (reduced.samples + reduced.left_range_jumps, self.pairs());
        if n < 2 {
            return Ok(None);
        }
        let full_jumps = self.full.jumps + self.jump_only.full_jumps;
        let jump = estimate(
            (reduced.jumps + reduced.left_range_jumps) as f64 / big_n as f64,
            big_n,
            n,
            (self.jump.mean_var(n).0, self.jump.adjusted_var(n)),
            indicator_var_adjusted(full_jumps, n),
            Some((0.0, 1.0)),
        )?;
        let (periods, whole_revolution) = match self.full.samples {
            0 | 1 => (Vec::new(), Vec::new()),
            _ => self.with_statistics(reduced)?,
        };
        Ok(Some(TwoLevelSummary {
            estimator: ESTIMATOR,
            samples: big_n,
            full_samples: n,
            jump,
            disagreements: self.jump,
            subsample_full_jump: Probability::of(full_jumps, n),
            jump_only_pairs: self.jump_only.pairs,
            full_not_workable: self.full.not_workable,
            full_not_workable_reason: self
                .full
                .first_not_workable
                .as_ref()
                .map(|(i, r)| format!("sample {i}: {r}")),
            periods,
            whole_revolution,
        }))
    }

    /// The period and column estimates over the pairs with statistics (at least 2).
    fn with_statistics(
        &self,
        reduced: &StudyStats,
    ) -> Result<(Vec<PeriodEstimate>, Vec<ColumnEstimate>)> {
        let (big_n, n) = (reduced.samples, self.full.samples);
        let p01 = Some((0.0, 1.0));
        let mut periods = Vec::new();
        for ((d, f), r) in self
            .period_jumps
            .iter()
            .zip(&self.full.periods)
            .zip(&reduced.periods)
        {
            let e = estimate(
                r.jumps as f64 / big_n as f64,
                big_n,
                n,
                (d.mean_var(n).0, d.adjusted_var(n)),
                indicator_var_adjusted(f.jumps, n),
                p01,
            )?;
            periods.push(PeriodEstimate {
                period: f.period.clone(),
                jump: e,
            });
        }
        let mut whole_revolution = Vec::new();
        for (((c, y), f), r) in REVOLUTION_COLUMNS
            .iter()
            .zip(&self.whole_revolution)
            .zip(&self.full.whole_revolution)
            .zip(&reduced.whole_revolution)
        {
            let e = estimate(
                r.mean(),
                big_n,
                n,
                (y.mean(), y.variance()),
                f.variance(),
                None,
            )?;
            whole_revolution.push(ColumnEstimate {
                column: c.to_string(),
                mean: e,
            });
        }
        Ok((periods, whole_revolution))
    }
}

/// The estimator's name, as the reports print it.
pub const ESTIMATOR: &str =
    "two-level Monte Carlo, paired differences (a control variate with coefficient 1)";

/// One period's jump probability on the full model.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PeriodEstimate {
    /// Period name.
    pub period: String,
    /// P(jump) in the period.
    pub jump: Estimate,
}

/// One whole-revolution column's mean on the full model.
#[derive(Clone, Debug, PartialEq)]
pub struct ColumnEstimate {
    /// The column (one of [`REVOLUTION_COLUMNS`]).
    pub column: String,
    /// Its mean over the cams, in the column's unit (inch family).
    pub mean: Estimate,
}

impl Serialize for ColumnEstimate {
    /// The column's name, and its mean as a measure of the column's quantity
    /// ([`crate::stats::columns::column_dimension`]): `mean_lb` / `mean_n` for a force,
    /// plain `mean` for a dimensionless column.
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(2))?;
        m.serialize_entry("column", &self.column)?;
        let dimension = crate::stats::columns::column_dimension(&self.column);
        crate::stats::columns::entry(&mut m, "mean", &self.mean, dimension)?;
        m.end()
    }
}

/// The full model's statistics of a two-level study.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TwoLevelSummary {
    /// [`ESTIMATOR`].
    pub estimator: &'static str,
    /// N: cams on the reduced model.
    pub samples: u64,
    /// n: the pairs, the subsample's cams with verdicts on both models (the subsample,
    /// cams 0 to `--two-level` − 1, less those not workable on either model).
    pub full_samples: u64,
    /// P(jump anywhere in the revolution) on the full model.
    pub jump: Estimate,
    /// Pairs of the subsample whose jump verdicts disagree.
    pub disagreements: Disagreements,
    /// The full model's own P(jump) on the n cams alone (Wilson), for comparison.
    pub subsample_full_jump: Probability,
    /// Of the n pairs, those without statistics: a model's run left its valid range
    /// after the follower separated (docs/MODEL.md §3.20).
    pub jump_only_pairs: u64,
    /// Subsample cams that left the full model's valid range with the follower on the
    /// cam: not workable on the full model, no pair.
    pub full_not_workable: u64,
    /// The first of them, with its reason.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub full_not_workable_reason: Option<String>,
    /// P(jump) per period.
    pub periods: Vec<PeriodEstimate>,
    /// Means of the whole-revolution columns.
    pub whole_revolution: Vec<ColumnEstimate>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::montecarlo::{PeriodValues, COLUMNS};

    /// SplitMix64: the test's own random numbers.
    struct Rng(u64);

    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        }

        /// A standard normal deviate (Box-Muller).
        fn normal(&mut self) -> f64 {
            let (u, v) = (1.0 - self.next(), self.next());
            (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
        }
    }

    /// A record of one period whose acceleration RMS is `acc` (so acc_rms_sum = acc).
    fn record(index: u64, jump: bool, acc: f64) -> SampleRecord {
        let mut values = [1.0; COLUMNS.len()];
        if let Some(i) = COLUMNS.iter().position(|c| *c == "rms_acceleration") {
            values[i] = acc;
        }
        SampleRecord {
            index,
            fpr: 17,
            rms_deviation_in: 1e-4,
            periods: vec![PeriodValues {
                period: "rise".into(),
                values,
                jump,
            }],
            steps: 1,
        }
    }

    /// The synthetic cam `i`: the full model jumps with probability 0.3 and has a mean
    /// acceleration sum of 10; the reduced model is deliberately wrong: P(jump) 0.24
    /// (0.2 + 0.8 × 0.05) and a mean of 0.9 × 10 + 2 = 11.
    fn pair(rng: &mut Rng, i: u64) -> (SampleRecord, SampleRecord) {
        let (u1, u2, g, g2) = (rng.next(), rng.next(), rng.normal(), rng.normal());
        let acc = 10.0 + g;
        let full = record(i, u1 < 0.3, acc);
        let reduced = record(i, u1 < 0.2 || u2 < 0.05, 0.9 * acc + 2.0 + 0.3 * g2);
        (reduced, full)
    }

    /// A two-level study of `big_n` synthetic cams, `n` of them on the full model.
    fn study(seed: u64, big_n: u64, n: u64) -> TwoLevelSummary {
        let mut rng = Rng(seed);
        let (mut reduced, mut two) = (StudyStats::default(), TwoLevelStats::default());
        for i in 0..big_n {
            let (r, f) = pair(&mut rng, i);
            reduced.add(&r).unwrap();
            if i < n {
                two.add(&r, &f).unwrap();
            }
        }
        two.check(n).unwrap();
        two.summary(&reduced).unwrap().unwrap()
    }

    #[test]
    fn the_whole_study_on_both_models_is_the_full_models_mean() {
        // n = N: the reduced model cancels, the estimate is the full model's mean and
        // its variance the full study's Var(F)/N.
        let mut rng = Rng(3);
        let (mut reduced, mut two) = (StudyStats::default(), TwoLevelStats::default());
        let mut f_jumps = 0u64;
        let mut acc = Vec::new();
        for i in 0..50 {
            let (r, f) = pair(&mut rng, i);
            f_jumps += u64::from(f.jump());
            acc.push(revolution_value(&f, "acc_rms_sum"));
            reduced.add(&r).unwrap();
            two.add(&r, &f).unwrap();
        }
        let s = two.summary(&reduced).unwrap().unwrap();
        let p = f_jumps as f64 / 50.0;
        assert!((s.jump.value - p).abs() < 1e-12, "{} vs {p}", s.jump.value);
        // (Agresti-Coull's p̃ in the variance of a probability.)
        let q = (f_jumps as f64 + 2.0) / 54.0;
        let var_f = q * (1.0 - q);
        assert!((s.jump.standard_error - (var_f / 50.0).sqrt()).abs() < 1e-12);
        let mean = acc.iter().sum::<f64>() / 50.0;
        let var = acc.iter().map(|a| (a - mean).powi(2)).sum::<f64>() / 49.0;
        let m = &s.whole_revolution[0];
        assert_eq!(m.column, "acc_rms_sum");
        assert!((m.mean.value - mean).abs() < 1e-12);
        assert!((m.mean.standard_error - (var / 50.0).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn hand_computed_estimate() {
        // N = 10 cams, 3 reduced jumps; n = 4 pairs: one full-only, none reduced-only,
        // the full model jumps on 2 of the 4. mean Y = 1/4, Var Y = (1 - 4/16)/3 = 1/4,
        // Var F = (1/2)(1/2)(4/3) = 1/3: Var = (1/3)/10 + (1/4 - 1/10)(1/4) = 0.070833...
        let d = Disagreements {
            full_only: 1,
            reduced_only: 0,
        };
        let (m, v) = d.mean_var(4);
        assert_eq!((m, v), (0.25, 0.25));
        assert!((indicator_var(2, 4) - 1.0 / 3.0).abs() < 1e-15);
        // With the pseudo-counts: 1.5 and 0.5 of 6 pairs, Var Y = (2 - 6/36)/5 = 11/30;
        // p̃ = 4/8, Var F = 1/4; Var = (1/4)/10 + (3/20)(11/30) = 0.08.
        assert!((d.adjusted_var(4) - 11.0 / 30.0).abs() < 1e-15);
        assert_eq!(indicator_var_adjusted(2, 4), 0.25);
        let adj = estimate(0.3, 10, 4, (m, d.adjusted_var(4)), 0.25, None).unwrap();
        assert!((adj.standard_error - 0.08f64.sqrt()).abs() < 1e-12);
        // Nothing seen (no jump, no disagreement in 10 of 40): not a zero width.
        let none = Disagreements::default();
        let e0 = estimate(
            0.0,
            40,
            10,
            (0.0, none.adjusted_var(10)),
            indicator_var_adjusted(0, 10),
            Some((0.0, 1.0)),
        )
        .unwrap();
        assert!(e0.lo95 == 0.0 && e0.hi95 > 0.05, "{e0:?}");
        let e = estimate(0.3, 10, 4, (m, v), indicator_var(2, 4), Some((0.0, 1.0))).unwrap();
        let var: f64 = 1.0 / 30.0 + 0.15 * 0.25;
        assert!((e.value - 0.55).abs() < 1e-12);
        assert!((e.standard_error - var.sqrt()).abs() < 1e-12);
        // 0.55 ± 0.52: the upper end cut at 1.
        assert!((e.lo95 - (0.55 - Z95 * var.sqrt())).abs() < 1e-12);
        assert_eq!(e.hi95, 1.0);
        let free = estimate(0.3, 10, 4, (m, v), indicator_var(2, 4), None).unwrap();
        assert!((free.hi95 - (0.55 + Z95 * var.sqrt())).abs() < 1e-12);
        // Refused: fewer than 2 full-model cams, or more than the study's.
        assert!(estimate(0.3, 10, 1, (0.0, 0.0), 0.0, None).is_err());
        assert!(estimate(0.3, 10, 11, (0.0, 0.0), 0.0, None).is_err());
    }

    #[test]
    fn unbiased_where_the_reduced_model_is_wrong() {
        // 400 studies of 1000 cams, 100 on the full model. The reduced model alone
        // says 0.24 and 11; the mean estimate is the full model's 0.3 and 10 within four
        // standard errors of a mean of 400 (the standard error from the spread seen).
        let reps = 400u64;
        let (mut p, mut p2, mut red, mut a, mut a2) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for seed in 0..reps {
            let s = study(1000 + seed, 1000, 100);
            p += s.jump.value;
            p2 += s.jump.value * s.jump.value;
            red += s.jump.reduced;
            let m = s.whole_revolution[0].mean;
            a += m.value;
            a2 += m.value * m.value;
        }
        let r = reps as f64;
        let se = |s: f64, s2: f64| ((s2 / r - (s / r).powi(2)) / (r - 1.0)).sqrt();
        assert!((red / r - 0.24).abs() < 0.005, "reduced {}", red / r);
        assert!(
            (p / r - 0.3).abs() < 4.0 * se(p, p2),
            "{} +- {}",
            p / r,
            se(p, p2)
        );
        assert!(
            (a / r - 10.0).abs() < 4.0 * se(a, a2),
            "{} +- {}",
            a / r,
            se(a, a2)
        );
    }

    #[test]
    fn the_interval_covers_the_full_models_answer_about_95_percent() {
        // 400 seeded studies: the 95 % intervals hold the true 0.3 and 10 in 360 to 397
        // of them (95 % of 400 is 380, binomial sd 4.4: about ±4 sd).
        let (mut pj, mut pa) = (0u32, 0u32);
        for seed in 0..400 {
            let s = study(7000 + seed, 1000, 100);
            pj += u32::from(s.jump.lo95 <= 0.3 && 0.3 <= s.jump.hi95);
            let m = s.whole_revolution[0].mean;
            pa += u32::from(m.lo95 <= 10.0 && 10.0 <= m.hi95);
        }
        assert!((360..=397).contains(&pj), "P(jump) covered {pj} of 400");
        assert!((360..=397).contains(&pa), "mean covered {pa} of 400");
    }

    #[test]
    fn merged_halves_are_the_whole_bit_for_bit() {
        let mut rng = Rng(11);
        let pairs: Vec<_> = (0..40).map(|i| pair(&mut rng, i)).collect();
        let (mut whole, mut a, mut b) = (
            TwoLevelStats::default(),
            TwoLevelStats::default(),
            TwoLevelStats::default(),
        );
        let mut reduced = StudyStats::default();
        for (i, (r, f)) in pairs.iter().enumerate() {
            whole.add(r, f).unwrap();
            reduced.add(r).unwrap();
            if i % 2 == 0 { &mut a } else { &mut b }.add(r, f).unwrap();
        }
        b.merge(&a).unwrap();
        let (x, y) = (
            whole.summary(&reduced).unwrap().unwrap(),
            b.summary(&reduced).unwrap().unwrap(),
        );
        assert_eq!(format!("{x:?}"), format!("{y:?}"));
    }

    /// The counting rule of docs/MODEL.md §3.20 on the pairs: a run that left the range
    /// after a separation is a jump on its model (a pair without statistics), one that
    /// left it on the full model with the follower on the cam has no pair. Five cams:
    /// 0 reduced left after separating, full on the cam without a jump (reduced only);
    /// 1 reduced jumps, full left after separating (agree); 2 full not workable;
    /// 3 and 4 record pairs (neither jumps, both jump). Reduced: 3 jumps of 5 workable
    /// (0.6); pairs 0, 1, 3, 4: correction (0 − 1)/4, estimate 0.35; full 2 of 4.
    #[test]
    fn cams_that_leave_the_range_are_jumps_or_no_pair() {
        use crate::study::montecarlo::LeftRange;
        let left = |separated| {
            Err(LeftRange {
                separated,
                reason: "left".into(),
            })
        };
        let cams: Vec<(Outcome, Outcome)> = vec![
            (left(true), Ok(record(0, false, 1.0))),
            (Ok(record(1, true, 1.0)), left(true)),
            (Ok(record(2, false, 1.0)), left(false)),
            (Ok(record(3, false, 1.0)), Ok(record(3, false, 2.0))),
            (Ok(record(4, true, 3.0)), Ok(record(4, true, 5.0))),
        ];
        let (mut reduced, mut whole) = (StudyStats::default(), TwoLevelStats::default());
        let (mut a, mut b) = (TwoLevelStats::default(), TwoLevelStats::default());
        for (i, (r, f)) in (0u64..).zip(&cams) {
            match r {
                Ok(rec) => reduced.add(rec).unwrap(),
                Err(l) => reduced.add_left_range(i, l.separated, &l.reason),
            }
            whole.add_outcomes(i, r, f).unwrap();
            if i < 2 { &mut a } else { &mut b }
                .add_outcomes(i, r, f)
                .unwrap();
        }
        whole.check(5).unwrap();
        assert_eq!((whole.pairs(), whole.jump_only.pairs), (4, 2));
        assert_eq!((whole.jump.full_only, whole.jump.reduced_only), (0, 1));
        let s = whole.summary(&reduced).unwrap().unwrap();
        assert_eq!((s.samples, s.full_samples, s.jump_only_pairs), (5, 4, 2));
        assert_eq!((s.jump.reduced, s.jump.correction), (0.6, -0.25));
        assert!((s.jump.value - 0.35).abs() < 1e-15, "{}", s.jump.value);
        assert_eq!((s.subsample_full_jump.count, s.full_not_workable), (2, 1));
        assert_eq!(
            s.full_not_workable_reason.as_deref(),
            Some("sample 2: on the full model: left")
        );
        // The periods and means over the record pairs 3 and 4 (reduced: cams 1-4).
        let acc = s
            .whole_revolution
            .iter()
            .find(|c| c.column == "acc_rms_sum")
            .unwrap();
        assert_eq!((acc.mean.reduced, acc.mean.correction), (1.5, 1.5));
        assert_eq!(s.periods.len(), 1);
        b.merge(&a).unwrap();
        let m = b.summary(&reduced).unwrap().unwrap();
        assert_eq!(format!("{m:?}"), format!("{s:?}"));
        // One pair with verdicts: no estimate.
        let mut one = TwoLevelStats::default();
        let (r, f) = &cams[0];
        one.add_outcomes(0, r, f).unwrap();
        assert!(one.summary(&reduced).unwrap().is_none());
    }
}
