//! `camsim design`: what must be built, found by search on the model
//! ([`crate::study::design`]): its options, turned into the study's spec, and the report
//! printed. The options of `design spring` are in design/spring_args.rs, those of the
//! Monte Carlo searches in design/mc_args.rs.

use anyhow::Result;

use crate::args::spec_from;
pub use crate::study::design::*;
use crate::units::Units;

mod mc_args;
mod spring_args;

pub use mc_args::McArgs;
pub use spring_args::SpringArgs;

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

/// Runs the command.
pub fn run(args: Args, units: Units) -> Result<()> {
    match &args.what {
        What::Spring(a) => crate::report::print(&spring(a, units)?, a.json, units),
        What::Speed(a) => crate::report::print(&mc_search(a, true, units)?, a.json, units),
        What::Tolerance(a) => crate::report::print(&tolerance_table(a, units)?, a.json, units),
    }
}

/// `design spring` ([`crate::study::design::spring()`]) on the spec of `args`.
pub fn spring(args: &SpringArgs, units: Units) -> Result<SpringReport> {
    crate::study::design::spring(&spring_spec(args, units)?)
}

/// `design speed` (`speed`) or a `design tolerance` search
/// ([`crate::study::design::mc_search`]).
pub fn mc_search(args: &McArgs, speed: bool, units: Units) -> Result<McSearchReport> {
    crate::study::design::mc_search(&mc_spec(args, units)?, speed)
}

/// `design tolerance` ([`crate::study::design::tolerance_table`]).
pub fn tolerance_table(args: &McArgs, units: Units) -> Result<ToleranceTable> {
    crate::study::design::tolerance_table(&mc_spec(args, units)?)
}

/// The spec of a Monte Carlo search: the scene resolved once.
fn mc_spec(a: &McArgs, units: Units) -> Result<McSpec> {
    Ok(McSpec {
        run: spec_from(&a.scene)?,
        p_max: a.p_max,
        samples: a.samples,
        threads: a.threads,
        actual: a.actual.cams(),
        waviness: a.waviness,
        tolerance_factor: a.tolerance_factor,
        quick: a.quick,
        units,
    })
}

/// The spec of `design spring`: the scene resolved once.
fn spring_spec(a: &SpringArgs, units: Units) -> Result<SpringSpec> {
    Ok(SpringSpec {
        run: spec_from(&a.scene)?,
        margin: a.margin,
        actual: a.actual.cams(),
        p_max: a.p_max,
        samples: a.samples,
        threads: a.threads,
        resolution: a.resolution,
        max_rate: a.max_rate,
        preload: a.preload,
        max_preload_length: a.max_preload_length,
        quick: a.quick,
        units,
    })
}
