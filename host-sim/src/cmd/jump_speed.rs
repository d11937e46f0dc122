//! `camsim jump-speed`: the lowest cam speed at which the follower separates from the
//! cam in steady state, found by bisection on the dynamic model, and the speed margin
//! of the current operating point.

use anyhow::{bail, Result};
use serde_json::json;

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

/// Bisection for the jump speed of `spec` between `lo` (must not jump) and `max_rpm`.
pub fn find(spec: &sim::RunSpec, resolution: f64, max_rpm: f64) -> Result<JumpSpeed> {
    if !(resolution.is_finite() && resolution > 0.0) {
        bail!("--resolution {resolution}: must be positive and finite (rpm)");
    }
    if !(max_rpm.is_finite() && max_rpm > 0.0) {
        bail!("--max-rpm {max_rpm}: must be positive and finite");
    }
    let mut spec = spec.clone();
    spec.revolutions = 2;
    let mut sims = 0;
    let mut jumps = |rpm: f64| -> Result<bool> {
        sims += 1;
        sim::jumps_at(&spec, rpm)
    };
    // Bracket: start from a low speed that must hold contact, double until separation.
    let mut lo = 50.0_f64.min(max_rpm / 2.0);
    if jumps(lo)? {
        bail!("the follower separates already at {lo} rpm: check the spring and preload");
    }
    let mut hi = lo * 2.0;
    loop {
        if hi >= max_rpm {
            hi = max_rpm;
            if !jumps(hi)? {
                return Ok(JumpSpeed {
                    jump_rpm: None,
                    no_jump_rpm: hi,
                    simulations: sims,
                });
            }
            break;
        }
        if jumps(hi)? {
            break;
        }
        lo = hi;
        hi *= 2.0;
    }
    while hi - lo > resolution {
        let mid = 0.5 * (lo + hi);
        if jumps(mid)? {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Ok(JumpSpeed {
        jump_rpm: Some(hi),
        no_jump_rpm: lo,
        simulations: sims,
    })
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
