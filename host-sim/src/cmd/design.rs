//! `camsim design`: what must be built, found by search on the model
//! ([`crate::study::design`]): its options, turned into the study's spec, and the report
//! printed.

use anyhow::Result;

use crate::args::ActualArgs;
use crate::args::SceneArgs;
pub use crate::study::design::spring::{
    MAX_PRELOAD_LENGTH, MAX_RATE, PRELOAD_RESOLUTION, START_PRELOAD_LENGTH, START_RATE,
};
pub use crate::study::design::{
    samples_for, McSearchReport, McSpec, NothingPasses, PartReport, SpringReport, SpringSpec,
    ToleranceRow, ToleranceTable, QUICK_P_MAX,
};

/// Command-line options of `camsim design`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// What to design.
    #[command(subcommand)]
    pub what: What,
}

/// The design searches.
#[derive(clap::Subcommand, Debug)]
pub enum What {
    /// The smallest return-spring rate that holds contact with a margin (theoretical cam),
    /// or with P(jump) <= --p-max on actual cams (--actual).
    Spring(SpringArgs),
    /// The highest cam speed at which P(jump) on actual cams is <= --p-max (its upper 95 %
    /// bound), beside the theoretical cam's jump onset.
    Speed(McArgs),
    /// The loosest cam and roller tolerance (a factor on VI.1's ±0.0005/±0.0001 in) at
    /// which P(jump) on actual cams at the operating speed is <= --p-max.
    Tolerance(McArgs),
}

