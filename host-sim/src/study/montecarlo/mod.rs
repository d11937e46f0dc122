//! The Monte Carlo study of `camsim montecarlo`: many actual cams, in parallel,
//! reproducible bit for bit.
//!
//! Sample `i` of a study with master seed `S` is the actual cam of
//! [`crate::actual::build_profile`]`(design, args, i)`, whose random numbers come from
//! `RandomStream::for_sample(S, i, method)` alone; it is simulated for
//! `--revolutions` (default 2) and the per-period statistics of its revolution 2 (cycle
//! II; revolution 1 in a reduced study of one revolution), the columns of `camsim run`'s
//! table, make one [`SampleRecord`], which is added to the study's streamed statistics
//! ([`StudyStats`], `crate::stats::study`) and dropped: memory does not grow with the
//! samples. Every statistic is order-independent (exact sums, integer counts, fixed
//! histogram bins), so the [`Summary`] is the same bit for bit for any `--threads`, any
//! order the samples finish in, and any split into shards (`--shard K/N`, then
//! `camsim montecarlo merge`).
//!
//! Shards are strided: shard `K` of `N` runs the samples `i ≡ K − 1 (mod N)`. Every
//! shard then sees the whole seed range and finishes in about the same time; a shard
//! file (JSON, written atomically through [`crate::output`]) holds the study's settings
//! and the statistics of the shard's samples, and the merge checks that the files belong
//! to one study and are every shard K of one N exactly once before it adds them up.
//!
//! Statistics of a column over the samples ([`Moments`], `crate::stats::stream`): the
//! mean (the exact sum rounded once, over n), the sample standard deviation (n − 1; the
//! exact Σ(x − mean)², rounded once), the minimum and maximum, and the 5th, 50th and
//! 95th percentiles by linear interpolation between order statistics at rank
//! `(n − 1)p` (Hyndman and Fan's type 7), each order statistic read from a histogram
//! bin of 2⁻¹⁰ relative width (within 0.098 % of its value; exact while a bin holds at
//! most two samples). The probability of a jump is the fraction of samples with a
//! separation in the period (or anywhere in revolution 2) with its 95 % Wilson
//! interval. A non-finite statistic anywhere is an error, never a result.
//!
//! A two-level study (`--two-level n`, [`Study::two_level`]) runs every cam on the reduced
//! model of the design searches ([`monte_carlo_model`]) and samples 0 to n − 1 on the full
//! scene as well; the pairs' counts and exact sums ([`TwoLevelStats`],
//! `crate::stats::two_level`, docs/MODEL.md §9.7) travel beside the reduced statistics in the
//! shard file and give the full model's estimate with its interval, bit for bit the same for
//! any threads or shards.
//!
//! The parts: the study and its samples (here), the statistics (`crate::stats`), the
//! study measured from its [`Spec`] or merged from its shards ([`measure()`], [`merge()`]), the shard
//! files and their merge ([`shard`]) and the printed report ([`report`]); the
//! histograms are [`crate::plot::montecarlo`], the command line `crate::cmd::montecarlo`.

use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use anyhow::{anyhow, Result};
use camsim_core::{jump_verdict, DriveLaw, FollowerModel, JumpWatch, Observer, Sample};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::actual::{self, Cams};
use crate::args::spec_from;
use crate::args::StudyArgs;
use crate::sim::{self, PeriodRow, RunSpec};

pub mod measure;
pub mod report;
pub mod shard;

pub use crate::stats::stream::Moments;
pub use crate::stats::study::{
    revolution_value, summarize, Columns, PeriodSummary, StudyStats, Summary, REVOLUTION_COLUMNS,
};
pub use crate::stats::two_level::{TwoLevelStats, TwoLevelSummary};
pub use crate::stats::Probability;
pub use measure::{measure, merge, Measured, MonteCarloOutcome, Spec};
pub use report::{MonteCarloReport, ShardReport, Timing};
pub use shard::{read_shard, ShardFile};

/// The revolution whose statistics a study keeps (the thesis's cycle II, steady state),
/// unless it simulates only one (`--revolutions 1`, a reduced study: revolution 1).
pub const REVOLUTION: u32 = 2;

/// The revolution a study of `revolutions` revolutions measures: 2, or 1 if it runs one.
pub fn measured_revolution(revolutions: u32) -> u32 {
    revolutions.clamp(1, REVOLUTION)
}

/// The shard file's `format` tag.
pub const SHARD_FORMAT: &str = "camsim-montecarlo-shard";
/// The shard file's format version.
pub const SHARD_VERSION: u32 = 5;

