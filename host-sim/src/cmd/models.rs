//! `camsim models` (formerly `camsim scenes`): which scene is accurate enough for which
//! question ([`crate::study::models`], which holds the study, its report and the report's
//! text). This command reads the arguments into the study's [`Spec`], runs it and prints
//! the report.

use anyhow::Result;

pub use crate::study::models::*;

/// Command-line options of `camsim models`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Cam speed of the work, time and error columns, rpm.
    #[arg(long, default_value_t = 800.0, allow_hyphen_values = true, value_parser = crate::args::rpm)]
    pub rpm: f64,
    /// Fewer timed repetitions and a coarser jump-onset bisection (CI).
    #[arg(long)]
    pub quick: bool,
    /// Print JSON: {"rows": [...], ...}.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(args: Args, units: crate::units::Units) -> Result<()> {
    let spec = Spec {
        rpm: args.rpm,
        quick: args.quick,
        progress: true,
    };
    crate::report::print(&report(&spec)?, args.json, units)
}
