//! `camsim montecarlo`: many actual cams, in parallel, reproducible bit for bit.
//!
//! Sample `i` of a study with master seed `S` is the actual cam of
//! [`crate::actual::build_profile`]`(design, args, i)`, whose random numbers come from
//! `RandomStream::for_sample(S, i, method)` alone; it is simulated for
//! `--revolutions` (default 2) and the per-period statistics of its revolution 2 (cycle
//! II; revolution 1 in a reduced study of one revolution), the columns of `camsim run`'s
//! table, are kept as one [`SampleRecord`]. The records
//! are collected by index and reduced in index order (never in the order the threads
//! finish), so the [`Summary`] is the same bit for bit for any `--threads`, and for any
//! split into shards (`--shard K/N`, then `camsim montecarlo merge`).
//!
//! Shards are strided: shard `K` of `N` runs the samples `i ≡ K − 1 (mod N)`. Every
//! shard then sees the whole seed range and finishes in about the same time; a shard
//! file (JSON, written atomically through [`crate::output`]) holds the study's settings
//! and every record of the shard, and the merge checks that the files belong to one
//! study and cover every sample exactly once before it reduces them with the same code
//! as a single-machine run.
//!
//! Statistics of a column over the samples ([`Moments`]): the mean (sum in index
//! order over n), the sample standard deviation (n − 1, two passes), the minimum and
//! maximum, and the 5th, 50th and 95th percentiles by linear interpolation between
//! order statistics at rank `(n − 1)p` (Hyndman and Fan's type 7). The probability
//! of a jump is the fraction of samples with a separation in the period (or anywhere
//! in revolution 2) and its binomial standard error `√(p(1 − p)/n)`. A non-finite
//! statistic anywhere is an error, never a result.

use std::collections::BTreeMap;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use anyhow::{anyhow, bail, Context, Result};
use camsim_core::DriveLaw;
use rayon::prelude::*;
use serde::{Deserialize, Serialize, Serializer};

use crate::actual::{self, ActualArgs};
use crate::cmd::run::{spec_from, SceneArgs};
use crate::output::{AtomicDir, Plan};
use crate::report::Report;
use crate::sim::{self, Nothing, PeriodRow, RunSpec};

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
pub const SHARD_VERSION: u32 = 2;

/// Command-line options of `camsim montecarlo`.
#[derive(clap::Args, Debug, Clone)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct Args {
    /// `merge FILES...`: merge shard files into the study's result.
    #[command(subcommand)]
    pub merge: Option<Sub>,
    /// The study.
    #[command(flatten)]
    pub study: StudyArgs,
    /// Worker threads (default: every core). The result does not depend on it.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// Run only shard K of N (K from 1): the samples i with i mod N = K - 1. Needs --out.
    #[arg(long, value_name = "K/N", value_parser = parse_shard, requires = "out")]
    pub shard: Option<Shard>,
    /// Write every sample's record to FILE (JSON; the shard file `merge` reads).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Run a study past the limits of memory (4 GB of records, 4 million samples) and
    /// estimated time (24 h) that otherwise refuse it (`camsim::study_limits`).
    #[arg(long)]
    pub allow_long: bool,
    /// Common output options.
    #[command(flatten)]
    pub output: OutputArgs,
}

/// `camsim montecarlo merge`.
#[derive(clap::Subcommand, Debug, Clone)]
pub enum Sub {
    /// Merge the shard files of one study (every sample exactly once); the result is
    /// the single-machine run's, bit for bit.
    Merge(MergeArgs),
}

/// Command-line options of `camsim montecarlo merge`.
#[derive(clap::Args, Debug, Clone)]
pub struct MergeArgs {
    /// The shard files (`camsim montecarlo --shard K/N --out FILE`).
    #[arg(required = true, value_name = "FILES")]
    pub files: Vec<PathBuf>,
    /// Common output options.
    #[command(flatten)]
    pub output: OutputArgs,
}

