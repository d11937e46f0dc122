//! The statistics of a Monte Carlo study (`camsim montecarlo`), streamed: every sample's
//! record is added to a [`StudyStats`] and dropped, so a study's memory does not grow with
//! its samples. A [`StudyStats`] is what a shard file holds; merged shards give the same
//! [`Summary`], bit for bit, as the single run, whatever the thread count, the order the
//! samples finish in or the split (every statistic is order-independent:
//! [`crate::stats::stream`]).

use anyhow::{anyhow, ensure, Result};
use serde::{Deserialize, Serialize};

pub use crate::stats::columns::Columns;
use crate::stats::stream::{Moments, Stream};
use crate::stats::Probability;
use crate::study::montecarlo::{SampleRecord, COLUMNS};

/// One period of revolution 2 over the samples.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PeriodSummary {
    /// Period name.
    pub period: String,
    /// Every column of the run table.
    pub columns: Columns,
    /// Probability of a separation in this period.
    pub jump: Probability,
}

/// Whole-revolution statistics of revolution 2 (one value per sample each).
pub const REVOLUTION_COLUMNS: [&str; 6] = [
    "acc_rms_sum",
    "contact_force_min",
    "contact_force_max",
    "torque_max",
    "torque_min",
    "contact_stress_max",
];

/// The value of a whole-revolution statistic of one sample: the sum of the periods'
/// acceleration RMS (the sensitivity index of VI.4.2), or the extreme of the periods'
/// extremes.
pub fn revolution_value(r: &SampleRecord, name: &str) -> f64 {
    fn col<'a>(r: &'a SampleRecord, c: &'a str) -> impl Iterator<Item = f64> + 'a {
        r.periods.iter().filter_map(move |p| p.get(c))
    }
    match name {
        "acc_rms_sum" => col(r, "rms_acceleration").sum(),
        "contact_force_min" | "torque_min" => col(r, name).fold(f64::INFINITY, f64::min),
        _ => col(r, name).fold(f64::NEG_INFINITY, f64::max),
    }
}

/// A study's result over its samples.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Summary {
    /// Samples reduced.
    pub samples: u64,
    /// The revolution the statistics are of.
    pub revolution: u32,
    /// Every period of the program.
    pub periods: Vec<PeriodSummary>,
    /// Whole-revolution statistics ([`REVOLUTION_COLUMNS`]).
    pub whole_revolution: Columns,
    /// Probability of a separation anywhere in the revolution.
    pub jump: Probability,
    /// The profiles: waviness FPR and RMS lift deviation, in.
    pub profile: Columns,
    /// Accepted solver steps per sample (absent when no sample has statistics: every
    /// one jumped and then left the model's valid range).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub steps: Option<Moments>,
    /// Samples counted as jumps because their run left the model's valid range after
    /// the follower separated (in `jump`, not in the statistics).
    pub left_range_jumps: u64,
    /// Samples not workable: their run left the model's valid range with the follower
    /// on the cam (excluded from everything above).
    pub not_workable: u64,
    /// The lowest-indexed not-workable sample's reason.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub not_workable_reason: Option<String>,
}

/// One period's statistics: a stream per column of [`COLUMNS`] and the jumps.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PeriodStats {
    /// Period name.
    pub period: String,
    /// The [`COLUMNS`], in order.
    pub columns: Vec<Stream>,
    /// Samples that separated in this period.
    pub jumps: u64,
    /// The [`COLUMNS`] of the samples that separated anywhere in the revolution (a
    /// plot draws them apart from the held ones: these minus the merged ones).
    pub jumped_columns: Vec<Stream>,
}

/// The statistics of any set of samples of a study (a shard's, or the whole study's).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudyStats {
    /// Samples added.
    pub samples: u64,
    /// Every period of the program (empty before the first sample).
    pub periods: Vec<PeriodStats>,
    /// The [`REVOLUTION_COLUMNS`], in order.
    pub whole_revolution: Vec<Stream>,
    /// Samples that separated anywhere in the revolution.
    pub jumps: u64,
    /// The [`REVOLUTION_COLUMNS`] of the samples that separated anywhere in the
    /// revolution.
    pub jumped_revolution: Vec<Stream>,
    /// Waviness FPR of the profiles.
    pub fpr: Stream,
    /// RMS lift deviation of the profiles, in.
    pub rms_deviation_in: Stream,
    /// Accepted solver steps.
    pub steps: Stream,
    /// Samples whose run left the model's valid range after the follower separated
    /// (docs/MODEL.md §3.20): jumps, with no statistics (not in `samples`).
    #[serde(default)]
    pub left_range_jumps: u64,
    /// Samples whose run left the model's valid range with the follower on the cam:
    /// not workable, excluded (not in `samples`).
    #[serde(default)]
    pub not_workable: u64,
    /// The lowest-indexed not-workable sample and its reason (the same for any threads
    /// or shards).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub first_not_workable: Option<(u64, String)>,
}

