//! `camsim waviness`: the waviness (FPR) an actual cam gets against its profile point
//! interval, for both profile methods, and the three criteria of IV.2.3 at each interval
//! (the table of docs/MODEL.md §9.6), or a measured revolution's waviness. The study is
//! [`crate::study::waviness`]; this command reads the arguments into its [`Spec`], runs
//! it and prints the report.

use anyhow::Result;

pub use crate::study::waviness::*;

/// Command-line options.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Master seeds (default 1,2,3).
    #[arg(long, value_delimiter = ',', value_parser = crate::args::seed)]
    pub seeds: Vec<u64>,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Instead of the table, a measured revolution's waviness (the CSV of `run
    /// --measured`, on the reference design): its FPR, RMS deviation, the equivalent
    /// ± cam tolerance (3 sigma) and the --waviness-fpr to study cams like it with.
    #[arg(long, value_name = "FILE", conflicts_with = "seeds")]
    pub measured: Option<std::path::PathBuf>,
}

/// The study's spec: the seeds given, 1, 2, 3 by default.
pub fn spec(args: &Args) -> Spec {
    let seeds = if args.seeds.is_empty() {
        vec![1, 2, 3]
    } else {
        args.seeds.clone()
    };
    Spec { seeds }
}

/// Runs the command.
pub fn run(args: Args, units: crate::units::Units) -> Result<()> {
    if let Some(path) = &args.measured {
        return crate::report::print(&measured(path)?, args.json, units);
    }
    crate::report::print(&report(&spec(&args))?, args.json, units)
}
