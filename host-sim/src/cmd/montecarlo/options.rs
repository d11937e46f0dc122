//! `camsim montecarlo`'s command-line options: the study's, the shard's and the
//! outputs' (`Args`), and `merge`'s (`MergeArgs`).

use std::path::PathBuf;

use super::{parse_shard, Shard};
use crate::args::{OutputArgs, StudyArgs};

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