/// What a study prints and draws.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct OutputArgs {
    /// Print JSON instead of tables.
    #[arg(long)]
    pub json: bool,
    /// Write histogram plots (PNG) into DIR (created if missing; existing plots need
    /// --force).
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
    /// Replace existing --out and --plot files.
    #[arg(long)]
    pub force: bool,
}

/// What a study is: the scene, the reduced-model options and the actual cam.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct StudyArgs {
    /// Number of actual cams.
    #[arg(long, required = true, value_parser = clap::value_parser!(u64).range(1..=100_000_000))]
    pub samples: Option<u64>,
    /// The scene and its overrides.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Revolutions to simulate, 1-16 (default 2: the statistics are revolution 2's;
    /// with 1, a reduced study, revolution 1's: give it --start static).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16))]
    pub revolutions: Option<u32>,
    /// Reduced model: drop the horizontal motion (x1, x2, x3).
    #[arg(long)]
    pub vertical: bool,
    /// Reduced model: an ideal constant cam speed (no motor, coupling or cam rotation).
    #[arg(long)]
    pub constant_cam_speed: bool,
    /// The actual cam (--actual is implied).
    #[command(flatten)]
    pub actual: ActualArgs,
}

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

/// A study ready to run: the scene, and the actual-cam options with the interval
/// fixed once (so no sample repeats the interval choice).
#[derive(Clone, Debug)]
pub struct Study {
    /// The scene (its `profile` is set per sample).
    pub spec: RunSpec,
    /// The actual-cam options, the interval resolved (`resolved` set).
    pub actual: ActualArgs,
    /// What identifies the study.
    pub settings: StudySettings,
}

fn value_name<V: clap::ValueEnum>(v: &V) -> String {
    v.to_possible_value()
        .map(|p| p.get_name().to_string())
        .unwrap_or_default()
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
        Self::from_spec(spec, &args.actual, samples)
    }

    /// A study of `samples` actual cams made by `actual` on the scene `spec`.
    pub fn from_spec(spec: RunSpec, actual: &ActualArgs, samples: u64) -> Result<Self> {
        anyhow::ensure!(
            spec.revolutions >= 1,
            "a study needs at least one revolution"
        );
        anyhow::ensure!(samples >= 1, "--samples must be at least 1");
        let tol = actual.tolerances()?;
        let (intervals, source) = actual::intervals_for(&spec.design, actual)?;
        let mut fixed = actual.clone();
        fixed.actual = true;
        fixed.resolved = Some((intervals, source));
        let settings = StudySettings {
            camsim_version: env!("CARGO_PKG_VERSION").to_string(),
            samples,
            seed: actual.seed(),
            revolutions: spec.revolutions,
            scene: crate::scene::spec_text(&spec)?,
            profile: ProfileSettings {
                method: value_name(&actual.profile_method),
                normal: value_name(&actual.normal),
                cam_tolerance_in: tol.cam,
                roller_tolerance_in: tol.roller,
                eccentricity_tolerance_in: tol.eccentricity,
                intervals,
                interval_source: source.label(),
            },
        };
        Ok(Study {
            spec,
            actual: fixed,
            settings,
        })
    }

    /// The revolution the study measures ([`measured_revolution`]).
    pub fn revolution(&self) -> u32 {
        measured_revolution(self.spec.revolutions)
    }

    /// Runs sample `index`: its profile, its simulation, its record of the measured
    /// revolution.
    pub fn sample(&self, index: u64) -> Result<SampleRecord> {
        let rev = self.revolution();
        let (dev, stats) = actual::build_profile(&self.spec.design, &self.actual, index)?;
        let mut spec = self.spec.clone();
        spec.profile = Some(Arc::new(dev));
        let r = sim::run(&spec, &mut Nothing)?;
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
        Ok(SampleRecord {
            index,
            fpr: stats.fpr,
            rms_deviation_in: stats.rms_deviation_in,
            periods,
            steps: r.solver.accepted,
        })
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
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads.max(1))
            // A profile (three arrays of 3601 f64) is built on the stack.
            .stack_size(16 << 20)
            .build()
            .context("cannot start the worker threads")?;
        let bar = progress_bar(indices.len() as u64, progress);
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
}