impl StudyStats {
    /// Adds one sample's record.
    pub fn add(&mut self, r: &SampleRecord) -> Result<()> {
        if self.samples == 0 && self.periods.is_empty() {
            self.periods = r
                .periods
                .iter()
                .map(|p| PeriodStats {
                    period: p.period.clone(),
                    columns: vec![Stream::default(); COLUMNS.len()],
                    jumps: 0,
                    jumped_columns: vec![Stream::default(); COLUMNS.len()],
                })
                .collect();
            self.whole_revolution = vec![Stream::default(); REVOLUTION_COLUMNS.len()];
            self.jumped_revolution = vec![Stream::default(); REVOLUTION_COLUMNS.len()];
        }
        let theirs: Vec<&str> = r.periods.iter().map(|p| p.period.as_str()).collect();
        let ours: Vec<&str> = self.periods.iter().map(|p| p.period.as_str()).collect();
        ensure!(
            theirs == ours,
            "sample {} has the periods {theirs:?}, the study {ours:?}",
            r.index
        );
        let jumped = r.jump();
        for (p, s) in r.periods.iter().zip(self.periods.iter_mut()) {
            for (((col, v), st), jt) in COLUMNS
                .iter()
                .zip(p.values)
                .zip(s.columns.iter_mut())
                .zip(s.jumped_columns.iter_mut())
            {
                st.add(&format!("{}.{col}", p.period), v)?;
                if jumped {
                    jt.add(&format!("{}.{col}", p.period), v)?;
                }
            }
            s.jumps += u64::from(p.jump);
        }
        for ((c, st), jt) in REVOLUTION_COLUMNS
            .iter()
            .zip(self.whole_revolution.iter_mut())
            .zip(self.jumped_revolution.iter_mut())
        {
            let v = revolution_value(r, c);
            st.add(c, v)?;
            if jumped {
                jt.add(c, v)?;
            }
        }
        self.jumps += u64::from(r.jump());
        self.fpr.add("fpr", r.fpr as f64)?;
        self.rms_deviation_in
            .add("rms_deviation_in", r.rms_deviation_in)?;
        self.steps.add("steps", f64::from(r.steps))?;
        self.samples += 1;
        Ok(())
    }

    /// Every sample accounted for: those with statistics, the jumps that left the
    /// model's range and the samples not workable.
    pub fn accounted(&self) -> u64 {
        self.samples + self.left_range_jumps + self.not_workable
    }

    /// Counts sample `index` that left the model's valid range: a jump if the follower
    /// had separated (`separated`), otherwise not workable for `reason`.
    pub fn add_left_range(&mut self, index: u64, separated: bool, reason: &str) {
        if separated {
            self.left_range_jumps += 1;
            return;
        }
        self.not_workable += 1;
        self.note_not_workable(Some((index, reason.to_string())));
    }

    fn note_not_workable(&mut self, other: Option<(u64, String)>) {
        if let Some((i, r)) = other {
            if self.first_not_workable.as_ref().is_none_or(|(j, _)| i < *j) {
                self.first_not_workable = Some((i, r));
            }
        }
    }

    /// Adds another set of samples' statistics (of the same study).
    pub fn merge(&mut self, other: &StudyStats) -> Result<()> {
        self.left_range_jumps += other.left_range_jumps;
        self.not_workable += other.not_workable;
        self.note_not_workable(other.first_not_workable.clone());
        if other.samples == 0 {
            return Ok(());
        }
        if self.samples == 0 {
            let (l, n, f) = (
                self.left_range_jumps,
                self.not_workable,
                self.first_not_workable.take(),
            );
            *self = other.clone();
            (
                self.left_range_jumps,
                self.not_workable,
                self.first_not_workable,
            ) = (l, n, f);
            return Ok(());
        }
        let theirs: Vec<&str> = other.periods.iter().map(|p| p.period.as_str()).collect();
        let ours: Vec<&str> = self.periods.iter().map(|p| p.period.as_str()).collect();
        ensure!(
            theirs == ours,
            "the periods {theirs:?} differ from {ours:?}"
        );
        for (a, b) in self.periods.iter_mut().zip(&other.periods) {
            for (x, y) in a.columns.iter_mut().zip(&b.columns) {
                x.merge(y);
            }
            for (x, y) in a.jumped_columns.iter_mut().zip(&b.jumped_columns) {
                x.merge(y);
            }
            a.jumps += b.jumps;
        }
        for (x, y) in self
            .whole_revolution
            .iter_mut()
            .zip(&other.whole_revolution)
        {
            x.merge(y);
        }
        for (x, y) in self
            .jumped_revolution
            .iter_mut()
            .zip(&other.jumped_revolution)
        {
            x.merge(y);
        }
        self.jumps += other.jumps;
        self.fpr.merge(&other.fpr);
        self.rms_deviation_in.merge(&other.rms_deviation_in);
        self.steps.merge(&other.steps);
        self.samples += other.samples;
        Ok(())
    }

