//! The statistics of a Monte Carlo study: every column of the run table, the
//! whole-revolution values and the profiles over the samples, reduced in index order
//! (the method is in [`super`]'s notes).

use anyhow::{anyhow, bail, Result};
use serde::{Serialize, Serializer};

use super::{SampleRecord, COLUMNS};

/// Mean, standard deviation and percentiles of one statistic over the samples.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Moments {
    /// Mean.
    pub mean: f64,
    /// Sample standard deviation (n − 1; 0 for one sample).
    pub sd: f64,
    /// 5th percentile.
    pub p5: f64,
    /// Median.
    pub p50: f64,
    /// 95th percentile.
    pub p95: f64,
    /// Smallest.
    pub min: f64,
    /// Largest.
    pub max: f64,
}

/// The percentile `p` (0..1) of sorted values: linear between the order statistics
/// at rank `(n − 1)p` (type 7).
fn percentile(sorted: &[f64], p: f64) -> f64 {
    let n = sorted.len();
    if n == 0 {
        return f64::NAN;
    }
    let h = (n - 1) as f64 * p;
    let lo = h.floor() as usize;
    let hi = (lo + 1).min(n - 1);
    let (a, b) = (sorted[lo], sorted[hi]);
    a + (h - lo as f64) * (b - a)
}

impl Moments {
    /// The moments of `values` (in index order; at least one, all finite).
    pub fn of(what: &str, values: &[f64]) -> Result<Self> {
        anyhow::ensure!(!values.is_empty(), "{what}: no samples");
        if let Some(v) = values.iter().find(|v| !v.is_finite()) {
            bail!("{what}: a sample is {v}");
        }
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        let sd = if values.len() > 1 {
            (values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0)).sqrt()
        } else {
            0.0
        };
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        let m = Moments {
            mean,
            sd,
            p5: percentile(&sorted, 0.05),
            p50: percentile(&sorted, 0.50),
            p95: percentile(&sorted, 0.95),
            min: sorted[0],
            max: sorted[sorted.len() - 1],
        };
        for (k, v) in [
            ("mean", m.mean),
            ("sd", m.sd),
            ("p5", m.p5),
            ("p50", m.p50),
            ("p95", m.p95),
        ] {
            anyhow::ensure!(v.is_finite(), "{what}: the {k} is {v}");
        }
        Ok(m)
    }
}

pub use crate::stats::Probability;

/// Named statistics in a fixed order (a JSON object in that order).
#[derive(Clone, Debug, PartialEq)]
pub struct Columns(pub Vec<(String, Moments)>);

impl Serialize for Columns {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(self.0.len()))?;
        for (k, v) in &self.0 {
            m.serialize_entry(k, v)?;
        }
        m.end()
    }
}

impl Columns {
    /// The statistics of `name`, if present.
    pub fn get(&self, name: &str) -> Option<&Moments> {
        self.0.iter().find(|(k, _)| k == name).map(|(_, m)| m)
    }
}

/// One period of revolution 2 over the samples.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PeriodSummary {
    /// Period name.
    pub period: String,
    /// Every column of the run table.
    pub columns: Columns,
    /// Probability of a separation in this period.
    pub jump: Probability,
}

/// Whole-revolution statistics of revolution 2 (one value per sample each).
pub const REVOLUTION_COLUMNS: [&str; 6] = [
    "acc_rms_sum",
    "contact_force_min",
    "contact_force_max",
    "torque_max",
    "torque_min",
    "contact_stress_max",
];

/// The value of a whole-revolution statistic of one sample: the sum of the periods'
/// acceleration RMS (the sensitivity index of VI.4.2), or the extreme of the periods'
/// extremes.
pub fn revolution_value(r: &SampleRecord, name: &str) -> f64 {
    fn col<'a>(r: &'a SampleRecord, c: &'a str) -> impl Iterator<Item = f64> + 'a {
        r.periods.iter().filter_map(move |p| p.get(c))
    }
    match name {
        "acc_rms_sum" => col(r, "rms_acceleration").sum(),
        "contact_force_min" | "torque_min" => col(r, name).fold(f64::INFINITY, f64::min),
        _ => col(r, name).fold(f64::NEG_INFINITY, f64::max),
    }
}

/// A study's result over its samples.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Summary {
    /// Samples reduced.
    pub samples: u64,
    /// The revolution the statistics are of.
    pub revolution: u32,
    /// Every period of the program.
    pub periods: Vec<PeriodSummary>,
    /// Whole-revolution statistics ([`REVOLUTION_COLUMNS`]).
    pub whole_revolution: Columns,
    /// Probability of a separation anywhere in the revolution.
    pub jump: Probability,
    /// The profiles: waviness FPR and RMS lift deviation, in.
    pub profile: Columns,
    /// Accepted solver steps per sample.
    pub steps: Moments,
}

/// Reduces records of `revolution` (sorted by index, every index of the study once)
/// in index order.
pub fn summarize(records: &[SampleRecord], revolution: u32) -> Result<Summary> {
    let first = records
        .first()
        .ok_or_else(|| anyhow!("no samples to summarize"))?;
    let n = records.len() as u64;
    let names: Vec<&str> = first.periods.iter().map(|p| p.period.as_str()).collect();
    for r in records {
        let theirs: Vec<&str> = r.periods.iter().map(|p| p.period.as_str()).collect();
        anyhow::ensure!(
            theirs == names,
            "sample {} has the periods {theirs:?}, sample {} {names:?}",
            r.index,
            first.index
        );
    }
    let mut periods = Vec::new();
    for (k, name) in names.iter().enumerate() {
        let mut columns = Vec::new();
        for (c, col) in COLUMNS.iter().enumerate() {
            let v: Vec<f64> = records.iter().map(|r| r.periods[k].values[c]).collect();
            columns.push((col.to_string(), Moments::of(&format!("{name}.{col}"), &v)?));
        }
        let jumps = records.iter().filter(|r| r.periods[k].jump).count() as u64;
        periods.push(PeriodSummary {
            period: name.to_string(),
            columns: Columns(columns),
            jump: Probability::of(jumps, n),
        });
    }
    let mut whole = Vec::new();
    for c in REVOLUTION_COLUMNS {
        let v: Vec<f64> = records.iter().map(|r| revolution_value(r, c)).collect();
        whole.push((c.to_string(), Moments::of(c, &v)?));
    }
    let fpr: Vec<f64> = records.iter().map(|r| r.fpr as f64).collect();
    let rms: Vec<f64> = records.iter().map(|r| r.rms_deviation_in).collect();
    let steps: Vec<f64> = records.iter().map(|r| f64::from(r.steps)).collect();
    Ok(Summary {
        samples: n,
        revolution,
        periods,
        whole_revolution: Columns(whole),
        jump: Probability::of(records.iter().filter(|r| r.jump()).count() as u64, n),
        profile: Columns(vec![
            ("fpr".into(), Moments::of("fpr", &fpr)?),
            (
                "rms_deviation_in".into(),
                Moments::of("rms_deviation_in", &rms)?,
            ),
        ]),
        steps: Moments::of("steps", &steps)?,
    })
}
