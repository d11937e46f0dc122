//! `camsim tolerance-study`: the grid of VI.4.1 (Table VI.2) on the thesis's more stable
//! program (4-5-6-7 rise, modified trapezoidal return; `scenes/stable-4567-rise.toml`),
//! the cam and roller tolerances by the waviness (`--waviness-fpr`) or by given
//! intervals (`--interval-deg`). The study is [`crate::study::tolerance`], its figures
//! [`crate::plot::tolerance`]; this command reads the arguments into the study's
//! [`Spec`], runs it, prints the report and draws its figures (`--plot DIR`).

use std::path::PathBuf;

use anyhow::Result;
use camsim_core::MotionLaw;

use crate::actual::NormalArg;
use crate::args::OutputArgs;
use crate::sim::RunSpec;
use crate::study::montecarlo;
pub use crate::study::tolerance::*;
use crate::units::{Length, Units};

/// The plots `--plot DIR` writes.
pub const PLOT_FILES: [&str; 2] = ["tolerance_grid.png", "tolerance_response.png"];

/// Command-line options of `camsim tolerance-study`.
#[derive(clap::Args, Debug, Clone)]
#[command(mut_arg("plot", |a| a.help("Write the grid as heat maps (P(jump) with its interval, acceleration RMS) and P(jump), smallest contact force and largest contact stress against the tolerance (p5, p50, p95) into DIR (tolerance_grid.png, tolerance_response.png)")))]
#[command(mut_arg("force", |a| a.help("Replace existing --plot files")))]
pub struct Args {
    /// Scene file (default: the thesis's more stable program, the reference design with
    /// a 4-5-6-7 rise and a modified trapezoidal return).
    pub scene: Option<PathBuf>,
    /// Cam speed, rpm (default: the scene's, 800).
    #[arg(long, allow_negative_numbers = true, value_parser = crate::args::rpm)]
    pub rpm: Option<f64>,
    /// Actual cams per cell (default 8; 1 with --quick).
    #[arg(long, value_parser = crate::args::whole_u64::<1, 100_000>)]
    pub samples: Option<u64>,
    /// The waviness axis, FPR (default 17,39,57; FPR 2n is a single harmonic of n
    /// undulations a revolution): each cell's interval is the one whose profile, drawn
    /// from the master seed at the cell's tolerances, has the FPR nearest.
    #[arg(long, value_name = "N", value_delimiter = ',', value_parser = crate::args::whole_u32::<2, 2000>, conflicts_with = "interval_deg")]
    pub waviness_fpr: Vec<u32>,
    /// Profile point intervals, degrees, instead of the waviness axis (each a whole
    /// number of intervals a revolution).
    #[arg(long, value_name = "DEG", value_delimiter = ',', value_parser = crate::actual::interval_deg)]
    pub interval_deg: Vec<f64>,
    /// Camshaft-bearing and eccentricity tolerance, ± in (kept at VI.1's 0.001 in every
    /// cell), or with its unit (mm).
    #[arg(long, value_name = "IN", allow_negative_numbers = true, value_parser = crate::args::tolerance_in)]
    pub eccentricity_tolerance: Option<f64>,
    /// Master seed (the same in every cell).
    #[arg(long, value_parser = crate::args::seed)]
    pub seed: Option<u64>,
    /// Normal deviates.
    #[arg(long, value_enum, default_value_t = NormalArg::Sum12)]
    pub normal: NormalArg,
    /// Quick mode: one cam per cell, the vertical scene.
    #[arg(long)]
    pub quick: bool,
    /// Worker threads (default: every core). The result does not depend on it.
    #[arg(long, value_parser = crate::args::whole_u32::<1, 1024>)]
    pub threads: Option<u32>,
    /// What it prints and draws.
    #[command(flatten)]
    pub output: OutputArgs,
}

/// The study's run: the scene (or the thesis's more stable program) at `--rpm`,
/// revolution [`montecarlo::REVOLUTION`], the vertical model with `--quick`.
fn base_spec(args: &Args) -> Result<RunSpec> {
    let mut spec = match &args.scene {
        Some(p) => crate::scene::load(p)?,
        None => {
            let mut s = RunSpec::reference();
            s.design.program = camsim_core::CamProgram::with_laws(
                MotionLaw::Poly4567,
                MotionLaw::ModifiedTrapezoidal,
            );
            s
        }
    };
    if let Some(r) = args.rpm {
        spec.design.set_speed_rpm(r)?;
    }
    spec.revolutions = montecarlo::REVOLUTION;
    if args.quick {
        spec.dofs.horizontal = false;
    }
    spec.design.validate()?;
    Ok(spec)
}

/// The waviness axis: the intervals given, or the FPRs asked (default [`WAVINESS_FPR`]).
fn waviness_axis(args: &Args) -> Vec<Column> {
    if !args.interval_deg.is_empty() {
        args.interval_deg
            .iter()
            .map(|&d| Column::IntervalDeg(d))
            .collect()
    } else if !args.waviness_fpr.is_empty() {
        args.waviness_fpr.iter().map(|&f| Column::Fpr(f)).collect()
    } else {
        WAVINESS_FPR.iter().map(|&f| Column::Fpr(f)).collect()
    }
}

/// The study's spec from the arguments.
fn spec(args: &Args) -> Result<Spec> {
    let reference = camsim_core::Tolerances::<f64>::reference();
    Ok(Spec {
        run: base_spec(args)?,
        samples: args.samples.unwrap_or(if args.quick { 1 } else { 8 }),
        columns: waviness_axis(args),
        eccentricity_tolerance: Length::inch(
            args.eccentricity_tolerance
                .unwrap_or(reference.eccentricity),
        ),
        seed: args.seed,
        normal: args.normal,
        quick: args.quick,
        threads: montecarlo::threads(args.threads),
    })
}

/// Runs the grid and draws its figures (`--plot DIR`, in `units`).
pub fn report(args: &Args, units: Units) -> Result<ToleranceReport> {
    let t0 = std::time::Instant::now();
    let spec = spec(args)?;
    let mut plan = crate::output::Plan::new(args.output.force);
    if let Some(p) = &args.scene {
        plan.input("scene file", p);
    }
    let plot_target = match &args.output.plot {
        Some(dir) => Some(plan.dir("--plot", dir, &PLOT_FILES)?),
        None => None,
    };
    let mut report = crate::study::tolerance::report(&spec)?;
    if let Some(t) = plot_target {
        let mut dir = t.open()?;
        let fig = crate::plot::tolerance::grid(&report, units);
        crate::figure::draw(&mut dir, PLOT_FILES[0], &fig, units)?;
        let fig = crate::plot::tolerance::response(&report, units);
        crate::figure::draw(&mut dir, PLOT_FILES[1], &fig, units)?;
        dir.commit()?;
    }
    report.wall_s = t0.elapsed().as_secs_f64();
    Ok(report)
}

/// Runs the command.
pub fn run(args: Args, units: Units) -> Result<()> {
    crate::report::print(&report(&args, units)?, args.output.json, units)
}
