//! `camsim design`'s searches: what must be built, found by search on the model.
//!
//! [`mod@spring`]: the smallest return-spring rate (or with a preload search, the shortest
//! preload length) that holds contact with a margin on the theoretical cam, or keeps
//! P(jump) on actual cams at most a limit. [`speed`]: the highest cam speed whose P(jump)
//! on actual cams is at most the limit. [`tolerance`]: the loosest cam tolerance (or the
//! roughest waviness) that does. Each takes a typed spec (no command-line types) and
//! returns a report; the searches are core's [`camsim_core::OnsetSearch`]: bounded, and
//! deterministic (the same cams, seeded, at every step, collected by index whatever the
//! thread count).

pub mod speed;
pub mod spring;
pub mod tolerance;

use std::time::Instant;

use anyhow::Result;

use crate::actual::Cams;
use crate::sim::{self, RunSpec};
use crate::stats::Probability;
use crate::study::montecarlo::Study;
use crate::units;

pub use speed::{mc_search, McSearchReport};
pub use spring::{
    spring, PartReport, Searched, SpringReport, SpringSpec, MAX_PRELOAD_LENGTH, MAX_RATE,
    PRELOAD_RESOLUTION, START_PRELOAD_LENGTH, START_RATE,
};
pub use tolerance::{tolerance_table, NothingPasses, ToleranceRow, ToleranceTable};

/// What a Monte Carlo search (`design speed`, `design tolerance`) is asked: the scene, the
/// actual cams and the pass limit.
#[derive(Clone, Debug)]
pub struct McSpec {
    /// The scene with its overrides, resolved (the operating speed is its rpm).
    pub run: RunSpec,
    /// Largest acceptable P(jump) (its upper 95 % Wilson bound).
    pub p_max: f64,
    /// Actual cams a step (None: the fewest that can pass, [`samples_for`]).
    pub samples: Option<u64>,
    /// Worker threads (None: every core). The answer does not depend on it.
    pub threads: Option<u32>,
    /// The actual cams (the same at every step).
    pub actual: Cams,
    /// `design tolerance` only: search the roughest waviness instead of the tolerance.
    pub waviness: bool,
    /// With `waviness`: the tolerances held, a factor on VI.1's (None: 1).
    pub tolerance_factor: Option<f64>,
    /// CI's quick mode: a coarse bracket and a P(jump) limit at least [`QUICK_P_MAX`].
    pub quick: bool,
    /// The unit family of the report's lines.
    pub units: units::Units,
}

/// The P(jump) limit of a Monte Carlo search (at least [`QUICK_P_MAX`] in the quick mode)
/// and its actual cams a step (`samples`, or the fewest that can pass).
/// A `--p-max` that needs more cams than any study may take is refused
/// ([`crate::study_limits::check_p_max`]).
pub(crate) fn p_max_and_samples(
    p_max: f64,
    quick: bool,
    samples: Option<u64>,
) -> Result<(f64, u64)> {
    use crate::study_limits::{check_p_max, MAX_STUDY_SAMPLES};
    let p = if quick { p_max.max(QUICK_P_MAX) } else { p_max };
    if samples.is_none() {
        let smallest = Probability::of(0, MAX_STUDY_SAMPLES).hi95;
        check_p_max(p, samples_for(p), smallest)?;
    }
    Ok((p, samples.unwrap_or_else(|| samples_for(p))))
}

/// Times one actual cam of `mc` and refuses a search of up to `steps` steps of `n` cams
/// past the study time limit ([`crate::study_limits::check_search`]), before it starts.
pub(crate) fn check_search_time(
    mc: &RunSpec,
    actual: &Cams,
    n: u64,
    steps: u64,
    nthreads: usize,
) -> Result<()> {
    let t = Instant::now();
    // Only its time is wanted: a cam that leaves the model's range is a jump to the search.
    let _ = Study::from_spec(mc.clone(), actual, 1)?.run(&[0], 1, false);
    crate::study_limits::check_search(t.elapsed().as_secs_f64(), n, steps, nthreads)?;
    Ok(())
}

/// The most steps of a search from `start` doubling to `max`, then halving its bracket to
/// `resolution`.
pub(crate) fn search_steps(start: f64, max: f64, resolution: f64) -> u64 {
    let up = (max / start).log2().ceil().max(0.0);
    let down = (max / resolution).log2().ceil().max(0.0);
    (up + down) as u64 + 1
}

/// P(jump) in revolution 2 over `n` actual cams of `mc` (`actual`'s tolerances and seed).
/// When the perfect cam already separates every cam counts as jumping, without its Monte
/// Carlo; a cam thrown out of the model's valid range did not hold contact. Adds the model
/// runs to `runs`.
pub(crate) fn p_jump_on_actual_cams(
    mc: &RunSpec,
    actual: &Cams,
    n: u64,
    nthreads: usize,
    runs: &mut u64,
) -> Result<Probability> {
    let op_rpm = camsim_core::rad_per_s_to_rpm(mc.design.omega0);
    *runs += 1;
    if sim::jumps_at(mc, op_rpm)? {
        return Ok(Probability::of(n, n));
    }
    let study = Study::from_spec(mc.clone(), actual, n)?;
    let indices: Vec<u64> = (0..n).collect();
    *runs += n;
    match study.run(&indices, nthreads, true) {
        Ok(recs) => Ok(Probability::of(
            recs.iter().filter(|r| r.jump()).count() as u64,
            n,
        )),
        Err(e) if format!("{e:#}").contains("left its valid range") => Ok(Probability::of(n, n)),
        Err(e) => Err(e),
    }
}

/// The quick mode's least --p-max (35 actual cams a rate).
pub const QUICK_P_MAX: f64 = 0.1;

/// The fewest samples whose Wilson upper bound with no jump is at most `p`.
pub fn samples_for(p: f64) -> u64 {
    let mut n = 1u64;
    while n < 10_000_000 && Probability::of(0, n).hi95 > p {
        n = (n + 1).max(n + n / 8);
    }
    // Back down to the least such n.
    while n > 1 && Probability::of(0, n - 1).hi95 <= p {
        n -= 1;
    }
    n
}

pub(crate) fn describe(spec: &RunSpec, units: units::Units) -> String {
    format!(
        "{} follower, {} DOFs, rtol {:e}, atol {:e} {}, largest step {} rev, static start, 2 revolutions",
        spec.dofs.follower.name(),
        spec.dofs.set().name(),
        spec.solver.rtol,
        units.given(units::LENGTH, spec.solver.atol),
        units.symbol(units::LENGTH),
        spec.solver.max_step_fraction
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_for_is_the_least_n_whose_empty_upper_bound_is_p() {
        // 0 of n: Wilson's upper end is z²/(n + z²), so n >= z² (1 - p)/p.
        let z2 = crate::stats::Z95 * crate::stats::Z95;
        for p in [0.01, 0.05, 0.1] {
            let n = samples_for(p);
            assert!(Probability::of(0, n).hi95 <= p);
            assert!(Probability::of(0, n - 1).hi95 > p);
            assert_eq!(n, (z2 * (1.0 - p) / p).ceil() as u64, "{p}");
        }
        assert_eq!(samples_for(0.01), 381);
    }
}
