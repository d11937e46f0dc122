//! `camsim montecarlo`: many actual cams, in parallel, reproducible bit for bit.
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

use std::collections::BTreeMap;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use anyhow::{anyhow, bail, Context, Result};
use camsim_core::DriveLaw;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

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
pub const SHARD_VERSION: u32 = 3;

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
    /// Write the samples' statistics to FILE (JSON; the shard file `merge` reads).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Run a study past the limit of estimated time (24 h on its threads) that otherwise
    /// refuses it (`camsim::study_limits`).
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

    /// Runs the samples of `shard` on a local pool of `threads` threads, with progress
    /// (`progress`: a bar on a terminal, lines otherwise), and returns their statistics:
    /// each record is added to a thread's [`StudyStats`] and dropped, so memory does not
    /// grow with the samples, and the result does not depend on the threads. The first
    /// failure stops the samples not yet started; the error names the lowest failing
    /// index among those that ran.
    pub fn run_stats(&self, shard: Shard, threads: usize, progress: bool) -> Result<StudyStats> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads.max(1))
            .stack_size(16 << 20)
            .build()
            .context("cannot start the worker threads")?;
        let count = shard.len(self.settings.samples);
        let bar = progress_bar(count, progress);
        let lines = crate::study_limits::ProgressLines::new(
            "camsim montecarlo",
            count,
            progress && crate::study_limits::ProgressLines::batch(),
        );
        let stop = AtomicBool::new(false);
        type Part = (StudyStats, Option<(u64, anyhow::Error)>);
        fn lowest(
            a: Option<(u64, anyhow::Error)>,
            b: Option<(u64, anyhow::Error)>,
        ) -> Option<(u64, anyhow::Error)> {
            match (a, b) {
                (Some(x), Some(y)) => Some(if y.0 < x.0 { y } else { x }),
                (x, y) => x.or(y),
            }
        }
        let (stats, err): Part = pool.install(|| {
            use rayon::iter::IntoParallelIterator;
            (0..count)
                .into_par_iter()
                .map(|j| shard.index - 1 + j * shard.count)
                .fold(
                    || (StudyStats::default(), None),
                    |(mut acc, err): Part, i| {
                        if stop.load(Ordering::Relaxed) {
                            return (acc, err);
                        }
                        let r = self.sample(i).and_then(|rec| acc.add(&rec));
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
                    || (StudyStats::default(), None),
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
        anyhow::ensure!(stats.samples == count, "a sample failed");
        Ok(stats)
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

pub use crate::stats::stream::Moments;
pub use crate::stats::study::{
    revolution_value, summarize, Columns, PeriodSummary, StudyStats, Summary, REVOLUTION_COLUMNS,
};
pub use crate::stats::Probability;

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
    /// Its samples (those of [`Shard::indices`]).
    pub samples: u64,
    /// Their statistics (version 3 on; version 2 held every sample's record).
    pub stats: StudyStats,
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
    if let Some(p) = &args.study.scene.scene {
        plan.input("scene file", p);
    }
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
    let count = shard.len(study.settings.samples);
    // Memory does not grow with the samples (streamed statistics); time is estimated
    // from the first sample run alone (once more than the study needs: a sample depends
    // on its index only).
    if let Some(first) = shard.indices(study.settings.samples).next() {
        let t = Instant::now();
        study.sample(first)?;
        crate::study_limits::check_time(
            t.elapsed().as_secs_f64(),
            count,
            threads,
            args.allow_long,
        )?;
    }
    let t0 = Instant::now();
    let stats = study.run_stats(shard, threads, true)?;
    let wall_s = t0.elapsed().as_secs_f64();
    let timing = Timing {
        threads,
        wall_s,
        samples_per_s: stats.samples as f64 / wall_s,
        samples_per_s_per_thread: stats.samples as f64 / wall_s / threads as f64,
    };
    let summary = if args.shard.is_none() {
        Some(stats.summary(study.revolution())?)
    } else {
        None
    };
    let mut plots = match (plot_target, &summary) {
        (Some(t), Some(_)) => {
            let mut dir = t.open()?;
            draw(&mut dir, &stats, study.revolution())?;
            Some(dir)
        }
        _ => None,
    };
    let n = stats.samples;
    if let Some(mut f) = out_file.take() {
        let mut file = ShardFile {
            format: SHARD_FORMAT.into(),
            version: SHARD_VERSION,
            study: study.settings.clone(),
            shard,
            samples: n,
            stats,
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
    for f in files {
        plan.input("shard file", f);
    }
    let plot_target = match &out.plot {
        Some(dir) => Some(plan.dir("--plot", dir, &PLOT_FILES)?),
        None => None,
    };
    let first_path = files.first().ok_or_else(|| anyhow!("no shard files"))?;
    let mut study: Option<StudySettings> = None;
    // shard K -> the file that has it, all of one split N.
    let mut owner: BTreeMap<u64, usize> = BTreeMap::new();
    let mut split: Option<(u64, usize)> = None;
    let mut stats = StudyStats::default();
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
        let Shard { index, count } = shard.shard;
        match split {
            None => split = Some((count, f)),
            Some((n, g)) if n != count => bail!(
                "{} is shard {index}/{count} and {} a shard of {n}: the shards of a study are one split K/N with one N",
                path.display(),
                files[g].display()
            ),
            Some(_) => {}
        }
        if let Some(&other) = owner.get(&index) {
            bail!(
                "shard {index}/{count} is in {} and in {} (each sample must come from exactly one shard)",
                files[other].display(),
                path.display()
            );
        }
        owner.insert(index, f);
        stats
            .merge(&shard.stats)
            .map_err(|e| anyhow!("{}: {e}", path.display()))?;
    }
    let study = study.ok_or_else(|| anyhow!("no shard files"))?;
    let n = study.samples;
    let count = split.map_or(1, |s| s.0);
    let missing: Vec<u64> = (1..=count).filter(|k| !owner.contains_key(k)).collect();
    let lost: u64 = missing
        .iter()
        .map(|&k| Shard { index: k, count }.len(n))
        .sum();
    if lost > 0 {
        let mut first: Vec<u64> = missing
            .iter()
            .flat_map(|&k| Shard { index: k, count }.indices(n).take(5))
            .collect();
        first.sort_unstable();
        first.truncate(5);
        let first: Vec<String> = first.iter().map(|i| i.to_string()).collect();
        let shards: Vec<String> = missing
            .iter()
            .take(5)
            .map(|k| format!("{k}/{count}"))
            .collect();
        bail!(
            "{lost} of the study's {n} samples are missing (first: {}; shards {}); give every shard's file",
            first.join(", "),
            shards.join(", ")
        );
    }
    anyhow::ensure!(
        stats.samples == n,
        "the shards hold {} samples, the study {n}",
        stats.samples
    );
    let revolution = measured_revolution(study.revolutions);
    let summary = stats.summary(revolution)?;
    if let Some(t) = plot_target {
        let mut dir = t.open()?;
        draw(&mut dir, &stats, revolution)?;
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

/// Draws the histograms of a study's statistics into `dir` (from each stream's
/// histogram: counts of samples, the bins of each panel equal over its range).
fn draw(dir: &mut AtomicDir, stats: &StudyStats, revolution: u32) -> Result<()> {
    let n = stats.samples;
    let bins = ((n as f64).sqrt().ceil() as usize).clamp(5, 50);
    let mut panels: Vec<(String, plots::Binned)> = REVOLUTION_COLUMNS
        .iter()
        .zip(&stats.whole_revolution)
        .map(|(c, s)| {
            (
                format!("revolution {revolution}: {}", label(c)),
                s.display_bins(bins),
            )
        })
        .collect();
    panels.push(("profile FPR".into(), stats.fpr.display_bins(bins)));
    panels.push((
        "profile rms lift deviation, in".into(),
        stats.rms_deviation_in.display_bins(bins),
    ));
    plots::histograms_binned(
        dir,
        PLOT_FILES[0],
        &format!(
            "{n} actual cams: revolution {revolution}, {} with a jump",
            stats.jumps
        ),
        &panels,
        4,
    )?;
    let mut panels = Vec::new();
    for col in [
        "rms_acceleration",
        "contact_force_min",
        "torque_max",
        "contact_stress_max",
    ] {
        let c = COLUMNS.iter().position(|x| *x == col);
        for p in &stats.periods {
            if let Some(s) = c.and_then(|c| p.columns.get(c)) {
                panels.push((
                    format!("{}: {}", p.period, label(col)),
                    s.display_bins(bins),
                ));
            }
        }
    }
    plots::histograms_binned(
        dir,
        PLOT_FILES[1],
        &format!("{n} actual cams: revolution {revolution} by period"),
        &panels,
        stats.periods.len().max(1),
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

    /// A histogram binned for a plot: (lo, hi, counts of equal bins over lo..hi).
    pub type Binned = (f64, f64, Vec<u32>);

    /// A grid of histograms, `cols` panels a row, titled `title`, as `file` in `dir`.
    pub fn histograms(
        dir: &mut AtomicDir,
        file: &str,
        title: &str,
        panels: &[(String, Vec<f64>)],
        cols: usize,
    ) -> Result<()> {
        let binned: Vec<(String, Binned)> = panels
            .iter()
            .map(|(name, values)| {
                let bins = ((values.len() as f64).sqrt().ceil() as usize).clamp(5, 50);
                (name.clone(), bin(values, bins))
            })
            .collect();
        histograms_binned(dir, file, title, &binned, cols)
    }

    /// A grid of histograms already binned (`(lo, hi, counts)` a panel, equal bins).
    pub fn histograms_binned(
        dir: &mut AtomicDir,
        file: &str,
        title: &str,
        panels: &[(String, Binned)],
        cols: usize,
    ) -> Result<()> {
        let cols = cols.max(1);
        let rows = panels.len().div_ceil(cols).max(1);
        let size = (360 * cols as u32, 60 + 280 * rows as u32);
        png(dir, file, size, |root| {
            let root = root.titled(title, ("sans-serif", 24)).map_err(err(file))?;
            let areas = root.split_evenly((rows, cols));
            for ((name, (lo, hi, counts)), area) in panels.iter().zip(areas.iter()) {
                let (lo, hi) = (*lo, *hi);
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
