//! `camsim jump-speed`: the lowest cam speed at which the follower separates from the
//! cam in steady state, found by bisection on the dynamic model, and the speed margin
//! of the current operating point.

use anyhow::Result;
use serde::Serialize;

use crate::args::{spec_from, SceneArgs};
use crate::report::Report;
pub use crate::study::jump_speed::{find, find_with, JumpSpeed, MAX_RPM, START_RPM};
use crate::study::jump_speed_actual;

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

/// What `camsim jump-speed` prints: the text output and `--json` are both this report.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct JumpSpeedReport {
    /// Lowest speed with steady-state separation, rpm (absent: none up to `--max-rpm`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump_rpm: Option<f64>,
    /// Highest speed checked without separation, rpm.
    pub no_jump_rpm: f64,
    /// The scene's operating speed, rpm.
    pub operating_rpm: f64,
    /// Jump speed minus operating speed, rpm (absent without a jump speed).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub margin_rpm: Option<f64>,
    /// The margin in percent of the operating speed (absent without a jump speed).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub margin_percent: Option<f64>,
    /// Bisection resolution asked for, rpm.
    pub resolution_rpm: f64,
    /// Simulations run.
    pub simulations: u32,
    /// Wall time of the search, ms.
    pub wall_ms: f64,
}

impl JumpSpeedReport {
    /// The report of a search result at operating speed `operating_rpm`.
    pub fn new(r: &JumpSpeed, operating_rpm: f64, resolution_rpm: f64, wall_ms: f64) -> Self {
        let margin_rpm = r.jump_rpm.map(|j| j - operating_rpm);
        Self {
            jump_rpm: r.jump_rpm,
            no_jump_rpm: r.no_jump_rpm,
            operating_rpm,
            margin_rpm,
            margin_percent: margin_rpm.map(|m| 100.0 * m / operating_rpm),
            resolution_rpm,
            simulations: r.simulations,
            wall_ms,
        }
    }
}

/// The human-readable output.
pub fn render_text(r: &JumpSpeedReport) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let op = r.operating_rpm;
    match (r.jump_rpm, r.margin_rpm, r.margin_percent) {
        (Some(j), Some(m), Some(pct)) => {
            let below = r.no_jump_rpm;
            let _ = writeln!(
                out,
                "jump speed: {j:.1} rpm (steady-state separation; contact holds at {below:.1} rpm: the onset lies between)",
            );
            let jumps = if m <= 0.0 {
                "  -- the follower JUMPS at the operating speed"
            } else {
                ""
            };
            // A bracket wider than 1 % of the operating speed is stated as the range it
            // is: the margin is only known to lie between its ends.
            if j - below > 0.01 * op {
                let (m_lo, pct_lo) = (below - op, 100.0 * (below - op) / op);
                let _ = writeln!(
                    out,
                    "operating point {op:.1} rpm: margin between {m_lo:+.1} and {m:+.1} rpm ({pct_lo:+.1} % to {pct:+.1} %; a smaller --resolution narrows it){jumps}"
                );
            } else {
                let _ = writeln!(
                    out,
                    "operating point {op:.1} rpm: margin {m:+.1} rpm ({pct:+.1} %){jumps}"
                );
            }
        }
        _ => {
            let _ = writeln!(out, "no jump up to {:.0} rpm", r.no_jump_rpm);
        }
    }
    let _ = writeln!(
        out,
        "{} simulations of 2 revolutions, {:.0} ms",
        r.simulations, r.wall_ms
    );
    out
}

impl Report for JumpSpeedReport {
    fn text(&self, _units: crate::units::Units) -> String {
        render_text(self)
    }
    fn json(&self) -> serde_json::Result<String> {
        serde_json::to_string(self)
    }
}

/// Runs the command.
pub fn run(args: Args, units: crate::units::Units) -> Result<()> {
    let mut scene = args.scene.clone();
    scene.start.get_or_insert(crate::args::StartArg::Static);
    let spec = spec_from(&scene)?;
    if args.actual.actual {
        let threads = crate::study::montecarlo::threads(args.threads);
        let samples = args.samples.unwrap_or(jump_speed_actual::DEFAULT_SAMPLES);
        let report = jump_speed_actual::study(
            &spec,
            &args.actual.cams(),
            samples,
            threads,
            args.resolution,
            args.max_rpm,
        )?;
        return crate::report::print(&report, args.json, units);
    }
    args.actual.ensure_actual_if_options()?;
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
    let op_rpm = camsim_core::rad_per_s_to_rpm(spec.design.omega0);
    let t0 = std::time::Instant::now();
    let r = find(&spec, args.resolution, args.max_rpm)?;
    let wall_ms = t0.elapsed().as_secs_f64() * 1e3;
    let report = JumpSpeedReport::new(&r, op_rpm, args.resolution, wall_ms);
    crate::report::print(&report, args.json, units)
}
