//! `camsim bench`: run time against error (the measurements, the report's text and the
//! plots are [`crate::bench`]'s); this command reads the arguments into its
//! [`Options`], runs it, prints the report and draws its plots.

use anyhow::Result;

use crate::args::OutputArgs;
use crate::bench::{self, Options};
use crate::output::Plan;

/// Command-line options of `camsim bench`.
#[derive(clap::Args, Debug)]
#[command(mut_arg("json", |a| a.help("Print JSON: {\"runs\": [...], ...}")))]
#[command(mut_arg("plot", |a| a.help("Write error_vs_evals.png, error_vs_time.png and error_vs_cpu_time.png (log-log) into DIR (created if missing; its parent must exist; existing plots need --force)")))]
#[command(mut_arg("force", |a| a.help("Replace existing --plot files")))]
pub struct Args {
    /// Cam speed, rpm (500: the reference holds contact, so the errors are reproducible;
    /// at 800 and above it jumps and the impacts make the motion chaotic).
    #[arg(long, default_value_t = 500.0, allow_hyphen_values = true, value_parser = crate::args::rpm)]
    pub rpm: f64,
    /// A few points only (what CI runs): 3 tolerances in f64, one in f32, no jump onset.
    #[arg(long)]
    pub quick: bool,
    /// Timed repetitions of each run, the median reported [default: 5, 3 with --quick].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::args::whole_u32::<1, 100>)]
    pub repeat: Option<u32>,
    /// Run a bench estimated (from its first, reference run) past 1 hour, which is
    /// otherwise refused (`camsim::bench::MAX_BENCH_SECONDS`).
    #[arg(long)]
    pub allow_long: bool,
    /// What it prints and draws.
    #[command(flatten)]
    pub output: OutputArgs,
}

/// Runs the command: the plot directory is checked before anything runs, written to
/// temporaries and committed when every plot was drawn.
pub fn run(args: Args, units: crate::units::Units) -> Result<()> {
    let mut plan = Plan::new(args.output.force);
    let plot_target = match &args.output.plot {
        Some(dir) => Some(plan.dir("--plot", dir, &bench::plot::FILES)?),
        None => None,
    };
    let opts = Options {
        rpm: args.rpm,
        quick: args.quick,
        repeat: args.repeat.unwrap_or(if args.quick { 3 } else { 5 }),
        onset: !args.quick,
        allow_long: args.allow_long,
        progress: true,
    };
    let report = bench::measure(&opts)?;
    if let Some(t) = plot_target {
        let mut out = t.open()?;
        bench::plot::draw_all(&mut out, &report, units)?;
        out.commit()?;
    }
    crate::report::print(&report, args.output.json, units)
}
