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
//! The parts: the study and its models ([`levels`]), a sample's run ([`sample`]), the
//! samples run in parallel ([`parallel`]), the settings that identify a study
//! ([`settings`]), the statistics (`crate::stats`), the study measured from its [`Spec`]
//! or merged from its shards ([`measure()`], [`merge()`]), the shard files and their
//! merge ([`shard`]) and the printed report ([`report`]); the histograms are
//! [`crate::plot::montecarlo`], the command line `crate::cmd::montecarlo`.

pub mod levels;
pub mod measure;
pub mod parallel;
pub mod report;
pub mod sample;
pub mod settings;
pub mod shard;

pub use crate::stats::stream::Moments;
pub use crate::stats::study::{
    revolution_value, summarize, Columns, PeriodSummary, StudyStats, Summary, REVOLUTION_COLUMNS,
};
pub use crate::stats::two_level::{TwoLevelStats, TwoLevelSummary};
pub use crate::stats::Probability;
pub use levels::{default_full_samples, monte_carlo_model, Study, MIN_FULL_SAMPLES};
pub use measure::{measure, merge, Measured, MonteCarloOutcome, Spec};
pub use parallel::{threads, Tally};
pub use report::{MonteCarloReport, ShardReport, Timing};
pub use sample::{LeftRange, Outcome, PeriodValues, SampleRecord, COLUMNS};
pub use settings::{ProfileSettings, StudySettings, TwoLevelSettings};
pub use shard::{parse_shard, read_shard, Shard, ShardFile, SHARD_FORMAT, SHARD_VERSION};

/// The revolution whose statistics a study keeps (the thesis's cycle II, steady state),
/// unless it simulates only one (`--revolutions 1`, a reduced study: revolution 1).
pub const REVOLUTION: u32 = 2;

/// The revolution a study of `revolutions` revolutions measures: 2, or 1 if it runs one.
pub fn measured_revolution(revolutions: u32) -> u32 {
    revolutions.clamp(1, REVOLUTION)
}