/// A progress bar on standard error when it is a terminal and `want`, hidden otherwise.
fn progress_bar(len: u64, want: bool) -> indicatif::ProgressBar {
    progress_bar_of(len, want, "samples")
}

/// A progress bar of `len` items called `unit` on standard error when it is a terminal
/// and `want`, hidden otherwise (the studies and the design searches share it).
pub fn progress_bar_of(len: u64, want: bool, unit: &str) -> indicatif::ProgressBar {
    use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
    if !want || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
    if let Ok(style) = ProgressStyle::with_template(&format!(
        "{{elapsed_precise}} [{{bar:40}}] {{pos}}/{{len}} {unit}, {{per_sec}}, eta {{eta}}"
    )) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar
}

/// Mean, standard deviation and percentiles of one statistic over the samples.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Moments {
    /// Mean.
    pub mean: f64,
    /// Sample standard deviation (n − 1; 0 for one sample).
    pub sd: f64,
    /// 5th percentile.
    pub p5: f64,
    /// Median.
    pub p50: f64,
    /// 95th percentile.
    pub p95: f64,
    /// Smallest.
    pub min: f64,
    /// Largest.
    pub max: f64,
}

/// The percentile `p` (0..1) of sorted values: linear between the order statistics
/// at rank `(n − 1)p` (type 7).
fn percentile(sorted: &[f64], p: f64) -> f64 {
    let n = sorted.len();
    if n == 0 {
        return f64::NAN;
    }
    let h = (n - 1) as f64 * p;
    let lo = h.floor() as usize;
    let hi = (lo + 1).min(n - 1);
    let (a, b) = (sorted[lo], sorted[hi]);
    a + (h - lo as f64) * (b - a)
}

impl Moments {
    /// The moments of `values` (in index order; at least one, all finite).
    pub fn of(what: &str, values: &[f64]) -> Result<Self> {
        anyhow::ensure!(!values.is_empty(), "{what}: no samples");
        if let Some(v) = values.iter().find(|v| !v.is_finite()) {
            bail!("{what}: a sample is {v}");
        }
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        let sd = if values.len() > 1 {
            (values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0)).sqrt()
        } else {
            0.0
        };
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        let m = Moments {
            mean,
            sd,
            p5: percentile(&sorted, 0.05),
            p50: percentile(&sorted, 0.50),
            p95: percentile(&sorted, 0.95),
            min: sorted[0],
            max: sorted[sorted.len() - 1],
        };
        for (k, v) in [
            ("mean", m.mean),
            ("sd", m.sd),
            ("p5", m.p5),
            ("p50", m.p50),
            ("p95", m.p95),
        ] {
            anyhow::ensure!(v.is_finite(), "{what}: the {k} is {v}");
        }
        Ok(m)
    }
}

pub use crate::stats::Probability;

/// Named statistics in a fixed order (a JSON object in that order).
#[derive(Clone, Debug, PartialEq)]
pub struct Columns(pub Vec<(String, Moments)>);

impl Serialize for Columns {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(self.0.len()))?;
        for (k, v) in &self.0 {
            m.serialize_entry(k, v)?;
        }
        m.end()
    }
}

impl Columns {
    /// The statistics of `name`, if present.
    pub fn get(&self, name: &str) -> Option<&Moments> {
        self.0.iter().find(|(k, _)| k == name).map(|(_, m)| m)
    }
}

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
fn revolution_value(r: &SampleRecord, name: &str) -> f64 {
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
    /// Accepted solver steps per sample.
    pub steps: Moments,
}

