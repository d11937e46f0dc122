//! `camsim sensitivity`: the sensitivity study of VI.4.3 (Tables VI.11-VI.12) and, beyond
//! the thesis, every design key's elasticity ([`crate::study::sensitivity`], which holds
//! the study, its report and the report's text). This command reads the arguments into
//! the study's [`Spec`], runs it, prints the report and draws its figure.

use std::path::PathBuf;

use anyhow::{anyhow, Result};

use crate::args::ActualArgs;
use crate::args::OutputArgs;
use crate::output::Plan;
use crate::sim::RunSpec;
pub use crate::study::sensitivity::*;

/// The plot `--plot DIR` writes.
pub const PLOT_FILES: [&str; 1] = ["sensitivity.png"];

/// Command-line options of `camsim sensitivity`.
#[derive(clap::Args, Debug, Clone, Default)]
#[command(mut_arg("actual", |a| a.hide(true)))]
#[command(mut_arg("plot", |a| a.help("Write a tornado-style bar chart (sensitivity.png) into DIR")))]
#[command(mut_arg("force", |a| a.help("Replace an existing --plot file")))]
pub struct Args {
    /// Scene file (the reference design if omitted).
    pub scene: Option<PathBuf>,
    /// Cam speed, rpm, 1-10 000 (default: the scene's, 800 for the reference).
    #[arg(long, allow_hyphen_values = true, value_parser = crate::args::rpm)]
    pub rpm: Option<f64>,
    /// Quick mode for CI: the vertical scene, changes of ±30 % only, and with --per-key
    /// a 1 rpm onset resolution.
    #[arg(long)]
    pub quick: bool,
    /// Also every design key's elasticity (d ln output / d ln key, central differences
    /// at ±1 %) on the five outputs and on the jump-onset speed, ranked (theoretical cam).
    #[arg(long)]
    pub per_key: bool,
    /// Worker threads (default: every core). The result does not depend on it.
    #[arg(long, value_parser = crate::args::whole_u32::<1, 1024>)]
    pub threads: Option<u32>,
    /// The actual cam (sample 0 of --seed): both cams always run.
    #[command(flatten)]
    pub actual: ActualArgs,
    /// What it prints and draws.
    #[command(flatten)]
    pub output: OutputArgs,
}

/// The study's run: the scene (or the reference) at `--rpm`, revolution [`REVOLUTION`],
/// the vertical model with `--quick`.
fn base_spec(args: &Args) -> Result<RunSpec> {
    let mut spec = match &args.scene {
        Some(p) => crate::scene::load(p)?,
        None => RunSpec::reference(),
    };
    if let Some(r) = args.rpm {
        spec.design.set_speed_rpm(r).map_err(|e| match e {
            camsim_core::Error::InvalidParameter { rule, .. } => anyhow!("--rpm {r}: {rule}"),
            other => other.into(),
        })?;
    }
    spec.revolutions = REVOLUTION;
    if args.quick {
        spec.dofs.horizontal = false;
    }
    spec.design.validate()?;
    Ok(spec)
}

/// Runs the study (its figure drawn in `units`).
pub fn report(args: &Args, units: crate::units::Units) -> Result<SensitivityReport> {
    args.actual.refuse_actual_flag("sensitivity")?;
    let t0 = std::time::Instant::now();
    let run = base_spec(args)?;
    let mut plan = Plan::new(args.output.force);
    if let Some(p) = &args.scene {
        plan.input("scene file", p);
    }
    let plot_target = match &args.output.plot {
        Some(dir) => Some(plan.dir("--plot", dir, &PLOT_FILES)?),
        None => None,
    };
    let spec = Spec {
        run,
        actual: args.actual.cams(),
        quick: args.quick,
        per_key: args.per_key,
        threads: crate::study::montecarlo::threads(args.threads),
    };
    let mut report = crate::study::sensitivity::report(&spec)?;
    report.wall_s = t0.elapsed().as_secs_f64();
    if let Some(t) = plot_target {
        crate::report::ensure_finite(&report)?;
        let mut dir = t.open()?;
        let fig = crate::plot::sensitivity::figure(&report, units);
        crate::figure::draw(&mut dir, PLOT_FILES[0], &fig, units)?;
        dir.commit()?;
    }
    Ok(report)
}

/// Runs the command.
pub fn run(args: Args, units: crate::units::Units) -> Result<()> {
    crate::report::print(&report(&args, units)?, args.output.json, units)
}