/// Shard `index` (from 1) of `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// K, from 1.
    pub index: u64,
    /// N.
    pub count: u64,
}

impl Shard {
    /// The whole study as one shard.
    pub const WHOLE: Shard = Shard { index: 1, count: 1 };

    /// The sample indices of this shard among `samples`: K − 1, K − 1 + N, ...
    pub fn indices(self, samples: u64) -> impl Iterator<Item = u64> {
        (self.index - 1..samples).step_by(self.count as usize)
    }

    /// How many of `samples` this shard holds.
    pub fn len(self, samples: u64) -> u64 {
        samples
            .saturating_sub(self.index - 1)
            .div_ceil(self.count.max(1))
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// `--shard K/N`: 1 ≤ K ≤ N.
pub fn parse_shard(s: &str) -> Result<Shard, String> {
    let (k, n) = s
        .split_once('/')
        .ok_or_else(|| "must be K/N (shard K of N, K from 1)".to_string())?;
    let k: u64 = k.trim().parse().map_err(|_| "K must be a whole number")?;
    let n: u64 = n.trim().parse().map_err(|_| "N must be a whole number")?;
    if n == 0 || k == 0 || k > n || n > 1_000_000 {
        return Err("must be K/N with 1 <= K <= N <= 1000000".into());
    }
    Ok(Shard { index: k, count: n })
}

/// The columns of a per-period record (those of `camsim run`'s table), in order.
pub const COLUMNS: [&str; 13] = [
    "rms_displacement",
    "rms_velocity",
    "rms_acceleration",
    "torque_avg",
    "torque_max",
    "torque_min",
    "contact_force_min",
    "contact_force_max",
    "contact_force_avg",
    "contact_stress_max",
    "aord_motor",
    "aord_coupling",
    "aord_cam",
];

/// One period of one sample's revolution 2: the run table's columns and the jump flag.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PeriodValues {
    /// Period name.
    pub period: String,
    /// The [`COLUMNS`], in order.
    pub values: [f64; COLUMNS.len()],
    /// Whether the follower separated in this period.
    pub jump: bool,
}

impl PeriodValues {
    /// The record of a row of `camsim run`'s table.
    pub fn of(r: &PeriodRow) -> Self {
        PeriodValues {
            period: r.period.to_string(),
            values: [
                r.rms_displacement,
                r.rms_velocity,
                r.rms_acceleration,
                r.torque_avg,
                r.torque_max,
                r.torque_min,
                r.contact_force_min,
                r.contact_force_max,
                r.contact_force_avg,
                r.contact_stress_max,
                r.aord_motor,
                r.aord_coupling,
                r.aord_cam,
            ],
            jump: r.jump,
        }
    }

    /// The value of column `name` (one of [`COLUMNS`]).
    pub fn get(&self, name: &str) -> Option<f64> {
        COLUMNS
            .iter()
            .position(|c| *c == name)
            .and_then(|i| self.values.get(i).copied())
    }
}

/// Everything a study keeps of one sample.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SampleRecord {
    /// The sample index i (its profile comes from the master seed and i alone).
    pub index: u64,
    /// Waviness frequency per revolution of its profile.
    pub fpr: usize,
    /// RMS lift deviation of its profile, in.
    pub rms_deviation_in: f64,
    /// Revolution 2, period by period.
    pub periods: Vec<PeriodValues>,
    /// Accepted solver steps of the whole run.
    pub steps: u32,
}

impl SampleRecord {
    /// Whether the follower separated anywhere in revolution 2.
    pub fn jump(&self) -> bool {
        self.periods.iter().any(|p| p.jump)
    }
}

/// A sample whose run left the model's valid range (docs/MODEL.md §3.20): no record.
#[derive(Clone, Debug, PartialEq)]
pub struct LeftRange {
    /// Whether the follower had separated first (then the sample is a jump, the rule of
    /// `camsim jump-speed` and the sweeps); otherwise it is not workable.
    pub separated: bool,
    /// The run's error.
    pub reason: String,
}

/// What a sample's run gave: its record, or how it left the model's range.
pub type Outcome = std::result::Result<SampleRecord, LeftRange>;

/// Core's jump rule's watch, fed every solver sample of a run.
struct Separation(JumpWatch<f64>);

impl Observer<f64> for Separation {
    fn observe(&mut self, s: &Sample<f64>) -> ControlFlow<()> {
        let _ = self.0.note_sample(s);
        ControlFlow::Continue(())
    }
}

