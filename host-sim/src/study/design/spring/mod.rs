//! `design spring`: the smallest return-spring rate (at the scene's preload length; its mass
//! follows the rate by the wire-and-coil model, core's `HelicalSpring`) that holds contact
//! with a margin: on the theoretical cam, contact in steady state at `(1 + margin/100)`
//! times the operating speed ([`crate::sim::jumps_at`], the jump predicate of
//! `camsim jump-speed`); on actual cams, the upper end of the 95 % Wilson interval of
//! P(jump) at the operating speed at most the limit (the Monte Carlo of `camsim
//! montecarlo`, on the quasi-static-cantilever follower that docs/RESULTS.md "Reduced
//! scenes" shows adequate on actual cams). With a preload search, the shortest preload
//! length at the rate held. The search doubles from [`START_RATE`], then bisects to the
//! resolution. Then the spring to build: the lightest standard part that passes.
//!
//! The study in parts: the search over the rate or the preload length (search.rs), the
//! part to build and its judgement (part.rs: the wire and coil search of
//! [`crate::study::coil_spring`] and its contact check), the report (report.rs) and its
//! text with the part's scene lines (text.rs).

mod part;
mod report;
mod search;
mod text;

use std::time::Instant;

use anyhow::{bail, Result};
use camsim_core::Start;
use serde::Serialize;

use crate::actual::Cams;
use crate::sim::RunSpec;
use crate::units::Units;

pub use part::{CoilReport, PartReport};
pub use report::SpringReport;
use search::{spring_on_actual_cams, spring_on_theoretical_cam};

/// What `design spring` is asked.
#[derive(Clone, Debug)]
pub struct SpringSpec {
    /// The scene with its overrides, resolved (the operating speed is its rpm).
    pub run: RunSpec,
    /// Speed margin on the theoretical cam, percent.
    pub margin: f64,
    /// The actual cams (judged on them when `actual.actual`).
    pub actual: Cams,
    /// Largest acceptable P(jump) (its upper 95 % Wilson bound), on actual cams.
    pub p_max: f64,
    /// Actual cams per rate (None: the fewest that can pass).
    pub samples: Option<u64>,
    /// Worker threads (None: every core). The answer does not depend on it.
    pub threads: Option<u32>,
    /// The unit family of the report's lines.
    pub units: Units,
    /// Bracket width the rate search stops at, lb/in.
    pub resolution: f64,
    /// Largest rate searched, lb/in.
    pub max_rate: f64,
    /// Search the preload length δ_rs instead of the rate.
    pub preload: bool,
    /// Largest preload length searched, in.
    pub max_preload_length: f64,
    /// CI's quick mode: coarse brackets, and on actual cams a limit at least
    /// [`super::QUICK_P_MAX`].
    pub quick: bool,
}

/// The preload search's first length, in: a tenth of the reference's 0.5 in.
pub const START_PRELOAD_LENGTH: f64 = 0.05;

/// The default largest preload length, in: 20 times the reference's 0.5 in, beyond any
/// compression the reference spring's coils could take.
pub const MAX_PRELOAD_LENGTH: f64 = 10.0;

/// The preload search's bracket width, in (0.1 in the quick mode).
pub const PRELOAD_RESOLUTION: f64 = 0.005;

/// The search's first rate, lb/in.
pub const START_RATE: f64 = 10.0;

/// The default largest rate, lb/in: the reference wire's stiffest spring of two active
/// coils (G d⁴ / (8 D³ · 2) = 274 lb/in) is well below it.
pub const MAX_RATE: f64 = 1000.0;

/// (start, max, resolution) of `design spring`'s search: over the rate, or over the
/// preload length with --preload.
fn spring_search_range(args: &SpringSpec) -> Result<(f64, f64, f64)> {
    Ok(if args.preload {
        let res = if args.quick { 0.1 } else { PRELOAD_RESOLUTION };
        if args.max_preload_length <= START_PRELOAD_LENGTH {
            bail!(
                "--max-preload-length {}: must be above the search's first length {START_PRELOAD_LENGTH} in",
                args.max_preload_length
            );
        }
        (START_PRELOAD_LENGTH, args.max_preload_length, res)
    } else {
        let res = if args.quick {
            args.resolution.max(10.0)
        } else {
            args.resolution
        };
        if args.max_rate <= START_RATE {
            bail!(
                "--max-rate {}: must be above the search's first rate {START_RATE} lb/in",
                args.max_rate
            );
        }
        (START_RATE, args.max_rate, res)
    })
}

/// The spring search.
pub fn spring(args: &SpringSpec) -> Result<SpringReport> {
    let t0 = Instant::now();
    let mut spec = args.run.clone();
    spec.solver.start = Start::Static;
    spec.revolutions = 2;
    let range = spring_search_range(args)?;
    args.actual.ensure_actual_if_options()?;
    let report = if args.actual.actual {
        spring_on_actual_cams(args, &spec, range, t0)?
    } else {
        spring_on_theoretical_cam(args, &spec, range, t0)?
    };
    crate::report::ensure_finite(&report)?;
    Ok(report)
}

/// What `design spring` varies: the rate (at the preload length), or with --preload the
/// preload length (at the rate held).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Searched {
    /// The spring rate, lb/in.
    #[serde(rename = "spring rate")]
    Rate,
    /// The preload length δ_rs, in.
    #[serde(rename = "preload length")]
    PreloadLength,
}

impl Searched {
    fn of(preload: bool) -> Self {
        if preload {
            Searched::PreloadLength
        } else {
            Searched::Rate
        }
    }

    /// Its name and unit: `spring rate` lb/in or `preload length` in.
    fn words(self) -> (&'static str, &'static str) {
        match self {
            Searched::PreloadLength => ("preload length", "in"),
            Searched::Rate => ("spring rate", "lb/in"),
        }
    }
}

impl PartialEq<&str> for Searched {
    fn eq(&self, other: &&str) -> bool {
        self.words().0 == *other
    }
}
