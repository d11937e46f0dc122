//! `camsim compare`: the method comparison of VI.4.2 ([`crate::study::compare`], which
//! holds the study, its report and the report's text). This command reads the arguments
//! into the study's [`Spec`], runs it, prints the report and draws its figures
//! ([`crate::plot::compare`]).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Result;
use camsim_core::Start;

use crate::args::ActualArgs;
use crate::args::OutputArgs;
use crate::output::{AtomicDir, Plan};
use crate::sim::RunSpec;
pub use crate::study::compare::*;
use crate::units::Units;

/// The plots `--plot DIR` writes.
pub const PLOT_FILES: [&str; 2] = ["rankings.png", "responses.png"];

/// Command-line options of `camsim compare`.
#[derive(clap::Args, Debug, Clone, Default)]
#[command(mut_arg("actual", |a| a.hide(true)))]
#[command(mut_arg("plot", |a| a.help("Write PNG plots (the rankings, and the responses of a few laws) into DIR")))]
#[command(mut_arg("force", |a| a.help("Replace existing --plot files")))]
pub struct Args {
    /// Scene file whose program's rises and returns take each law in turn (the
    /// reference design if omitted).
    pub scene: Option<PathBuf>,
    /// Cam speed, rpm (default: the scene's, 800 for the reference).
    #[arg(long, allow_negative_numbers = true, value_parser = crate::args::rpm)]
    pub rpm: Option<f64>,
    /// Quick mode for CI: the vertical scene (the horizontal motion does not feed back
    /// into the vertical chain or the drive; docs/MODEL.md §9).
    #[arg(long)]
    pub quick: bool,
    /// Worker threads (default: every core). The result does not depend on it.
    #[arg(long, value_parser = crate::args::whole_u32::<1, 1024>)]
    pub threads: Option<u32>,
    /// The actual cam (sample 0 of --seed): always run beside the theoretical one.
    #[command(flatten)]
    pub actual: ActualArgs,
    /// What it prints and draws.
    #[command(flatten)]
    pub output: OutputArgs,
}

/// The scene every law starts from.
fn base_spec(args: &Args) -> Result<RunSpec> {
    let mut spec = match &args.scene {
        Some(p) => crate::scene::load(p)?,
        None => RunSpec::reference(),
    };
    if let Some(r) = args.rpm {
        spec.design.set_speed_rpm(r)?;
    }
    // Cycle I is measured from the thesis's start (its start-up shock).
    spec.solver.start = Start::Thesis;
    spec.revolutions = 2;
    if args.quick {
        spec.dofs.horizontal = false;
    }
    Ok(spec)
}

/// The study's spec from the arguments.
pub fn spec(args: &Args) -> Result<Spec> {
    args.actual.refuse_actual_flag("compare")?;
    let base = base_spec(args)?;
    // One interval for every law: the one the scene's own program gets.
    let mut actual = args.actual.cams().resolve(&base.design)?;
    actual.actual = true;
    Ok(Spec {
        base,
        actual,
        quick: args.quick,
        threads: crate::study::montecarlo::threads(args.threads),
    })
}

/// The study's report for `args` (its figures are [`run`]'s).
pub fn report(args: &Args) -> Result<CompareReport> {
    let t0 = Instant::now();
    let mut report = crate::study::compare::report(&spec(args)?)?;
    report.wall_s = t0.elapsed().as_secs_f64();
    Ok(report)
}

/// Runs the command: the study, its figures if asked (the files named before it
/// runs), the report printed in `units`.
pub fn run(args: Args, units: Units) -> Result<()> {
    let t0 = Instant::now();
    let spec = spec(&args)?;
    let mut plan = Plan::new(args.output.force);
    if let Some(p) = &args.scene {
        plan.input("scene file", p);
    }
    let plot_target = match &args.output.plot {
        Some(dir) => Some(plan.dir("--plot", dir, &PLOT_FILES)?),
        None => None,
    };
    let mut report = crate::study::compare::report(&spec)?;
    if let Some(t) = plot_target {
        let mut dir = t.open()?;
        draw(&mut dir, &report, &spec, units)?;
        dir.commit()?;
    }
    report.wall_s = t0.elapsed().as_secs_f64();
    crate::report::print(&report, args.output.json, units)
}

/// Draws [`PLOT_FILES`]: the rankings, then the responses of the laws
/// [`response_traces`] picks.
fn draw(dir: &mut AtomicDir, report: &CompareReport, spec: &Spec, units: Units) -> Result<()> {
    use crate::plot::compare::{rankings, responses};
    let ranks = rankings(&report.laws, &report.not_workable, units);
    crate::figure::draw(dir, PLOT_FILES[0], &ranks, units)?;
    let traces = response_traces(&report.laws, spec)?;
    crate::figure::draw(dir, PLOT_FILES[1], &responses(&traces), units)
}