/// The settings that make two runs the same study (a shard file carries them; the
/// merge refuses files whose settings differ in anything).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudySettings {
    /// The camsim version that ran it.
    pub camsim_version: String,
    /// Number of samples of the whole study.
    pub samples: u64,
    /// Master seed.
    pub seed: u64,
    /// Revolutions simulated (the statistics are revolution 2's).
    pub revolutions: u32,
    /// The scene as a complete scene file (design, solver, DOFs).
    pub scene: String,
    /// How the actual cams are made.
    pub profile: ProfileSettings,
    /// The two-level estimate's levels (absent: every cam on the one model of `scene`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub two_level: Option<TwoLevelSettings>,
    /// Why a study without `--follower` or `--two-level` runs one model rather than the
    /// default two-level estimate ([`Study::default_levels`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub one_model: Option<String>,
}

/// The levels of a two-level study (`--two-level n`): every cam on the reduced scene,
/// the first n on the full one (`scene`) as well.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TwoLevelSettings {
    /// n: the cams (samples 0 to n − 1) that run on the full model too.
    pub full_samples: u64,
    /// The reduced scene every cam runs on, as a complete scene file.
    pub reduced_scene: String,
}

/// How a study's actual cams are made.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProfileSettings {
    /// `thesis` or `envelope`.
    pub method: String,
    /// `sum12` or `polar`.
    pub normal: String,
    /// Cam profile tolerance, ± in.
    pub cam_tolerance_in: f64,
    /// Roller radius tolerance, ± in.
    pub roller_tolerance_in: f64,
    /// Eccentricity tolerance, ± in.
    pub eccentricity_tolerance_in: f64,
    /// Profile points per revolution.
    pub intervals: usize,
    /// `given` (--interval-deg), `criteria` (IV.2.3's three, on the master seed) or
    /// `waviness FPR n (master seed's profile FPR m)` (--waviness-fpr).
    pub interval_source: String,
}

impl ProfileSettings {
    /// How `actual`'s cams are made, with the interval chosen for them
    /// ([`actual::intervals_for`]).
    pub fn of(actual: &Cams, interval: (usize, actual::IntervalSource)) -> Result<Self> {
        let tol = actual.tolerances()?;
        Ok(ProfileSettings {
            method: actual.profile_method.name().into(),
            normal: actual.normal.name().into(),
            cam_tolerance_in: tol.cam,
            roller_tolerance_in: tol.roller,
            eccentricity_tolerance_in: tol.eccentricity,
            intervals: interval.0,
            interval_source: interval.1.label(),
        })
    }
}

/// The fewest full-model cams of a default two-level study.
pub const MIN_FULL_SAMPLES: u64 = 30;

/// The default subsample of a two-level study of `samples` cams (docs/MODEL.md §9.7):
/// a tenth of the cams, at least [`MIN_FULL_SAMPLES`], at most all of them.
pub fn default_full_samples(samples: u64) -> u64 {
    samples.div_ceil(10).max(MIN_FULL_SAMPLES).min(samples)
}

/// A study ready to run: the scene, and the actual-cam options with the interval
/// fixed once (so no sample repeats the interval choice).
#[derive(Clone, Debug)]
pub struct Study {
    /// The scene (its `profile` is set per sample).
    pub spec: RunSpec,
    /// The actual-cam options, the interval resolved (`resolved` set).
    pub actual: Cams,
    /// What identifies the study.
    pub settings: StudySettings,
    /// The reduced scene of a two-level study (`spec` is then its full one).
    pub reduced: Option<RunSpec>,
}

/// What a study adds up: the statistics of the cams on the study's first model (the
/// reduced one of a two-level study) and those of the full-model subsample (empty in a
/// study of one model).
#[derive(Clone, Debug, Default)]
pub struct Tally {
    /// Every cam.
    pub stats: StudyStats,
    /// The subsample's pairs.
    pub two_level: TwoLevelStats,
}

impl Tally {
    fn merge(&mut self, other: &Tally) -> Result<()> {
        self.stats.merge(&other.stats)?;
        self.two_level.merge(&other.two_level)
    }

    /// Adds cam `index`'s outcome on the first model and, in the subsample, on the full.
    fn add(&mut self, index: u64, rec: &Outcome, full: Option<Outcome>) -> Result<()> {
        if let Some(f) = &full {
            self.two_level.add_outcomes(index, rec, f)?;
        }
        match rec {
            Ok(r) => self.stats.add(r),
            Err(l) => {
                self.stats.add_left_range(index, l.separated, &l.reason);
                Ok(())
            }
        }
    }
}