/// Command-line options of the Monte Carlo searches (`design speed`, `design tolerance`).
#[derive(clap::Args, Debug)]
#[command(mut_arg("actual", |a| a.hide(true)))]
pub struct McArgs {
    /// The scene and its overrides (the operating speed is its --rpm).
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Largest acceptable P(jump) (its upper 95 % Wilson bound) (0-1).
    #[arg(long, default_value_t = 0.01, allow_hyphen_values = true, value_parser = crate::args::unit_interval)]
    pub p_max: f64,
    /// Actual cams a step (default: the fewest whose upper bound can be at most --p-max
    /// with no jump, 381 for 0.01).
    #[arg(long, value_parser = crate::args::whole_u64::<1, 1_000_000>)]
    pub samples: Option<u64>,
    /// Worker threads (default: every core). The answer does not depend on it.
    #[arg(long, value_parser = crate::args::whole_u32::<1, 1024>)]
    pub threads: Option<u32>,
    /// The actual cams, as montecarlo's (the same cams at every step; the waviness
    /// matters: the tolerance that passes depends strongly on it). `design tolerance`
    /// searches the cam tolerance, holds the roller and eccentricity tolerances as given,
    /// and takes a list of FPRs.
    #[command(flatten)]
    pub actual: ActualArgs,
    /// `design tolerance` only: search the roughest waviness instead, the highest FPR
    /// (the shortest waves: the acceleration a wave imposes grows as FPR², docs/MODEL.md
    /// §9.6) that passes at the tolerance --tolerance-factor.
    #[arg(long, conflicts_with = "waviness_fpr")]
    pub waviness: bool,
    /// With --waviness: the tolerances held, a factor on VI.1's (default 1).
    #[arg(long, value_name = "FACTOR", allow_hyphen_values = true, value_parser = tolerance_factor, requires = "waviness")]
    pub tolerance_factor: Option<f64>,
    /// CI's quick mode: a coarse bracket and --p-max at least 0.1 (35 cams a step).
    #[arg(long)]
    pub quick: bool,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// `--tolerance-factor`: positive, and VI.1's largest tolerance times it within the
/// tolerance options' own limit ([`crate::args::MAX_TOLERANCE_IN`]): a larger factor
/// asks for a different cam, not a tolerance (issue 33: `1e300` reached the profile
/// builder and was reported as a waviness).
fn tolerance_factor(s: &str) -> Result<f64, String> {
    let r = camsim_core::Tolerances::<f64>::reference();
    let largest = r.cam.max(r.roller).max(r.eccentricity);
    let max = crate::args::MAX_TOLERANCE_IN / largest;
    match crate::args::positive_finite(s)? {
        x if x <= max => Ok(x),
        _ => Err(format!(
            "must be at most {max} (VI.1's largest tolerance, {largest} in, times {max} is the tolerances' limit of {} in: a larger error is a different cam)",
            crate::args::MAX_TOLERANCE_IN
        )),
    }
}

/// Command-line options of `camsim design spring`.
#[derive(clap::Args, Debug)]
#[command(mut_arg("actual", |a| a.help("Judge on actual cams instead (made by the options below, as montecarlo's; the same cams at every rate): the upper 95 % bound of P(jump) at the operating speed must be at most --p-max")))]
pub struct SpringArgs {
    /// The scene and its overrides (the operating speed is its --rpm).
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Speed margin on the theoretical cam, percent: contact must hold at (1 + margin/100)
    /// times the operating speed (0-100).
    #[arg(long, default_value_t = 15.0, allow_hyphen_values = true, value_parser = margin_percent)]
    pub margin: f64,
    /// The actual cams of --actual.
    #[command(flatten)]
    pub actual: ActualArgs,
    /// Largest acceptable P(jump) (its upper 95 % Wilson bound), with --actual (0-1).
    #[arg(long, default_value_t = 0.01, allow_hyphen_values = true, value_parser = crate::args::unit_interval, requires = "actual")]
    pub p_max: f64,
    /// Actual cams per rate, with --actual (default: the fewest whose upper bound can be
    /// at most --p-max with no jump, 381 for 0.01).
    #[arg(long, value_parser = crate::args::whole_u64::<1, 1_000_000>, requires = "actual")]
    pub samples: Option<u64>,
    /// Worker threads (default: every core). The answer does not depend on it.
    #[arg(long, value_parser = crate::args::whole_u32::<1, 1024>)]
    pub threads: Option<u32>,
    /// Bracket width the search stops at, lb/in, or with its unit (0.2N/mm).
    #[arg(long, default_value_t = 1.0, value_name = "LB_PER_IN", allow_hyphen_values = true, value_parser = crate::args::rate_resolution)]
    pub resolution: f64,
    /// Largest rate searched, lb/in, or with its unit (N/mm).
    #[arg(long, default_value_t = MAX_RATE, value_name = "LB_PER_IN", allow_hyphen_values = true, value_parser = crate::args::spring_rate)]
    pub max_rate: f64,
    /// Search the spring's preload length δ_rs instead of its rate: the shortest
    /// compression at assembly (at the scene's or --spring-rate's rate) that passes.
    #[arg(long)]
    pub preload: bool,
    /// Largest preload length searched with --preload, in, or with its unit (mm).
    #[arg(long, default_value_t = MAX_PRELOAD_LENGTH, value_name = "IN", allow_hyphen_values = true, value_parser = crate::args::positive_length, requires = "preload")]
    pub max_preload_length: f64,
    /// CI's quick mode: resolution 10 lb/in (0.1 in with --preload); with --actual,
    /// --p-max at least 0.1 (35 cams).
    #[arg(long)]
    pub quick: bool,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

fn margin_percent(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if (0.0..=100.0).contains(&x) => Ok(x),
        Ok(_) => Err("must be between 0 and 100 (percent)".into()),
        Err(_) => Err("not a number".into()),
    }
}

/// Runs the command.
pub fn run(args: Args, units: crate::units::Units) -> Result<()> {
    match args.what {
        What::Spring(a) => {
            let r = spring(&a, units)?;
            crate::report::print(&r, a.json, units)
        }
        What::Speed(a) => {
            let r = mc_search(&a, true, units)?;
            crate::report::print(&r, a.json, units)
        }
        What::Tolerance(a) => {
            let r = tolerance_table(&a, units)?;
            crate::report::print(&r, a.json, units)
        }
    }
}

impl McArgs {
    /// The search's spec.
    pub fn spec(&self, units: crate::units::Units) -> McSpec {
        McSpec {
            scene: self.scene.clone(),
            p_max: self.p_max,
            samples: self.samples,
            threads: self.threads,
            actual: self.actual.cams(),
            waviness: self.waviness,
            tolerance_factor: self.tolerance_factor,
            quick: self.quick,
            units,
        }
    }
}

impl SpringArgs {
    /// The search's spec.
    pub fn spec(&self, units: crate::units::Units) -> SpringSpec {
        SpringSpec {
            scene: self.scene.clone(),
            margin: self.margin,
            actual: self.actual.cams(),
            p_max: self.p_max,
            samples: self.samples,
            threads: self.threads,
            resolution: self.resolution,
            max_rate: self.max_rate,
            preload: self.preload,
            max_preload_length: self.max_preload_length,
            quick: self.quick,
            units,
        }
    }
}

/// `design spring` ([`crate::study::design::spring()`]).
pub fn spring(args: &SpringArgs, units: crate::units::Units) -> Result<SpringReport> {
    crate::study::design::spring(&args.spec(units))
}

/// `design speed` (`speed`) or a `design tolerance` search
/// ([`crate::study::design::mc_search`]).
pub fn mc_search(args: &McArgs, speed: bool, units: crate::units::Units) -> Result<McSearchReport> {
    crate::study::design::mc_search(&args.spec(units), speed)
}

/// `design tolerance` ([`crate::study::design::tolerance_table`]).
pub fn tolerance_table(args: &McArgs, units: crate::units::Units) -> Result<ToleranceTable> {
    crate::study::design::tolerance_table(&args.spec(units))
}
