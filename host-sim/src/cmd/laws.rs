//! `camsim laws`: peak dimensionless coefficients of every Appendix A motion law for a
//! unit rise over a unit angle, and the largest pressure angle each gives on the
//! reference cam. The study and its figure are [`crate::study::laws`]; this command
//! prints the report and draws the figure.

pub use crate::study::laws::*;

/// Command-line options.
#[derive(clap::Args, Debug)]
#[command(mut_arg("json", |a| a.help("Print JSON instead of a table")))]
#[command(mut_arg("plot", |a| a.help("Draw every law's normalized S, V, A and J against u = θ/β on one figure (laws.png) into DIR (created if missing; its parent must exist)")))]
#[command(mut_arg("force", |a| a.help("Replace an existing --plot file")))]
pub struct Args {
    /// What it prints and draws.
    #[command(flatten)]
    pub output: crate::args::OutputArgs,
}

/// The plot `--plot DIR` writes.
pub const PLOT_FILES: [&str; 1] = ["laws.png"];

/// Runs the command.
pub fn run(args: Args, units: crate::units::Units) -> anyhow::Result<()> {
    if let Some(d) = &args.output.plot {
        let mut plan = crate::output::Plan::new(args.output.force);
        let mut dir = plan.dir("--plot", d, &PLOT_FILES)?.open()?;
        crate::figure::draw(&mut dir, PLOT_FILES[0], &figure(), units)?;
        dir.commit()?;
    }
    crate::report::print(&report(), args.output.json, units)
}