impl Study {
    /// The study `args` describe (scene loaded and checked, interval chosen).
    pub fn new(args: &StudyArgs) -> Result<Self> {
        let samples = args
            .samples
            .ok_or_else(|| anyhow!("--samples N is required"))?;
        let mut spec = spec_from(&args.scene)?;
        spec.revolutions = args.revolutions.unwrap_or(REVOLUTION);
        if args.vertical {
            spec.dofs.horizontal = false;
        }
        if args.constant_cam_speed {
            spec.design.drive = DriveLaw::ConstantCamSpeed;
        }
        Self::from_spec(spec, &args.actual.cams(), samples)
    }

    /// A study of `samples` actual cams made by `actual` on the scene `spec`.
    pub fn from_spec(spec: RunSpec, actual: &Cams, samples: u64) -> Result<Self> {
        anyhow::ensure!(
            spec.revolutions >= 1,
            "a study needs at least one revolution"
        );
        anyhow::ensure!(samples >= 1, "--samples must be at least 1");
        let (intervals, source) = actual::intervals_for(&spec.design, actual)?;
        let profile = ProfileSettings::of(actual, (intervals, source))?;
        let mut fixed = actual.clone();
        fixed.actual = true;
        fixed.resolved = Some((intervals, source));
        let settings = StudySettings {
            camsim_version: env!("CARGO_PKG_VERSION").to_string(),
            samples,
            seed: actual.seed(),
            revolutions: spec.revolutions,
            scene: crate::scene::spec_text(&spec)?,
            profile,
            two_level: None,
            one_model: None,
        };
        Ok(Study {
            spec,
            actual: fixed,
            settings,
            reduced: None,
        })
    }

    /// The two-level study of this one (`--two-level n`): every cam on the Monte Carlo
    /// model of the design searches ([`monte_carlo_model`]), samples 0 to n − 1 on this
    /// study's full scene as well.
    pub fn two_level(mut self, n: u64) -> Result<Self> {
        let samples = self.settings.samples;
        anyhow::ensure!(
            self.spec.dofs.follower == FollowerModel::Full,
            "--two-level {n}: the scene's follower is {}: the two-level estimate pairs the full follower with a reduced one (drop --follower, or the scene's run.follower)",
            self.spec.dofs.follower.name()
        );
        anyhow::ensure!(
            matches!(self.spec.design.drive, DriveLaw::Regulated { .. }),
            "--two-level {n}: the reduced followers are built for the regulated drive only (drop --constant-cam-speed, or the scene's constant drive)"
        );
        anyhow::ensure!(
            (2..=samples).contains(&n),
            "--two-level {n}: the full-model cams must be at least 2 and at most --samples ({samples})"
        );
        let reduced = monte_carlo_model(&self.spec);
        self.settings.two_level = Some(TwoLevelSettings {
            full_samples: n,
            reduced_scene: crate::scene::spec_text(&reduced)?,
        });
        self.reduced = Some(reduced);
        Ok(self)
    }

    /// The study montecarlo runs when neither `--follower` nor `--two-level` is given:
    /// the two-level estimate with [`default_full_samples`] cams on the full model, or,
    /// where it cannot run, the scene's one model with the reason in `one_model`.
    pub fn default_levels(mut self) -> Result<Self> {
        let samples = self.settings.samples;
        let why = if self.spec.dofs.follower != FollowerModel::Full {
            format!(
                "the scene's run.follower ({})",
                self.spec.dofs.follower.name()
            )
        } else if !matches!(self.spec.design.drive, DriveLaw::Regulated { .. }) {
            "the full model alone: the reduced followers need the regulated drive (constant cam speed given)".to_string()
        } else if samples < 2 {
            "the full model alone: the two-level estimate needs at least 2 cams".to_string()
        } else {
            return self.two_level(default_full_samples(samples));
        };
        self.settings.one_model = Some(why);
        Ok(self)
    }

    /// n of a two-level study (0 in a study of one model).
    pub fn full_samples(&self) -> u64 {
        self.settings
            .two_level
            .as_ref()
            .map_or(0, |t| t.full_samples)
    }

    /// The revolution the study measures ([`measured_revolution`]).
    pub fn revolution(&self) -> u32 {
        measured_revolution(self.spec.revolutions)
    }

