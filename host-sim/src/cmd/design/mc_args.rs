//! The options of `camsim design`'s Monte Carlo searches (`design speed`, `design
//! tolerance`).

use crate::args::ActualArgs;
use crate::args::SceneArgs;

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