    /// Histogram bins held over every stream (the memory: about 60 bytes each).
    pub fn bins(&self) -> usize {
        self.periods
            .iter()
            .flat_map(|p| p.columns.iter().chain(&p.jumped_columns))
            .chain(&self.whole_revolution)
            .chain(&self.jumped_revolution)
            .chain([&self.fpr, &self.rms_deviation_in, &self.steps])
            .map(Stream::bins)
            .sum()
    }

    /// The result of a study whose every workable sample jumped and then left the
    /// model's valid range (docs/MODEL.md §3.20): P(jump) = 1 over them, no statistics.
    fn jumps_only(&self, revolution: u32) -> Summary {
        let l = self.left_range_jumps;
        Summary {
            samples: 0,
            revolution,
            periods: Vec::new(),
            whole_revolution: Columns(Vec::new()),
            jump: Probability::of(l, l),
            profile: Columns(Vec::new()),
            steps: None,
            left_range_jumps: l,
            not_workable: self.not_workable,
            not_workable_reason: self
                .first_not_workable
                .as_ref()
                .map(|(i, r)| format!("sample {i}: {r}")),
        }
    }

    /// The result of `revolution`'s statistics.
    pub fn summary(&self, revolution: u32) -> Result<Summary> {
        // Only samples that left the range without a separation failed: jumps are answers.
        if self.samples == 0 && self.left_range_jumps > 0 {
            return Ok(self.jumps_only(revolution));
        }
        if let (0, Some((i, why))) = (self.samples, &self.first_not_workable) {
            anyhow::bail!(
                "no sample is workable: {} of {} left the model's valid range with the follower on the cam (sample {i}: {why})",
                self.not_workable,
                self.accounted()
            );
        }
        ensure!(self.samples > 0, "no samples to summarize");
        let n = self.samples;
        let mut periods = Vec::new();
        for p in &self.periods {
            let mut columns = Vec::new();
            for (col, st) in COLUMNS.iter().zip(&p.columns) {
                columns.push((col.to_string(), st.moments(&format!("{}.{col}", p.period))?));
            }
            periods.push(PeriodSummary {
                period: p.period.clone(),
                columns: Columns(columns),
                jump: Probability::of(p.jumps, n),
            });
        }
        let mut whole = Vec::new();
        for (c, st) in REVOLUTION_COLUMNS.iter().zip(&self.whole_revolution) {
            whole.push((c.to_string(), st.moments(c)?));
        }
        Ok(Summary {
            samples: n,
            revolution,
            periods,
            whole_revolution: Columns(whole),
            jump: Probability::of(
                self.jumps + self.left_range_jumps,
                n + self.left_range_jumps,
            ),
            profile: Columns(vec![
                ("fpr".into(), self.fpr.moments("fpr")?),
                (
                    "rms_deviation_in".into(),
                    self.rms_deviation_in.moments("rms_deviation_in")?,
                ),
            ]),
            steps: Some(self.steps.moments("steps")?),
            left_range_jumps: self.left_range_jumps,
            not_workable: self.not_workable,
            not_workable_reason: self
                .first_not_workable
                .as_ref()
                .map(|(i, r)| format!("sample {i}: {r}")),
        })
    }

    /// The sanity checks of statistics read from a file of `samples` samples: every
    /// stream's own consistency and count, and what every run satisfies (solver steps
    /// taken, RMS values and stress not negative, each period's minima at most its
    /// averages and maxima, jumps at most the samples).
    pub fn check(&self, samples: u64) -> Result<()> {
        ensure!(
            self.accounted() == samples,
            "the statistics hold {} samples, the shard {samples}",
            self.accounted()
        );
        ensure!(
            (self.not_workable == 0) == self.first_not_workable.is_none(),
            "{} samples not workable, with the first's reason {}",
            self.not_workable,
            if self.first_not_workable.is_some() {
                "given"
            } else {
                "missing"
            }
        );
        // The streams hold the samples with statistics only.
        let samples = self.samples;
        if self.samples == 0 {
            ensure!(
                self.periods.is_empty()
                    && self.whole_revolution.is_empty()
                    && self.jumped_revolution.is_empty(),
                "an empty shard with statistics"
            );
            return Ok(());
        }
        ensure!(
            self.whole_revolution.len() == REVOLUTION_COLUMNS.len()
                && self.jumped_revolution.len() == REVOLUTION_COLUMNS.len()
                && self.periods.iter().all(|p| {
                    p.columns.len() == COLUMNS.len() && p.jumped_columns.len() == COLUMNS.len()
                })
                && !self.periods.is_empty(),
            "the statistics do not have the study's columns"
        );
        self.check_streams(samples)?;
        self.check_jumped_streams()?;
        let steps_min = self.steps.range().map_or(0.0, |r| r.0);
        ensure!(
            steps_min >= 1.0,
            "steps = {steps_min}: every run takes solver steps"
        );
        ensure!(
            self.jumps <= samples,
            "{} jumps in {samples} samples",
            self.jumps
        );
        self.check_periods_ordered()
    }

