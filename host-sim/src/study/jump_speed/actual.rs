//! `camsim jump-speed --actual [--samples N]`: the jump onset of machined cams as a
//! distribution over samples.
//!
//! Sample i is the actual cam [`crate::actual::build_profile`]`(design, args, i)` (its
//! random numbers from the master seed and i alone); its onset is found by the same
//! search as the theoretical cam's ([`super::find`]). The samples run in
//! parallel on a local pool and are collected by index, so the result is the same for
//! any `--threads`. The theoretical cam's onset is searched too, beside the
//! distribution.

use std::sync::Arc;

use anyhow::{Context, Result};
use rayon::prelude::*;
use serde::Serialize;

use super::{find, JumpSpeed};
use crate::actual::Cams;
use crate::sim::RunSpec;

/// The default `--samples` of `jump-speed --actual`: 20 (about 20 searches of 16 runs
/// of two revolutions; the quartiles are then order statistics 5 and 15).
pub const DEFAULT_SAMPLES: u32 = 20;

/// The empirical quantile `q` of sorted `v` (linear between order statistics, the
/// "type 7" rule: `h = (n - 1) q`); an infinite entry (no onset up to the maximum
/// speed) gives None when it is used.
pub fn quantile(v: &[f64], q: f64) -> Option<f64> {
    let n = v.len();
    if n == 0 {
        return None;
    }
    let h = (n - 1) as f64 * q;
    let (lo, hi) = (h.floor() as usize, h.ceil() as usize);
    let (a, b) = (v[lo.min(n - 1)], v[hi.min(n - 1)]);
    let x = a + (h - lo as f64) * (b - a);
    let x = if lo == hi { a } else { x };
    x.is_finite().then_some(x)
}

/// What `camsim jump-speed --actual` reports.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ActualOnsetReport {
    /// Machined cams drawn.
    pub samples: usize,
    /// Master seed.
    pub seed: u64,
    /// How the machined cams are made (method, normal deviates, tolerances, interval).
    pub profile: crate::study::montecarlo::ProfileSettings,
    /// The scene's operating speed, rpm.
    pub operating_rpm: f64,
    /// Bisection resolution, rpm.
    pub resolution_rpm: f64,
    /// Highest speed searched, rpm.
    pub max_rpm: f64,
    /// The theoretical cam's jump onset, rpm (absent: none up to `max_rpm`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub theoretical_jump_rpm: Option<f64>,
    /// Each sample's onset, rpm, by sample index (absent entries: no onset up to
    /// `max_rpm`, written as `max_rpm` in `onset_rpm_or_max` instead).
    pub onset_rpm_or_max: Vec<f64>,
    /// Samples without an onset up to `max_rpm`.
    pub beyond_max: usize,
    /// Smallest onset, rpm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_rpm: Option<f64>,
    /// 5 % quantile, rpm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub q05_rpm: Option<f64>,
    /// Lower quartile, rpm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub q25_rpm: Option<f64>,
    /// Median, rpm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub median_rpm: Option<f64>,
    /// Upper quartile, rpm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub q75_rpm: Option<f64>,
    /// Largest onset, rpm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_onset_rpm: Option<f64>,
    /// Samples whose onset is at or below the operating speed (they jump in operation).
    pub jump_at_operating: usize,
    /// That share as P(jump) at the operating speed, with its 95 % Wilson interval.
    pub p_jump_at_operating: crate::stats::Probability,
    /// Simulations run (every sample's and the theoretical search's).
    pub simulations: u32,
    /// Worker threads.
    pub threads: usize,
    /// Wall time, ms.
    pub wall_ms: f64,
}

/// The onset distribution of `samples` actual cams of `spec` drawn with `actual`.
pub fn study(
    spec: &RunSpec,
    actual: &Cams,
    samples: u32,
    threads: usize,
    resolution: f64,
    max_rpm: f64,
) -> Result<ActualOnsetReport> {
    let t0 = std::time::Instant::now();
    // The interval chosen once for every sample.
    let actual = &actual.resolve(&spec.design)?;
    let interval = crate::actual::intervals_for(&spec.design, actual)?;
    let profile = crate::study::montecarlo::ProfileSettings::of(actual, interval)?;
    let op = camsim_core::rad_per_s_to_rpm(spec.design.omega0);
    let pool = crate::study::pool(threads)?;
    // A progress bar on a terminal: the theoretical search and every sample's.
    let bar = crate::study_limits::progress_bar(
        u64::from(samples) + 1,
        true,
        "{elapsed_precise} [{bar:40}] {pos}/{len} onset searches, {per_sec}, eta {eta}",
    );
    let theory = find(spec, resolution, max_rpm).context("the theoretical cam")?;
    bar.inc(1);
    let results: Vec<Result<JumpSpeed>> = pool.install(|| {
        (0..u64::from(samples))
            .into_par_iter()
            .map(|i| {
                let (dev, _) = crate::actual::build_profile(&spec.design, actual, i)?;
                let mut s = spec.clone();
                s.profile = Some(Arc::new(dev));
                let r = find(&s, resolution, max_rpm).with_context(|| format!("sample {i}"));
                bar.inc(1);
                r
            })
            .collect()
    });
    bar.finish_and_clear();
    let mut onsets = Vec::with_capacity(results.len());
    let mut simulations = theory.simulations;
    for r in results {
        let r = r?;
        simulations += r.simulations;
        onsets.push(r.jump_rpm);
    }
    let mut sorted: Vec<f64> = onsets.iter().map(|o| o.unwrap_or(f64::INFINITY)).collect();
    sorted.sort_by(f64::total_cmp);
    let jump_at_operating = onsets.iter().filter(|o| o.is_some_and(|r| r <= op)).count();
    Ok(ActualOnsetReport {
        samples: onsets.len(),
        seed: actual.seed(),
        profile,
        operating_rpm: op,
        resolution_rpm: resolution,
        max_rpm,
        theoretical_jump_rpm: theory.jump_rpm,
        onset_rpm_or_max: onsets.iter().map(|o| o.unwrap_or(max_rpm)).collect(),
        beyond_max: onsets.iter().filter(|o| o.is_none()).count(),
        min_rpm: quantile(&sorted, 0.0),
        q05_rpm: quantile(&sorted, 0.05),
        q25_rpm: quantile(&sorted, 0.25),
        median_rpm: quantile(&sorted, 0.5),
        q75_rpm: quantile(&sorted, 0.75),
        max_onset_rpm: quantile(&sorted, 1.0),
        jump_at_operating,
        p_jump_at_operating: crate::stats::Probability::of(
            jump_at_operating as u64,
            onsets.len() as u64,
        ),
        simulations,
        threads: threads.max(1),
        wall_ms: t0.elapsed().as_secs_f64() * 1e3,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_are_type_7() {
        let v = [1.0, 2.0, 3.0, 4.0, 5.0];
        assert_eq!(quantile(&v, 0.0), Some(1.0));
        assert_eq!(quantile(&v, 0.5), Some(3.0));
        assert_eq!(quantile(&v, 0.25), Some(2.0));
        assert_eq!(quantile(&v, 1.0), Some(5.0));
        assert_eq!(quantile(&[1.0, 2.0], 0.5), Some(1.5));
        assert_eq!(quantile(&[1.0, f64::INFINITY], 1.0), None);
        assert_eq!(quantile(&[1.0, f64::INFINITY], 0.0), Some(1.0));
        assert_eq!(quantile(&[], 0.5), None);
    }
}
