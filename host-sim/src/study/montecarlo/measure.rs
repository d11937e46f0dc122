//! A study measured from its [`Spec`] ([`measure`]: the time check, the samples, the
//! summaries) or from its shard files ([`merge`]): the statistics (for the shard file
//! and the histograms) with the report's numbers.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Result;

use super::report::{MonteCarloReport, ShardReport, Timing};
use super::{measured_revolution, Shard, ShardFile, Study, StudySettings, StudyStats, Summary};
use super::{TwoLevelStats, TwoLevelSummary, SHARD_FORMAT, SHARD_VERSION};

/// What a study (or one shard of it) runs.
#[derive(Clone, Debug)]
pub struct Spec {
    /// The study, its models chosen ([`Study::with_levels`]).
    pub study: Study,
    /// The shard it runs (`None`: the whole study, summarized).
    pub shard: Option<Shard>,
    /// Worker threads (the result does not depend on them).
    pub threads: usize,
    /// Run past the limit of estimated time (`crate::study_limits`).
    pub allow_long: bool,
}

/// What a study or a shard measured.
#[derive(Clone, Debug)]
pub struct Measured {
    /// The study.
    pub settings: StudySettings,
    /// The revolution the statistics are of.
    pub revolution: u32,
    /// The samples it ran ([`Shard::WHOLE`]: every one).
    pub shard: Shard,
    /// Every cam's statistics (the reduced model's in a two-level study).
    pub stats: StudyStats,
    /// A two-level study's pairs.
    pub two_level: Option<TwoLevelStats>,
    /// The summary (none for a shard).
    pub summary: Option<Summary>,
    /// A two-level study's estimate of the full model (none for a shard, or with fewer
    /// than two workable pairs).
    pub two_level_summary: Option<TwoLevelSummary>,
    /// Run time (none for a merge).
    pub timing: Option<Timing>,
}

/// Runs the study's samples (those of its shard), after refusing a run whose estimated
/// time is too long; a whole study is summarized.
pub fn measure(spec: &Spec) -> Result<Measured> {
    let (study, threads) = (&spec.study, spec.threads);
    let shard = spec.shard.unwrap_or(Shard::WHOLE);
    first_sample_time(study, shard, threads, spec.allow_long)?;
    let t0 = Instant::now();
    let tally = study.run_tally(shard, threads, true)?;
    let stats = tally.stats;
    let two_level = study
        .settings
        .two_level
        .is_some()
        .then_some(tally.two_level);
    let timing = timing(threads, t0.elapsed().as_secs_f64(), stats.accounted());
    let (summary, two_level_summary) = if spec.shard.is_none() {
        let t = match &two_level {
            Some(t) => t.summary(&stats)?,
            None => None,
        };
        (Some(stats.summary(study.revolution())?), t)
    } else {
        (None, None)
    };
    Ok(Measured {
        settings: study.settings.clone(),
        revolution: study.revolution(),
        shard,
        stats,
        two_level,
        summary,
        two_level_summary,
        timing: Some(timing),
    })
}

/// Merges shard files into the result of their study (every sample exactly once).
pub fn merge(files: &[PathBuf]) -> Result<Measured> {
    let (settings, tally) = super::shard::collect(files)?;
    let stats = tally.stats;
    let revolution = measured_revolution(settings.revolutions);
    let summary = stats.summary(revolution)?;
    let two_level_summary = match &settings.two_level {
        Some(_) => tally.two_level.summary(&stats)?,
        None => None,
    };
    Ok(Measured {
        revolution,
        shard: Shard::WHOLE,
        two_level: settings.two_level.is_some().then_some(tally.two_level),
        settings,
        stats,
        summary: Some(summary),
        two_level_summary,
        timing: None,
    })
}

impl Measured {
    /// The shard file of these statistics, with its digest.
    pub fn shard_file(&self) -> Result<ShardFile> {
        let mut file = ShardFile {
            format: SHARD_FORMAT.into(),
            version: SHARD_VERSION,
            study: self.settings.clone(),
            shard: self.shard,
            samples: self.stats.accounted(),
            stats: self.stats.clone(),
            two_level: self.two_level.clone(),
            digest: String::new(),
        };
        file.digest = crate::shard::digest(&file)?;
        Ok(file)
    }

    /// The study's report, or a shard's (`out` its shard file).
    pub fn report(self, out: PathBuf) -> MonteCarloOutcome {
        match self.summary {
            Some(summary) => MonteCarloOutcome::Study(Box::new(MonteCarloReport {
                study: self.settings.measured(),
                summary,
                two_level: self.two_level_summary,
                timing: self.timing,
            })),
            None => MonteCarloOutcome::Shard(ShardReport {
                shard: self.shard,
                samples: self.stats.accounted(),
                out,
                // Only `measure` makes a shard's statistics: it times them.
                timing: self.timing.unwrap_or(Timing {
                    threads: 0,
                    wall_s: 0.0,
                    samples_per_s: 0.0,
                    samples_per_s_per_thread: 0.0,
                }),
            }),
        }
    }
}

impl Measured {
    /// The whole study's report (a merge's); an error for a shard's statistics.
    pub fn study_report(self) -> Result<MonteCarloReport> {
        match self.report(PathBuf::new()) {
            MonteCarloOutcome::Study(r) => Ok(*r),
            MonteCarloOutcome::Shard(_) => anyhow::bail!("a merge gave a shard, not a study"),
        }
    }
}

/// The report of `camsim montecarlo`.
#[derive(Clone, Debug)]
pub enum MonteCarloOutcome {
    /// A whole study (or a merge).
    Study(Box<MonteCarloReport>),
    /// One shard written.
    Shard(ShardReport),
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
