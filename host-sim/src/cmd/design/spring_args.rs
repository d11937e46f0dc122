//! The options of `camsim design spring`.

use crate::args::ActualArgs;
use crate::args::SceneArgs;
use crate::study::design::{MAX_PRELOAD_LENGTH, MAX_RATE};

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
