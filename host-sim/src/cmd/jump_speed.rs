//! `camsim jump-speed`: the lowest cam speed at which the follower separates from the
//! cam in steady state, found by bisection on the dynamic model, and the speed margin
//! of the current operating point. The study is [`crate::study::jump_speed`]; this
//! command reads the arguments into its spec and prints the report.

use anyhow::Result;

use crate::args::{spec_from, SceneArgs};
use crate::study::jump_speed::{self, actual, Spec};
pub use crate::study::jump_speed::{
    find, find_with, render_text, JumpSpeed, JumpSpeedReport, MAX_RPM, START_RPM,
};
use crate::units::Units;

/// Command-line options of `camsim jump-speed`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The scene and its overrides (`--start` defaults to "static" here).
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Bisection resolution, rpm (positive, at most 10 000; below the numbers' spacing
    /// the bisection ends on neighbouring speeds).
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true, value_parser = crate::args::resolution_rpm)]
    pub resolution: f64,
    /// Highest speed searched, rpm (at most 10 000, the plausibility range of a cam speed).
    #[arg(long, default_value_t = MAX_RPM, allow_hyphen_values = true, value_parser = crate::args::rpm)]
    pub max_rpm: f64,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
    /// Machined cams instead of the theoretical (`--actual` and its options): the onset
    /// as a distribution over samples (`jump_speed_actual`).
    #[command(flatten)]
    pub actual: crate::args::ActualArgs,
    /// With --actual: machined cams drawn, samples 0 to N-1 of --seed (default 20).
    #[arg(long, value_parser = crate::args::whole_u32::<1, 10000>)]
    pub samples: Option<u32>,
    /// With --actual: worker threads (default: every core); the result does not depend on it.
    #[arg(long, value_parser = crate::args::whole_u32::<1, 1024>)]
    pub threads: Option<u32>,
}

/// Runs the command.
pub fn run(args: Args, units: Units) -> Result<()> {
    let spec = spec_of(&args)?;
    if args.actual.actual {
        let threads = crate::study::montecarlo::threads(args.threads);
        let samples = args.samples.unwrap_or(actual::DEFAULT_SAMPLES);
        let report = actual::study(
            &spec.run,
            &args.actual.cams(),
            samples,
            threads,
            spec.resolution_rpm,
            spec.max_rpm,
        )?;
        return crate::report::print(&report, args.json, units);
    }
    args.actual.ensure_actual_if_options()?;
    theoretical_only(&args)?;
    crate::report::print(&jump_speed::report(&spec)?, args.json, units)
}

/// The study's spec: the scene (`--start` static unless given), the resolution and the
/// highest speed searched.
fn spec_of(args: &Args) -> Result<Spec> {
    let mut scene = args.scene.clone();
    scene.start.get_or_insert(crate::args::StartArg::Static);
    Ok(Spec {
        run: spec_from(&scene)?,
        resolution_rpm: args.resolution,
        max_rpm: args.max_rpm,
    })
}

/// Refuses `--samples` and `--threads` on the theoretical cam (they count actual cams).
fn theoretical_only(args: &Args) -> Result<()> {
    let given: Vec<String> = [("--samples", args.samples), ("--threads", args.threads)]
        .iter()
        .filter_map(|(name, v)| v.map(|v| format!("{name} {v}")))
        .collect();
    if !given.is_empty() {
        return Err(crate::args::usage(format!(
            "{} counts actual cams: add --actual (without it the theoretical cam runs)",
            given.join(", ")
        )));
    }
    Ok(())
}
