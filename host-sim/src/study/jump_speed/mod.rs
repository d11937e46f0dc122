//! The jump-onset search of `camsim jump-speed` (and of `run --margin`, `design` and
//! `sensitivity`): the lowest cam speed at which the follower separates in steady state,
//! by bisection on the dynamic model. [`report()`] is `jump-speed` on the theoretical
//! cam (its report in [`mod@report`], its text in [`text`]); [`actual`] is
//! `jump-speed --actual`, the onset of machined cams as a distribution over samples.

use anyhow::{bail, Result};
use camsim_core::{Onset, OnsetSearch};

use crate::sim;

pub mod actual;
pub mod report;
pub mod text;

pub use report::JumpSpeedReport;
pub use text::render_text;

/// What `camsim jump-speed` computes on the theoretical cam.
#[derive(Clone, Debug)]
pub struct Spec {
    /// The scene's run (its start static unless given).
    pub run: sim::RunSpec,
    /// Bisection resolution, rpm.
    pub resolution_rpm: f64,
    /// Highest speed searched, rpm.
    pub max_rpm: f64,
}

/// The jump speed of `spec`'s theoretical cam ([`find`]) and the margin of the scene's
/// operating speed to it.
pub fn report(spec: &Spec) -> Result<JumpSpeedReport> {
    let op_rpm = camsim_core::rad_per_s_to_rpm(spec.run.design.omega0);
    let t0 = std::time::Instant::now();
    let r = find(&spec.run, spec.resolution_rpm, spec.max_rpm)?;
    let wall_ms = t0.elapsed().as_secs_f64() * 1e3;
    Ok(JumpSpeedReport::new(
        &r,
        op_rpm,
        spec.resolution_rpm,
        wall_ms,
    ))
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

/// The default and largest `--max-rpm`: the top of a cam speed's plausibility range
/// ([`camsim_core::key::SPEED_RPM`]).
pub const MAX_RPM: f64 = camsim_core::key::SPEED_RPM.max;

/// The jump speed of `spec` to `resolution` rpm, up to `max_rpm`: core's [`OnsetSearch`]
/// (doubling from [`START_RPM`], then bisection) with [`sim::jumps_at`] (two revolutions,
/// stopped at the first separation in the second) as the predicate.
///
/// A simulation that ends in an error after the follower has left the cam (the model
/// leaving its valid range, [`camsim_core::Error::OutOfModel`], or the solver failing)
/// counts as separation: the follower did not hold contact at that speed. One that ends
/// in an error with the follower on the cam ends the search with that error.
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
    if !camsim_core::key::SPEED_RPM.contains(max_rpm) {
        bail!("--max-rpm {max_rpm}: {}", camsim_core::key::SPEED_RPM.rule);
    }
    let lowest = camsim_core::key::SPEED_RPM.min;
    if max_rpm < 2.0 * lowest {
        bail!("--max-rpm {max_rpm}: must be at least {} rpm (the search starts below it, at no less than {lowest} rpm)", 2.0 * lowest);
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
