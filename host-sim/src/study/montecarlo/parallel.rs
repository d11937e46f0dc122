//! A study's samples run in parallel on a local pool of threads, with progress: their
//! records ([`Study::run`]) or their statistics added up as they finish ([`Tally`],
//! [`Study::run_tally`]), the same bit for bit for any threads.

use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::Result;
use rayon::prelude::*;

use super::{Outcome, SampleRecord, Shard, Study, StudyStats, TwoLevelStats};

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
        let pool = crate::study::pool(threads)?;
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
        let pool = crate::study::pool(threads)?;
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

/// The worker threads: `--threads`, or every core.
pub fn threads(arg: Option<u32>) -> usize {
    arg.map(|t| t as usize).unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    })
}