/// Reduces records of `revolution` (sorted by index, every index of the study once)
/// in index order.
pub fn summarize(records: &[SampleRecord], revolution: u32) -> Result<Summary> {
    let first = records
        .first()
        .ok_or_else(|| anyhow!("no samples to summarize"))?;
    let n = records.len() as u64;
    let names: Vec<&str> = first.periods.iter().map(|p| p.period.as_str()).collect();
    for r in records {
        let theirs: Vec<&str> = r.periods.iter().map(|p| p.period.as_str()).collect();
        anyhow::ensure!(
            theirs == names,
            "sample {} has the periods {theirs:?}, sample {} {names:?}",
            r.index,
            first.index
        );
    }
    let mut periods = Vec::new();
    for (k, name) in names.iter().enumerate() {
        let mut columns = Vec::new();
        for (c, col) in COLUMNS.iter().enumerate() {
            let v: Vec<f64> = records.iter().map(|r| r.periods[k].values[c]).collect();
            columns.push((col.to_string(), Moments::of(&format!("{name}.{col}"), &v)?));
        }
        let jumps = records.iter().filter(|r| r.periods[k].jump).count() as u64;
        periods.push(PeriodSummary {
            period: name.to_string(),
            columns: Columns(columns),
            jump: Probability::of(jumps, n),
        });
    }
    let mut whole = Vec::new();
    for c in REVOLUTION_COLUMNS {
        let v: Vec<f64> = records.iter().map(|r| revolution_value(r, c)).collect();
        whole.push((c.to_string(), Moments::of(c, &v)?));
    }
    let fpr: Vec<f64> = records.iter().map(|r| r.fpr as f64).collect();
    let rms: Vec<f64> = records.iter().map(|r| r.rms_deviation_in).collect();
    let steps: Vec<f64> = records.iter().map(|r| f64::from(r.steps)).collect();
    Ok(Summary {
        samples: n,
        revolution,
        periods,
        whole_revolution: Columns(whole),
        jump: Probability::of(records.iter().filter(|r| r.jump()).count() as u64, n),
        profile: Columns(vec![
            ("fpr".into(), Moments::of("fpr", &fpr)?),
            (
                "rms_deviation_in".into(),
                Moments::of("rms_deviation_in", &rms)?,
            ),
        ]),
        steps: Moments::of("steps", &steps)?,
    })
}

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
    pub study: StudySettings,
    /// The result.
    pub summary: Summary,
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

/// A shard file: the study and the records of one shard.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShardFile {
    /// [`SHARD_FORMAT`].
    pub format: String,
    /// [`SHARD_VERSION`].
    pub version: u32,
    /// The study.
    pub study: StudySettings,
    /// Which shard.
    pub shard: Shard,
    /// Its records, by index.
    pub records: Vec<SampleRecord>,
    /// The content digest of everything above (`crate::shard::digest`; version 2 on).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub digest: String,
}

/// The worker threads: `--threads`, or every core.
pub fn threads(arg: Option<u32>) -> usize {
    arg.map(|t| t as usize).unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    })
}

/// The outcome of `camsim montecarlo`.
#[derive(Clone, Debug)]
pub enum Outcome {
    /// A whole study (or a merge).
    Study(Box<MonteCarloReport>),
    /// One shard written.
    Shard(ShardReport),
}