    /// Runs sample `index` on the study's first model (the reduced one of a two-level
    /// study): its profile, its simulation, its record of the measured revolution.
    /// A run that leaves the model's valid range is an error here.
    pub fn sample(&self, index: u64) -> Result<SampleRecord> {
        self.pair(index)?.0.map_err(|l| anyhow!(l.reason))
    }

    /// Runs sample `index` on the first model and, if it is in a two-level study's
    /// subsample and workable there, on the full model too (the same actual cam). A run
    /// that leaves a model's valid range is an outcome, not an error (the counting rule
    /// of docs/MODEL.md §3.20 applies to both models).
    pub fn pair(&self, index: u64) -> Result<(Outcome, Option<Outcome>)> {
        let (dev, stats) = actual::build_profile(&self.spec.design, &self.actual, index)?;
        let dev = Arc::new(dev);
        let first = self.reduced.as_ref().unwrap_or(&self.spec);
        let rec = self.record(first, &dev, &stats, index)?;
        // A cam not workable on the first model is out of the study: no pair.
        let not_workable = matches!(&rec, Err(l) if !l.separated);
        if index >= self.full_samples() || not_workable {
            return Ok((rec, None));
        }
        let full = self
            .record(&self.spec, &dev, &stats, index)
            .map_err(|e| e.context("on the full model"))?;
        Ok((rec, Some(full)))
    }

    /// The record of sample `index`'s cam `dev` simulated on `spec`.
    fn record(
        &self,
        spec: &RunSpec,
        dev: &Arc<sim::HostDeviation>,
        stats: &actual::ProfileStats,
        index: u64,
    ) -> Result<Outcome> {
        let rev = self.revolution();
        let mut spec = spec.clone();
        spec.profile = Some(Arc::clone(dev));
        let mut watch = Separation(JumpWatch::new());
        let r = match sim::run(&spec, &mut watch) {
            Ok(r) => r,
            Err(e) => {
                // Core's rule: a failure after a separation is a jump; leaving the
                // range with the follower on the cam is not workable; anything else
                // is an error.
                let separated = jump_verdict::<(), (), f64>(Err(()), &watch.0).is_ok();
                if !separated && !crate::study::sweep::out_of_model(&e) {
                    return Err(e);
                }
                let reason = format!("{e:#}");
                return Ok(Err(LeftRange { separated, reason }));
            }
        };
        let periods: Vec<PeriodValues> = sim::period_rows(&spec.design, &r.stats)
            .iter()
            .filter(|p| p.revolution == rev)
            .map(PeriodValues::of)
            .collect();
        let names = sim::period_names(&spec.design);
        anyhow::ensure!(
            periods.len() == names.len(),
            "revolution {rev} has {} of the program's {} periods",
            periods.len(),
            names.len()
        );
        for p in &periods {
            for (c, v) in COLUMNS.iter().zip(p.values) {
                anyhow::ensure!(v.is_finite(), "{}.{c} is {v}", p.period);
            }
        }
        anyhow::ensure!(
            stats.rms_deviation_in.is_finite(),
            "profile RMS deviation is not finite"
        );
        Ok(Ok(SampleRecord {
            index,
            fpr: stats.fpr,
            rms_deviation_in: stats.rms_deviation_in,
            periods,
            steps: r.solver.accepted,
        }))
    }

    /// Runs the samples `indices` on a local pool of `threads` threads, with a progress
    /// bar on a terminal (`progress`), and returns their records in the order of
    /// `indices`. The first failure stops the samples not yet started; the error names
    /// the lowest failing index among those that ran.
    pub fn run(
        &self,
        indices: &[u64],
        threads: usize,
        progress: bool,
    ) -> Result<Vec<SampleRecord>> {
        let pool = super::pool(threads)?;
        let bar = crate::study_limits::progress_bar(
            indices.len() as u64,
            progress,
            "{elapsed_precise} [{bar:40}] {pos}/{len} samples, {per_sec}, eta {eta}",
        );
        let lines = crate::study_limits::ProgressLines::new(
            "camsim montecarlo",
            indices.len() as u64,
            progress && crate::study_limits::ProgressLines::batch(),
        );
        let stop = AtomicBool::new(false);
        let results: Vec<Option<Result<SampleRecord>>> = pool.install(|| {
            indices
                .par_iter()
                .map(|&i| {
                    if stop.load(Ordering::Relaxed) {
                        return None;
                    }
                    let r = self.sample(i);
                    if r.is_err() {
                        stop.store(true, Ordering::Relaxed);
                    }
                    bar.inc(1);
                    lines.inc();
                    Some(r)
                })
                .collect()
        });
        bar.finish_and_clear();
        let mut out = Vec::with_capacity(results.len());
        for (i, r) in indices.iter().zip(results) {
            match r {
                Some(Ok(rec)) => out.push(rec),
                Some(Err(e)) => {
                    return Err(
                        e.context(format!("sample {i} (seed {}) failed", self.settings.seed))
                    )
                }
                None => {}
            }
        }
        // Every sample ran (no failure stopped any).
        anyhow::ensure!(out.len() == indices.len(), "a sample failed");
        Ok(out)
    }

