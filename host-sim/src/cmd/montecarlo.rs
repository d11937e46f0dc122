//! `camsim montecarlo`: many actual cams, in parallel, reproducible bit for bit. The
//! command line and its outputs; the study is [`crate::study::montecarlo`], its
//! histograms [`crate::plot::montecarlo`].

use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::{bail, Result};

pub use crate::args::{OutputArgs, StudyArgs};
use crate::output::{AtomicFile, DirTarget, Plan};
use crate::plot::montecarlo::{draw, PLOT_FILES};
pub use crate::study::montecarlo::{
    default_full_samples, measured_revolution, parse_shard, read_shard, summarize, threads,
    Columns, Moments, MonteCarloReport, PeriodSummary, PeriodValues, Probability, ProfileSettings,
    SampleRecord, Shard, ShardFile, ShardReport, Study, StudySettings, StudyStats, Summary, Timing,
    COLUMNS, REVOLUTION, REVOLUTION_COLUMNS, SHARD_FORMAT, SHARD_VERSION,
};

/// Command-line options of `camsim montecarlo`.
#[derive(clap::Args, Debug, Clone)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
#[command(mut_arg("actual", |a| a.hide(true)))]
#[command(mut_arg("plot", |a| a.help("Write histogram plots (PNG) into DIR (created if missing; existing plots need --force)")))]
#[command(mut_arg("force", |a| a.help("Replace existing --out and --plot files")))]
pub struct Args {
    /// `merge FILES...`: merge shard files into the study's result.
    #[command(subcommand)]
    pub merge: Option<Sub>,
    /// The study.
    #[command(flatten)]
    pub study: StudyArgs,
    /// Worker threads (default: every core). The result does not depend on it.
    #[arg(long, value_parser = crate::args::whole_u32::<1, 1024>)]
    pub threads: Option<u32>,
    /// The full model's answer as a two-level estimate (the default when --follower is
    /// not given): every cam on the reduced model of the design searches (quasi-static
    /// cantilever, vertical, rtol 1e-4), the first N cams on the full model too; the full
    /// model's P(jump) and means are the reduced model's plus the measured difference,
    /// with a 95 % interval that includes the difference's uncertainty (docs/MODEL.md
    /// §9.7). Default N: a tenth of --samples, at least 30, at most --samples. N = 0: every
    /// cam on the full model alone (as --follower full). The scene's constant cam speed
    /// or run.follower runs its one model, said in the report.
    #[arg(long, value_name = "N", conflicts_with = "follower", value_parser = clap::value_parser!(u64))]
    pub two_level: Option<u64>,
    /// Run only shard K of N (K from 1): the samples i with i mod N = K - 1. Needs --out.
    #[arg(long, value_name = "K/N", allow_hyphen_values = true, value_parser = parse_shard, requires = "out")]
    pub shard: Option<Shard>,
    /// Write the samples' statistics to FILE (JSON; the shard file `merge` reads).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Run a study past the limit of estimated time (24 h on its threads) that otherwise
    /// refuses it (`camsim::study_limits`).
    #[arg(long)]
    pub allow_long: bool,
    /// What it prints and draws.
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
#[command(mut_arg("plot", |a| a.help("Write histogram plots (PNG) into DIR (created if missing; existing plots need --force)")))]
#[command(mut_arg("force", |a| a.help("Replace existing --out and --plot files")))]
pub struct MergeArgs {
    /// The shard files (`camsim montecarlo --shard K/N --out FILE`).
    #[arg(required = true, value_name = "FILES")]
    pub files: Vec<PathBuf>,
    /// What it prints and draws.
    #[command(flatten)]
    pub output: OutputArgs,
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
    args.study.actual.refuse_actual_flag("montecarlo")?;
    let study = levels(Study::new(&args.study)?, args)?;
    let shard = args.shard.unwrap_or(Shard::WHOLE);
    let (mut out_file, plot_target) = outputs(args)?;
    let threads = threads(args.threads);
    first_sample_time(&study, shard, threads, args.allow_long)?;
    let t0 = Instant::now();
    let tally = study.run_tally(shard, threads, true)?;
    let stats = tally.stats;
    let two_level = study
        .settings
        .two_level
        .is_some()
        .then_some(tally.two_level);
    let timing = timing(threads, t0.elapsed().as_secs_f64(), stats.accounted());
    let (summary, two_level_summary) = if args.shard.is_none() {
        let t = match &two_level {
            Some(t) => t.summary(&stats)?,
            None => None,
        };
        (Some(stats.summary(study.revolution())?), t)
    } else {
        (None, None)
    };
    let mut plots = match (plot_target, &summary) {
        (Some(t), Some(_)) => {
            let mut dir = t.open()?;
            draw(&mut dir, &stats, study.revolution())?;
            Some(dir)
        }
        _ => None,
    };
    let n = stats.accounted();
    if let Some(f) = out_file.take() {
        write_shard(f, &study.settings, shard, stats, two_level)?;
    }
    if let Some(p) = plots.take() {
        p.commit()?;
    }
    match summary {
        Some(summary) => Ok(Outcome::Study(Box::new(MonteCarloReport {
            study: study.settings,
            summary,
            two_level: two_level_summary,
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

/// Every output checked before any sample runs: the `--out` file, its temporary already
/// open (a name the file system refuses fails now, not after the whole study), and the
/// `--plot` directory.
fn outputs(args: &Args) -> Result<(Option<AtomicFile>, Option<DirTarget>)> {
    let out = &args.output;
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
    let out_file = match out_target {
        Some(t) => Some(t.open()?),
        None => None,
    };
    Ok((out_file, plot_target))
}

/// The study's speed: `samples` accounted in `wall_s` seconds on `threads` threads.
fn timing(threads: usize, wall_s: f64, samples: u64) -> Timing {
    Timing {
        threads,
        wall_s,
        samples_per_s: samples as f64 / wall_s,
        samples_per_s_per_thread: samples as f64 / wall_s / threads as f64,
    }
}

/// Refuses a shard whose estimated time is too long (unless `allow_long`), before it runs.
fn first_sample_time(study: &Study, shard: Shard, threads: usize, allow_long: bool) -> Result<()> {
    let count = shard.len(study.settings.samples);
    // Memory does not grow with the samples (streamed statistics); time is estimated
    // from the first sample run alone (once more than the study needs: a sample depends
    // on its index only).
    // (A two-level study's first sample runs on both models: its time counts the
    // shard's full-model cams once more for each of its cams, an overestimate.)
    if let Some(first) = shard.indices(study.settings.samples).next() {
        let t = Instant::now();
        let _ = study.pair(first)?;
        crate::study_limits::check_time(t.elapsed().as_secs_f64(), count, threads, allow_long)?;
    }
    Ok(())
}

/// Writes the shard's statistics (with their digest) to its output file and commits it.
fn write_shard(
    mut f: crate::output::AtomicFile,
    settings: &StudySettings,
    shard: Shard,
    stats: StudyStats,
    two_level: Option<crate::stats::two_level::TwoLevelStats>,
) -> Result<()> {
    let mut file = ShardFile {
        format: SHARD_FORMAT.into(),
        version: SHARD_VERSION,
        study: settings.clone(),
        shard,
        samples: stats.accounted(),
        stats,
        two_level,
        digest: String::new(),
    };
    file.digest = crate::shard::digest(&file)?;
    serde_json::to_writer(&mut f, &file)?;
    f.write_all(b"\n")?;
    f.commit()
}

/// The study's models: `--two-level N` (0: the full model alone), `--follower` one
/// model, neither the default two-level estimate ([`Study::default_levels`]).
fn levels(mut study: Study, args: &Args) -> Result<Study> {
    match args.two_level {
        Some(0) => {
            study.settings.one_model = Some("the full model alone (--two-level 0)".into());
            Ok(study)
        }
        Some(n) => study.two_level(n),
        None if args.study.scene.follower.is_some() => Ok(study),
        None => study.default_levels(),
    }
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
    let (study, tally) = crate::study::montecarlo::shard::collect(files)?;
    let stats = tally.stats;
    let revolution = measured_revolution(study.revolutions);
    let summary = stats.summary(revolution)?;
    let two_level = match &study.two_level {
        Some(_) => tally.two_level.summary(&stats)?,
        None => None,
    };
    if let Some(t) = plot_target {
        let mut dir = t.open()?;
        draw(&mut dir, &stats, revolution)?;
        dir.commit()?;
    }
    Ok(MonteCarloReport {
        study,
        summary,
        two_level,
        timing: None,
    })
}

/// Runs the command.
pub fn run(args: Args, units: crate::units::Units) -> Result<()> {
    let json = match &args.merge {
        Some(Sub::Merge(m)) => m.output.json,
        None => args.output.json,
    };
    match execute(&args)? {
        Outcome::Study(r) => crate::report::print(r.as_ref(), json, units),
        Outcome::Shard(r) => crate::report::print(&r, json, units),
    }
}