/// Runs what `args` ask for (a study, a shard or a merge) and writes its files.
pub fn execute(args: &Args) -> Result<Outcome> {
    if let Some(Sub::Merge(m)) = &args.merge {
        return merge(&m.files, &m.output).map(|r| Outcome::Study(Box::new(r)));
    }
    let study = Study::new(&args.study)?;
    let shard = args.shard.unwrap_or(Shard::WHOLE);
    let out = &args.output;
    // Every output checked before any sample runs.
    let mut plan = Plan::new(out.force);
    let out_target = match &args.out {
        Some(p) => Some(plan.file("--out", p)?),
        None => None,
    };
    let plot_target = match (&out.plot, args.shard) {
        (Some(_), Some(_)) => {
            bail!("--plot draws a whole study: give it to `merge`, not to a shard")
        }
        (Some(dir), None) => Some(plan.dir("--plot", dir, &PLOT_FILES)?),
        (None, _) => None,
    };
    // The output's temporary exists before the first sample: a name the file system
    // refuses fails now, not after the whole study.
    let mut out_file = match out_target {
        Some(t) => Some(t.open()?),
        None => None,
    };
    let threads = threads(args.threads);
    let indices: Vec<u64> = shard.indices(study.settings.samples).collect();
    // Memory before any sample, time from the first sample run alone (once more than
    // the study needs: a sample depends on its index only).
    crate::study_limits::check_memory(indices.len() as u64, args.allow_long)?;
    if let Some(&first) = indices.first() {
        let t = Instant::now();
        study.run(&[first], 1, false)?;
        crate::study_limits::check_time(
            t.elapsed().as_secs_f64(),
            indices.len() as u64,
            threads,
            args.allow_long,
        )?;
    }
    let t0 = Instant::now();
    let records = study.run(&indices, threads, true)?;
    let wall_s = t0.elapsed().as_secs_f64();
    let timing = Timing {
        threads,
        wall_s,
        samples_per_s: records.len() as f64 / wall_s,
        samples_per_s_per_thread: records.len() as f64 / wall_s / threads as f64,
    };
    let summary = if args.shard.is_none() {
        Some(summarize(&records, study.revolution())?)
    } else {
        None
    };
    let mut plots = match (plot_target, &summary) {
        (Some(t), Some(_)) => {
            let mut dir = t.open()?;
            draw(&mut dir, &records, study.revolution())?;
            Some(dir)
        }
        _ => None,
    };
    let n = records.len() as u64;
    if let Some(mut f) = out_file.take() {
        let mut file = ShardFile {
            format: SHARD_FORMAT.into(),
            version: SHARD_VERSION,
            study: study.settings.clone(),
            shard,
            records,
            digest: String::new(),
        };
        file.digest = crate::shard::digest(&file)?;
        serde_json::to_writer(&mut f, &file)?;
        f.write_all(b"\n")?;
        f.commit()?;
    }
    if let Some(p) = plots.take() {
        p.commit()?;
    }
    match summary {
        Some(summary) => Ok(Outcome::Study(Box::new(MonteCarloReport {
            study: study.settings,
            summary,
            timing: Some(timing),
        }))),
        None => Ok(Outcome::Shard(ShardReport {
            shard,
            samples: n,
            out: args.out.clone().unwrap_or_default(),
            timing,
        })),
    }
}

/// Reads one shard file.
pub fn read_shard(path: &Path) -> Result<ShardFile> {
    let text = camsim_scene_file::read_text(path, crate::shard::MAX_SHARD_BYTES, "the shard file")
        .map_err(anyhow::Error::msg)?;
    let value: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| anyhow!("{}: not JSON: {e}", path.display()))?;
    if value.get("format").and_then(|f| f.as_str()) != Some(SHARD_FORMAT) {
        bail!(
            "{}: not a camsim montecarlo shard file (no \"format\": \"{SHARD_FORMAT}\")",
            path.display()
        );
    }
    let version = value.get("version").and_then(|v| v.as_u64());
    if version != Some(u64::from(SHARD_VERSION)) {
        bail!(
            "{}: shard file version {} (this camsim reads version {SHARD_VERSION})",
            path.display(),
            version.map_or("missing".into(), |v| v.to_string())
        );
    }
    // Parsed from the text (not the Value) so that every number reads back bit for bit.
    let file: ShardFile = serde_json::from_str(&text)
        .map_err(|e| anyhow!("{}: bad shard file: {e}", path.display()))?;
    crate::shard::verify(path, &file)?;
    Ok(file)
}

/// The first difference between two studies' settings, in words.
fn settings_difference(a: &StudySettings, b: &StudySettings) -> String {
    if a.samples != b.samples {
        return format!("--samples {} vs {}", b.samples, a.samples);
    }
    if a.seed != b.seed {
        return format!("seed {} vs {}", b.seed, a.seed);
    }
    if a.camsim_version != b.camsim_version {
        return format!("camsim {} vs {}", b.camsim_version, a.camsim_version);
    }
    if a.revolutions != b.revolutions {
        return format!("--revolutions {} vs {}", b.revolutions, a.revolutions);
    }
    if a.profile != b.profile {
        return format!("profile {:?} vs {:?}", b.profile, a.profile);
    }
    if let Some((x, y)) = a.scene.lines().zip(b.scene.lines()).find(|(x, y)| x != y) {
        return format!("scene line `{}` vs `{}`", y.trim(), x.trim());
    }
    "scene".into()
}