    /// Runs the samples of `shard` on a local pool of `threads` threads, with progress
    /// (`progress`: a bar on a terminal, lines otherwise), and returns their statistics:
    /// each record is added to a thread's [`StudyStats`] and dropped, so memory does not
    /// grow with the samples, and the result does not depend on the threads. The first
    /// failure stops the samples not yet started; the error names the lowest failing
    /// index among those that ran.
    pub fn run_stats(&self, shard: Shard, threads: usize, progress: bool) -> Result<StudyStats> {
        Ok(self.run_tally(shard, threads, progress)?.stats)
    }

    /// [`Study::run_stats`] with the full-model subsample's pairs of a two-level study.
    pub fn run_tally(&self, shard: Shard, threads: usize, progress: bool) -> Result<Tally> {
        let pool = super::pool(threads)?;
        let count = shard.len(self.settings.samples);
        let bar = crate::study_limits::progress_bar(
            count,
            progress,
            "{elapsed_precise} [{bar:40}] {pos}/{len} samples, {per_sec}, eta {eta}",
        );
        let lines = crate::study_limits::ProgressLines::new(
            "camsim montecarlo",
            count,
            progress && crate::study_limits::ProgressLines::batch(),
        );
        let stop = AtomicBool::new(false);
        type Part = (Tally, Option<(u64, anyhow::Error)>);
        fn lowest(
            a: Option<(u64, anyhow::Error)>,
            b: Option<(u64, anyhow::Error)>,
        ) -> Option<(u64, anyhow::Error)> {
            match (a, b) {
                (Some(x), Some(y)) => Some(if y.0 < x.0 { y } else { x }),
                (x, y) => x.or(y),
            }
        }
        let (tally, err): Part = pool.install(|| {
            use rayon::iter::IntoParallelIterator;
            (0..count)
                .into_par_iter()
                .map(|j| shard.index - 1 + j * shard.count)
                .fold(
                    || (Tally::default(), None),
                    |(mut acc, err): Part, i| {
                        if stop.load(Ordering::Relaxed) {
                            return (acc, err);
                        }
                        let r = self.pair(i).and_then(|(rec, full)| acc.add(i, &rec, full));
                        bar.inc(1);
                        lines.inc();
                        match r {
                            Ok(()) => (acc, err),
                            Err(e) => {
                                stop.store(true, Ordering::Relaxed);
                                (acc, lowest(err, Some((i, e))))
                            }
                        }
                    },
                )
                .reduce(
                    || (Tally::default(), None),
                    |(mut a, ea): Part, (b, eb): Part| {
                        let e = match a.merge(&b) {
                            Ok(()) => None,
                            Err(e) => Some((u64::MAX, e)),
                        };
                        (a, lowest(lowest(ea, eb), e))
                    },
                )
        });
        bar.finish_and_clear();
        if let Some((i, e)) = err {
            return Err(e.context(format!("sample {i} (seed {}) failed", self.settings.seed)));
        }
        anyhow::ensure!(
            tally.stats.accounted() == count
                && tally
                    .two_level
                    .check(shard.len(self.full_samples()))
                    .is_ok(),
            "a sample failed"
        );
        Ok(tally)
    }
}

/// The Monte Carlo model of the design searches: the quasi-static cantilever, vertical
/// (docs/RESULTS.md "Reduced scenes": adequate for P(jump) on actual cams), at rtol 1e-4.
pub fn monte_carlo_model(spec: &RunSpec) -> RunSpec {
    let mut mc = spec.clone();
    mc.dofs.horizontal = false;
    mc.dofs.follower = FollowerModel::QuasiStaticCantilever;
    mc.solver.rtol = 1e-4;
    mc.solver.atol = 1e-8;
    mc.solver.max_step_fraction = 0.01;
    mc
}

/// The worker threads: `--threads`, or every core.
pub fn threads(arg: Option<u32>) -> usize {
    arg.map(|t| t as usize).unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    })
}
