//! The method comparison of VI.4.2. Every motion law (the same law for every rise and
//! return, the scene otherwise unchanged, [`with_law`]) runs on the theoretical cam with
//! the system's flexibility, and on one actual cam (sample 0 of the master seed, the
//! same interval for every law); cycle I (revolution 1, from the thesis's start) and
//! cycle II (revolution 2) are measured as docs/MODEL.md §9 defines, and every law is
//! ranked in every column ([`RANKED`], [`fill_ranks`]).
//!
//! The runs are independent and run in parallel ([`runs`]); each is deterministic, so
//! the result does not depend on the thread count.
//!
//! The study takes a typed [`Spec`] and returns a [`CompareReport`] (its types in
//! [`report`](mod@report), its text in [`text`]); [`response_traces`] gives the
//! responses its figure shows. `camsim compare` (crate::cmd::compare) builds the spec
//! from its arguments, prints the report and draws its figures (crate::plot::compare).

use anyhow::Result;
use camsim_core::{MotionLaw, SegmentKind};

use crate::actual::{self, Cams};
use crate::sim::RunSpec;

pub mod report;
pub mod runs;
pub mod text;
pub mod traces;

pub use report::*;
pub use text::HEADERS;
pub use traces::{response_traces, LawTraces, Trace};

/// What the study runs.
#[derive(Clone, Debug)]
pub struct Spec {
    /// The scene every law starts from: at the study's speed, from the thesis's start
    /// (cycle I's start-up shock), two revolutions (the vertical model with `quick`).
    pub base: RunSpec,
    /// The actual cam's tolerances, with the interval resolved once from the scene's own
    /// program (the same for every law); sample 0 of their seed is each law's actual cam.
    pub actual: Cams,
    /// `--quick`: the vertical scene ran (reported).
    pub quick: bool,
    /// Worker threads (the result does not depend on them).
    pub threads: usize,
}

/// The columns every law is ranked in, and whether a smaller value ranks better.
pub const RANKED: [(&str, bool); 8] = [
    ("sensitivity_to_flexibility", true),
    ("sensitivity_to_tolerance", true),
    ("shock_index", true),
    ("torque_avg", true),
    ("torque_max", true),
    ("contact_force_min", false),
    ("contact_force_max", true),
    ("contact_stress_max", true),
];

/// Runs the study: every law on both cams, measured and ranked. An error when no law
/// is workable (the first one's reason), or when a run fails otherwise.
pub fn report(spec: &Spec) -> Result<CompareReport> {
    let base = &spec.base;
    let (intervals, interval_source) = actual::intervals_for(&base.design, &spec.actual)?;
    let specs: Vec<(MotionLaw, RunSpec)> = MotionLaw::ALL
        .iter()
        .map(|&l| with_law(base, l).map(|s| (l, s)))
        .collect::<Result<_>>()?;
    let results = runs::run_every_law(&specs, &spec.actual, spec.threads)?;
    let (mut laws, not_workable) = runs::law_studies(base, &specs, results)?;
    anyhow::ensure!(
        !laws.is_empty(),
        "no law is workable: every law's run left the model's valid range (first: {} on the {} cam: {})",
        not_workable.first().map_or("", |n: &NotWorkable| n.name.as_str()),
        not_workable.first().map_or("", |n| n.cam.as_str()),
        not_workable.first().map_or("", |n| n.reason.as_str())
    );
    fill_ranks(&mut laws);
    Ok(CompareReport {
        laws,
        not_workable,
        rpm: camsim_core::rad_per_s_to_rpm(base.design.omega0),
        quick: spec.quick,
        seed: spec.actual.seed(),
        intervals,
        interval_source,
        wall_s: 0.0,
    })
}

/// Ranks `values` (one per law) from 1: ascending when `smaller_better`, else
/// descending; ties keep the laws' order, so the ranks are always a permutation.
pub fn rank(values: &[f64], smaller_better: bool) -> Vec<usize> {
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| {
        let o = values[a].total_cmp(&values[b]);
        let o = if smaller_better { o } else { o.reverse() };
        o.then(a.cmp(&b))
    });
    let mut ranks = vec![0; values.len()];
    for (r, &i) in order.iter().enumerate() {
        ranks[i] = r + 1;
    }
    ranks
}

/// Ranks every law in every column of [`RANKED`], then overall: the laws that hold
/// contact on the theoretical cam in cycle II before those that separate, each group by
/// the sum of its ranks (ties in the laws' order).
pub fn fill_ranks(laws: &mut [LawStudy]) {
    let mut sums = vec![0.0; laws.len()];
    for (col, smaller) in RANKED {
        let v: Vec<f64> = laws
            .iter()
            .map(|l| l.values.get(col).unwrap_or(f64::NAN))
            .collect();
        for (i, r) in rank(&v, smaller).into_iter().enumerate() {
            laws[i].ranks.set(col, r);
            sums[i] += r as f64;
        }
    }
    // The sum is at most 8 · 12 = 96: a separating law's key is above every other's.
    let keys: Vec<f64> = laws
        .iter()
        .zip(&sums)
        .map(|(l, s)| s + if l.flexibility.jump { 1000.0 } else { 0.0 })
        .collect();
    for (i, r) in rank(&keys, true).into_iter().enumerate() {
        laws[i].values.overall = sums[i];
        laws[i].ranks.overall = r;
    }
}

/// The scene with `law` for every rise and return.
pub fn with_law(base: &RunSpec, law: MotionLaw) -> Result<RunSpec> {
    let mut spec = base.clone();
    let mut segs: Vec<_> = spec.design.program.segments().to_vec();
    for s in &mut segs {
        match &mut s.kind {
            SegmentKind::Rise(l) | SegmentKind::Return(l) => *l = law,
            SegmentKind::Dwell => {}
        }
    }
    spec.design.program = camsim_core::CamProgram::new(&segs)?;
    spec.design.validate()?;
    Ok(spec)
}

/// The kind of each segment of the program (rise, return or dwell), in the order of its
/// periods.
fn segment_kinds(spec: &RunSpec) -> Vec<SegmentKind> {
    spec.design
        .program
        .segments()
        .iter()
        .map(|s| s.kind)
        .collect()
}