/// Merges shard files into the result of their study (every sample exactly once).
pub fn merge(files: &[PathBuf], out: &OutputArgs) -> Result<MonteCarloReport> {
    let mut plan = Plan::new(out.force);
    let plot_target = match &out.plot {
        Some(dir) => Some(plan.dir("--plot", dir, &PLOT_FILES)?),
        None => None,
    };
    let first_path = files.first().ok_or_else(|| anyhow!("no shard files"))?;
    let mut study: Option<StudySettings> = None;
    // index -> the file that has it.
    let mut owner: BTreeMap<u64, usize> = BTreeMap::new();
    let mut records: Vec<SampleRecord> = Vec::new();
    let mut seen: Vec<PathBuf> = Vec::new();
    for (f, path) in files.iter().enumerate() {
        let canonical = std::fs::canonicalize(path).unwrap_or_else(|_| path.clone());
        if seen.contains(&canonical) {
            bail!("{} is given twice", path.display());
        }
        seen.push(canonical);
        let shard = read_shard(path)?;
        match &study {
            None => study = Some(shard.study.clone()),
            Some(s) if *s != shard.study => bail!(
                "{}: belongs to another study than {} ({})",
                path.display(),
                first_path.display(),
                settings_difference(s, &shard.study)
            ),
            Some(_) => {}
        }
        let n = shard.study.samples;
        for r in shard.records {
            anyhow::ensure!(
                r.index < n,
                "{}: sample {} is outside the study's 0..{n}",
                path.display(),
                r.index
            );
            if let Some(&other) = owner.get(&r.index) {
                bail!(
                    "sample {} is in {} and in {} (each sample must come from exactly one shard)",
                    r.index,
                    files[other].display(),
                    path.display()
                );
            }
            owner.insert(r.index, f);
            records.push(r);
        }
    }
    let study = study.ok_or_else(|| anyhow!("no shard files"))?;
    let n = study.samples;
    if owner.len() as u64 != n {
        let missing: Vec<String> = (0..n)
            .filter(|i| !owner.contains_key(i))
            .take(5)
            .map(|i| i.to_string())
            .collect();
        bail!(
            "{} of the study's {n} samples are missing (first: {}); give every shard's file",
            n - owner.len() as u64,
            missing.join(", ")
        );
    }
    records.sort_by_key(|r| r.index);
    let revolution = measured_revolution(study.revolutions);
    let summary = summarize(&records, revolution)?;
    if let Some(t) = plot_target {
        let mut dir = t.open()?;
        draw(&mut dir, &records, revolution)?;
        dir.commit()?;
    }
    Ok(MonteCarloReport {
        study,
        summary,
        timing: None,
    })
}

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    let json = match &args.merge {
        Some(Sub::Merge(m)) => m.output.json,
        None => args.output.json,
    };
    match execute(&args)? {
        Outcome::Study(r) => crate::report::print(r.as_ref(), json),
        Outcome::Shard(r) => crate::report::print(&r, json),
    }
}

