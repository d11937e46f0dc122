//! `camsim jump-speed`: the lowest cam speed at which the follower separates from the
//! cam in steady state, found by bisection on the dynamic model, and the speed margin
//! of the current operating point.

use anyhow::{bail, Result};
use serde_json::json;

use camsim_core::{Onset, OnsetSearch};

use crate::cmd::run as run_cmd;
use crate::sim;

/// Command-line options of `camsim jump-speed`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The scene and its overrides (`--start` defaults to "static" here).
    #[command(flatten)]
    pub scene: run_cmd::SceneArgs,
    /// Bisection resolution, rpm.
    #[arg(long, default_value_t = 1.0)]
    pub resolution: f64,
    /// Highest speed searched, rpm.
    #[arg(long, default_value_t = 20000.0)]
    pub max_rpm: f64,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// Result of the search.
#[derive(Debug, Clone, Copy)]
pub struct JumpSpeed {
    /// Lowest speed with steady-state separation, rpm (None: none up to max_rpm).
    pub jump_rpm: Option<f64>,
    /// Highest speed checked without separation, rpm.
    pub no_jump_rpm: f64,
    /// Simulations run.
    pub simulations: u32,
}

/// Speed the bracket starts from (halved if `max_rpm` is below twice it), rpm: slow
/// enough that contact must hold there.
pub const START_RPM: f64 = 50.0;

/// The jump speed of `spec` to `resolution` rpm, up to `max_rpm`: core's [`OnsetSearch`]
/// (doubling from [`START_RPM`], then bisection) with [`sim::jumps_at`] (two revolutions,
/// stopped at the first separation in the second) as the predicate.
pub fn find(spec: &sim::RunSpec, resolution: f64, max_rpm: f64) -> Result<JumpSpeed> {
    let mut spec = spec.clone();
    spec.revolutions = 2;
    find_with(resolution, max_rpm, |rpm| sim::jumps_at(&spec, rpm))
}

/// [`find`] with any "separates at this speed?" predicate (counted in `simulations`).
pub fn find_with(
    resolution: f64,
    max_rpm: f64,
    mut jumps: impl FnMut(f64) -> Result<bool>,
) -> Result<JumpSpeed> {
    if !(resolution.is_finite() && resolution > 0.0) {
        bail!("--resolution {resolution}: must be positive and finite (rpm)");
    }
    if !(max_rpm.is_finite() && max_rpm > 0.0) {
        bail!("--max-rpm {max_rpm}: must be positive and finite");
    }
    let search = OnsetSearch::new(START_RPM.min(max_rpm / 2.0), Some(2.0), max_rpm, resolution)?;
    let mut simulations = 0;
    let onset = search.find(|rpm| {
        simulations += 1;
        jumps(rpm)
    })?;
    match onset {
        Onset::AtStart(lo) => {
            bail!("the follower separates already at {lo} rpm: check the spring and preload")
        }
        Onset::Bracketed { below, at } => Ok(JumpSpeed {
            jump_rpm: Some(at),
            no_jump_rpm: below,
            simulations,
        }),
        Onset::Beyond(max) => Ok(JumpSpeed {
            jump_rpm: None,
            no_jump_rpm: max,
            simulations,
        }),
    }
}

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    let mut scene = args.scene.clone();
    scene.start.get_or_insert_with(|| "static".into());
    let spec = run_cmd::spec_from(&scene)?;
    let op_rpm = camsim_core::rad_per_s_to_rpm(spec.design.omega0);
    let t0 = std::time::Instant::now();
    let r = find(&spec, args.resolution, args.max_rpm)?;
    let wall_ms = t0.elapsed().as_secs_f64() * 1e3;
    let margin = r.jump_rpm.map(|j| j - op_rpm);
    if args.json {
        let v = json!({
            "jump_rpm": r.jump_rpm,
            "no_jump_rpm": r.no_jump_rpm,
            "operating_rpm": op_rpm,
            "margin_rpm": margin,
            "margin_percent": margin.map(|m| 100.0 * m / op_rpm),
            "resolution_rpm": args.resolution,
            "simulations": r.simulations,
            "wall_ms": wall_ms,
        });
        println!("{v}");
        return Ok(());
    }
    match r.jump_rpm {
        Some(j) => {
            println!(
                "jump speed: {j:.1} rpm (steady-state separation; contact holds at {:.1} rpm)",
                r.no_jump_rpm
            );
            let m = j - op_rpm;
            println!(
                "operating point {op_rpm:.1} rpm: margin {m:+.1} rpm ({:+.1} %){}",
                100.0 * m / op_rpm,
                if m <= 0.0 {
                    "  -- the follower JUMPS at the operating speed"
                } else {
                    ""
                }
            );
        }
        None => println!("no jump up to {:.0} rpm", r.no_jump_rpm),
    }
    println!(
        "{} simulations of 2 revolutions, {:.0} ms",
        r.simulations, wall_ms
    );
    Ok(())
}