    /// Every stream's own consistency, its count of `samples`, and the non-negative ones
    /// not negative.
    fn check_streams(&self, samples: u64) -> Result<()> {
        let all = self
            .periods
            .iter()
            .flat_map(|p| {
                COLUMNS
                    .iter()
                    .zip(&p.columns)
                    .map(move |(c, s)| (format!("{}.{c}", p.period), s))
            })
            .chain(
                REVOLUTION_COLUMNS
                    .iter()
                    .zip(&self.whole_revolution)
                    .map(|(c, s)| (c.to_string(), s)),
            )
            .chain([
                ("fpr".to_string(), &self.fpr),
                ("rms_deviation_in".to_string(), &self.rms_deviation_in),
                ("steps".to_string(), &self.steps),
            ]);
        for (name, s) in all {
            s.check(&name)?;
            ensure!(
                s.count() == samples,
                "{name}: {} samples, the shard {samples}",
                s.count()
            );
            let lo = s.range().map_or(0.0, |r| r.0);
            let nonneg = name.contains(".rms_")
                || name.ends_with("contact_stress_max")
                || name == "rms_deviation_in"
                || name == "fpr";
            ensure!(
                !nonneg || lo >= 0.0,
                "{name}: minimum {lo}: must not be negative"
            );
        }
        Ok(())
    }

    /// Every jumped sample's stream: its own consistency and its count of the jumps.
    fn check_jumped_streams(&self) -> Result<()> {
        let jumped = self
            .periods
            .iter()
            .flat_map(|p| {
                COLUMNS
                    .iter()
                    .zip(&p.jumped_columns)
                    .map(move |(c, s)| (format!("jumped {}.{c}", p.period), s))
            })
            .chain(
                REVOLUTION_COLUMNS
                    .iter()
                    .zip(&self.jumped_revolution)
                    .map(|(c, s)| (format!("jumped {c}"), s)),
            );
        for (name, s) in jumped {
            s.check(&name)?;
            ensure!(
                s.count() == self.jumps,
                "{name}: {} samples, the jumps {}",
                s.count(),
                self.jumps
            );
        }
        Ok(())
    }

    /// Every period's jumps at most the revolution's, and its minima at most its averages
    /// and maxima.
    fn check_periods_ordered(&self) -> Result<()> {
        let col = |n: &str| COLUMNS.iter().position(|c| *c == n);
        for p in &self.periods {
            ensure!(
                p.jumps <= self.jumps,
                "period {}: {} jumps, more than the revolution's {}",
                p.period,
                p.jumps,
                self.jumps
            );
            for (lo, mid, hi) in [
                (
                    "contact_force_min",
                    "contact_force_avg",
                    "contact_force_max",
                ),
                ("torque_min", "torque_avg", "torque_max"),
            ] {
                let get = |n: &str| {
                    col(n)
                        .and_then(|i| p.columns.get(i))
                        .and_then(Stream::range)
                        .ok_or_else(|| anyhow!("period {}: no {n}", p.period))
                };
                let (a, m, b) = (get(lo)?, get(mid)?, get(hi)?);
                // Each sample's minimum ≤ average ≤ maximum: so are their smallest and
                // their largest values.
                ensure!(
                    a.0 <= m.0 && m.0 <= b.0 && a.1 <= m.1 && m.1 <= b.1,
                    "period {}: {lo}, {mid}, {hi}: the minimum must not exceed the average or the maximum (smallest {} / {} / {}, largest {} / {} / {})",
                    p.period,
                    a.0,
                    m.0,
                    b.0,
                    a.1,
                    m.1,
                    b.1
                );
            }
        }
        Ok(())
    }
}

/// The statistics of `records` of `revolution` (in any order, each sample once).
pub fn summarize(records: &[SampleRecord], revolution: u32) -> Result<Summary> {
    let mut s = StudyStats::default();
    for r in records {
        s.add(r)?;
    }
    s.summary(revolution)
}