impl Report for ShardReport {
    fn text(&self) -> String {
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

/// Short column labels of the text table.
fn label(col: &str) -> &str {
    match col {
        "rms_displacement" => "rms_y, in",
        "rms_velocity" => "rms_v, in/s",
        "rms_acceleration" => "rms_a, in/s2",
        "torque_avg" => "T_avg, lb in",
        "torque_max" => "T_max, lb in",
        "torque_min" => "T_min, lb in",
        "contact_force_min" => "Fc_min, lb",
        "contact_force_max" => "Fc_max, lb",
        "contact_force_avg" => "Fc_avg, lb",
        "contact_stress_max" => "stress, psi",
        "aord_motor" => "aord_m",
        "aord_coupling" => "aord_cp",
        "aord_cam" => "aord_c",
        "acc_rms_sum" => "sum rms_a, in/s2",
        "fpr" => "FPR",
        "rms_deviation_in" => "rms lift dev, in",
        other => other,
    }
}

fn moments_table(out: &mut String, columns: &Columns) {
    use std::fmt::Write;
    let _ = writeln!(
        out,
        "  {:<17} {:>11} {:>11} {:>11} {:>11} {:>11}",
        "", "mean", "sd", "p5", "p50", "p95"
    );
    for (name, m) in &columns.0 {
        let _ = writeln!(
            out,
            "  {:<17} {:>11.4e} {:>11.4e} {:>11.4e} {:>11.4e} {:>11.4e}",
            label(name),
            m.mean,
            m.sd,
            m.p5,
            m.p50,
            m.p95
        );
    }
}

fn probability_text(p: &Probability, n: u64) -> String {
    format!(
        "{} of {n}, p = {:.4}, 95 % interval [{:.4}, {:.4}] (Wilson)",
        p.count, p.p, p.lo95, p.hi95
    )
}

impl Report for MonteCarloReport {
    fn text(&self) -> String {
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
            "profile: {} ({} normal deviates), tolerances cam {} / roller {} / eccentricity {} in, {} intervals ({:.4} deg, {})",
            p.method,
            p.normal,
            p.cam_tolerance_in,
            p.roller_tolerance_in,
            p.eccentricity_tolerance_in,
            p.intervals,
            360.0 / p.intervals as f64,
            p.interval_source
        );
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
            moments_table(&mut out, &period.columns);
        }
        let _ = writeln!(out, "\nwhole revolution {}:", sm.revolution);
        moments_table(&mut out, &sm.whole_revolution);
        let _ = writeln!(out, "profiles:");
        moments_table(&mut out, &sm.profile);
        let _ = writeln!(
            out,
            "\njump anywhere in revolution {}: {}",
            sm.revolution,
            probability_text(&sm.jump, sm.samples)
        );
        let _ = writeln!(
            out,
            "solver: {:.0} accepted steps per sample on average",
            sm.steps.mean
        );
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

/// The plots `--plot DIR` writes.
pub const PLOT_FILES: [&str; 2] = ["histograms.png", "period_histograms.png"];

/// Draws the histograms of a study's records into `dir`.
fn draw(dir: &mut AtomicDir, records: &[SampleRecord], revolution: u32) -> Result<()> {
    let n = records.len();
    let mut panels: Vec<(String, Vec<f64>)> = REVOLUTION_COLUMNS
        .iter()
        .map(|c| {
            (
                format!("revolution {revolution}: {}", label(c)),
                records.iter().map(|r| revolution_value(r, c)).collect(),
            )
        })
        .collect();
    panels.push((
        "profile FPR".into(),
        records.iter().map(|r| r.fpr as f64).collect(),
    ));
    panels.push((
        "profile rms lift deviation, in".into(),
        records.iter().map(|r| r.rms_deviation_in).collect(),
    ));
    let jumps = records.iter().filter(|r| r.jump()).count();
    plots::histograms(
        dir,
        PLOT_FILES[0],
        &format!("{n} actual cams: revolution {revolution}, {jumps} with a jump"),
        &panels,
        4,
    )?;
    let mut panels = Vec::new();
    let names: Vec<String> = records
        .first()
        .map(|r| r.periods.iter().map(|p| p.period.clone()).collect())
        .unwrap_or_default();
    for col in [
        "rms_acceleration",
        "contact_force_min",
        "torque_max",
        "contact_stress_max",
    ] {
        for (k, name) in names.iter().enumerate() {
            panels.push((
                format!("{name}: {}", label(col)),
                records
                    .iter()
                    .filter_map(|r| r.periods.get(k).and_then(|p| p.get(col)))
                    .collect(),
            ));
        }
    }
    plots::histograms(
        dir,
        PLOT_FILES[1],
        &format!("{n} actual cams: revolution {revolution} by period"),
        &panels,
        names.len().max(1),
    )
}

/// Plots of the studies (histograms, bar charts, curves), drawn with the run plots'
/// embedded font.
pub mod plots {
    use anyhow::{anyhow, Result};
    use plotters::prelude::*;

    use crate::output::AtomicDir;

    const BAR: RGBColor = RGBColor(31, 119, 180);
    /// Colours of the curves of a line chart, in order.
    pub const PALETTE: [RGBColor; 6] = [
        RGBColor(31, 119, 180),
        RGBColor(214, 39, 40),
        RGBColor(44, 160, 44),
        RGBColor(255, 127, 14),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
    ];

    fn err<E: std::fmt::Display>(file: &str) -> impl Fn(E) -> anyhow::Error + '_ {
        move |e| anyhow!("cannot draw plot {file}: {e}")
    }

    /// Renders `size` pixels with `draw` and writes the PNG as `file` in `dir`.
    pub fn png(
        dir: &mut AtomicDir,
        file: &str,
        size: (u32, u32),
        draw: impl FnOnce(&DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>) -> Result<()>,
    ) -> Result<()> {
        crate::plot::ensure_font()?;
        let mut buf = vec![0u8; size.0 as usize * size.1 as usize * 3];
        {
            let root = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
            root.fill(&WHITE).map_err(err(file))?;
            draw(&root)?;
            root.present().map_err(err(file))?;
        }
        let path = dir.path(file)?;
        image::save_buffer_with_format(
            &path,
            &buf,
            size.0,
            size.1,
            image::ColorType::Rgb8,
            image::ImageFormat::Png,
        )
        .map_err(|e| anyhow!("cannot write plot {}: {e}", dir.dir().join(file).display()))
    }

    /// Bin counts of `values` over `bins` equal bins spanning their range.
    pub fn bin(values: &[f64], bins: usize) -> (f64, f64, Vec<u32>) {
        let bins = bins.max(1);
        let (mut lo, mut hi) = values
            .iter()
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        if lo > hi {
            (lo, hi) = (0.0, 1.0);
        }
        if hi - lo <= 1e-12 * hi.abs().max(lo.abs()).max(1e-300) {
            let half = if hi != 0.0 { 0.01 * hi.abs() } else { 0.5 };
            (lo, hi) = (lo - half, hi + half);
        }
        let mut counts = vec![0u32; bins];
        for &v in values.iter().filter(|v| v.is_finite()) {
            let k = (((v - lo) / (hi - lo)) * bins as f64).floor() as usize;
            counts[k.min(bins - 1)] += 1;
        }
        (lo, hi, counts)
    }

    /// A grid of histograms, `cols` panels a row, titled `title`, as `file` in `dir`.
    pub fn histograms(
        dir: &mut AtomicDir,
        file: &str,
        title: &str,
        panels: &[(String, Vec<f64>)],
        cols: usize,
    ) -> Result<()> {
        let cols = cols.max(1);
        let rows = panels.len().div_ceil(cols).max(1);
        let size = (360 * cols as u32, 60 + 280 * rows as u32);
        png(dir, file, size, |root| {
            let root = root.titled(title, ("sans-serif", 24)).map_err(err(file))?;
            let areas = root.split_evenly((rows, cols));
            for ((name, values), area) in panels.iter().zip(areas.iter()) {
                let bins = ((values.len() as f64).sqrt().ceil() as usize).clamp(5, 50);
                let (lo, hi, counts) = bin(values, bins);
                let top = counts.iter().copied().max().unwrap_or(1).max(1);
                let mut chart = ChartBuilder::on(area)
                    .caption(name, ("sans-serif", 15))
                    .margin(8)
                    .x_label_area_size(30)
                    .y_label_area_size(40)
                    .build_cartesian_2d(lo..hi, 0u32..top + top / 10 + 1)
                    .map_err(err(file))?;
                chart
                    .configure_mesh()
                    .disable_x_mesh()
                    .x_labels(4)
                    .y_labels(5)
                    .x_label_formatter(&|v| format!("{v:.3e}"))
                    .label_style(("sans-serif", 11))
                    .draw()
                    .map_err(err(file))?;
                let w = (hi - lo) / counts.len() as f64;
                chart
                    .draw_series(counts.iter().enumerate().map(|(k, &c)| {
                        let x0 = lo + k as f64 * w;
                        Rectangle::new([(x0, 0), (x0 + w, c)], BAR.filled())
                    }))
                    .map_err(err(file))?;
            }
            Ok(())
        })
    }
}
