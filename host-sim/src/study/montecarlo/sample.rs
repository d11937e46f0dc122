//! One sample of a study: its actual cam simulated on the study's model (and on the full
//! model too in a two-level study's subsample), and what the study keeps of it: the
//! per-period columns of its measured revolution ([`SampleRecord`]), or how its run left
//! the model's valid range ([`LeftRange`]).

use std::ops::ControlFlow;
use std::sync::Arc;

use anyhow::{anyhow, Result};
use camsim_core::{jump_verdict, JumpWatch, Observer, Sample};
use serde::{Deserialize, Serialize};

use super::Study;
use crate::actual;
use crate::sim::{self, PeriodRow, RunSpec};

/// The columns of a per-period record (those of `camsim run`'s table), in order.
pub const COLUMNS: [&str; 13] = [
    "rms_displacement",
    "rms_velocity",
    "rms_acceleration",
    "torque_avg",
    "torque_max",
    "torque_min",
    "contact_force_min",
    "contact_force_max",
    "contact_force_avg",
    "contact_stress_max",
    "aord_motor",
    "aord_coupling",
    "aord_cam",
];

/// One period of one sample's revolution 2: the run table's columns and the jump flag.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PeriodValues {
    /// Period name.
    pub period: String,
    /// The [`COLUMNS`], in order.
    pub values: [f64; COLUMNS.len()],
    /// Whether the follower separated in this period.
    pub jump: bool,
}

impl PeriodValues {
    /// The record of a row of `camsim run`'s table.
    pub fn of(r: &PeriodRow) -> Self {
        PeriodValues {
            period: r.period.to_string(),
            values: [
                r.rms_displacement.in_inch(),
                r.rms_velocity.in_inch(),
                r.rms_acceleration.in_inch(),
                r.torque_avg.in_inch(),
                r.torque_max.in_inch(),
                r.torque_min.in_inch(),
                r.contact_force_min.in_inch(),
                r.contact_force_max.in_inch(),
                r.contact_force_avg.in_inch(),
                r.contact_stress_max.in_inch(),
                r.aord_motor,
                r.aord_coupling,
                r.aord_cam,
            ],
            jump: r.jump,
        }
    }

    /// The value of column `name` (one of [`COLUMNS`]).
    pub fn get(&self, name: &str) -> Option<f64> {
        COLUMNS
            .iter()
            .position(|c| *c == name)
            .and_then(|i| self.values.get(i).copied())
    }
}

/// Everything a study keeps of one sample.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SampleRecord {
    /// The sample index i (its profile comes from the master seed and i alone).
    pub index: u64,
    /// Waviness frequency per revolution of its profile.
    pub fpr: usize,
    /// RMS lift deviation of its profile, in.
    pub rms_deviation_in: f64,
    /// Revolution 2, period by period.
    pub periods: Vec<PeriodValues>,
    /// Accepted solver steps of the whole run.
    pub steps: u32,
}

impl SampleRecord {
    /// Whether the follower separated anywhere in revolution 2.
    pub fn jump(&self) -> bool {
        self.periods.iter().any(|p| p.jump)
    }
}

/// A sample whose run left the model's valid range (docs/MODEL.md §3.20): no record.
#[derive(Clone, Debug, PartialEq)]
pub struct LeftRange {
    /// Whether the follower had separated first (then the sample is a jump, the rule of
    /// `camsim jump-speed` and the sweeps); otherwise it is not workable.
    pub separated: bool,
    /// The run's error.
    pub reason: String,
}

/// What a sample's run gave: its record, or how it left the model's range.
pub type Outcome = std::result::Result<SampleRecord, LeftRange>;

/// Core's jump rule's watch, fed every solver sample of a run.
struct Separation(JumpWatch<f64>);

impl Observer<f64> for Separation {
    fn observe(&mut self, s: &Sample<f64>) -> ControlFlow<()> {
        let _ = self.0.note_sample(s);
        ControlFlow::Continue(())
    }
}

impl Study {
    /// Runs sample `index` on the study's first model (the reduced one of a two-level
    /// study): its profile, its simulation, its record of the measured revolution.
    /// A run that leaves the model's valid range is an error here.
    pub fn sample(&self, index: u64) -> Result<SampleRecord> {
        self.pair(index)?.0.map_err(|l| anyhow!(l.reason))
    }

    /// Runs sample `index` on the first model and, if it is in a two-level study's
    /// subsample and workable there, on the full model too (the same actual cam). A run
    /// that leaves a model's valid range is an outcome, not an error (the counting rule
    /// of docs/MODEL.md §3.20 applies to both models).
    pub fn pair(&self, index: u64) -> Result<(Outcome, Option<Outcome>)> {
        let (dev, stats) = actual::build_profile(&self.spec.design, &self.actual, index)?;
        let dev = Arc::new(dev);
        let first = self.reduced.as_ref().unwrap_or(&self.spec);
        let rec = self.record(first, &dev, &stats, index)?;
        // A cam not workable on the first model is out of the study: no pair.
        let not_workable = matches!(&rec, Err(l) if !l.separated);
        if index >= self.full_samples() || not_workable {
            return Ok((rec, None));
        }
        let full = self
            .record(&self.spec, &dev, &stats, index)
            .map_err(|e| e.context("on the full model"))?;
        Ok((rec, Some(full)))
    }

    /// The record of sample `index`'s cam `dev` simulated on `spec`.
    fn record(
        &self,
        spec: &RunSpec,
        dev: &Arc<sim::HostDeviation>,
        stats: &actual::ProfileStats,
        index: u64,
    ) -> Result<Outcome> {
        let rev = self.revolution();
        let mut spec = spec.clone();
        spec.profile = Some(Arc::clone(dev));
        let mut watch = Separation(JumpWatch::new());
        let r = match sim::run(&spec, &mut watch) {
            Ok(r) => r,
            Err(e) => {
                // Core's rule: a failure after a separation is a jump; leaving the
                // range with the follower on the cam is not workable; anything else
                // is an error.
                let separated = jump_verdict::<(), (), f64>(Err(()), &watch.0).is_ok();
                if !separated && !crate::study::sweep::out_of_model(&e) {
                    return Err(e);
                }
                let reason = format!("{e:#}");
                return Ok(Err(LeftRange { separated, reason }));
            }
        };
        let periods: Vec<PeriodValues> = sim::period_rows(&spec.design, &r.stats)
            .iter()
            .filter(|p| p.revolution == rev)
            .map(PeriodValues::of)
            .collect();
        let names = sim::period_names(&spec.design);
        anyhow::ensure!(
            periods.len() == names.len(),
            "revolution {rev} has {} of the program's {} periods",
            periods.len(),
            names.len()
        );
        for p in &periods {
            for (c, v) in COLUMNS.iter().zip(p.values) {
                anyhow::ensure!(v.is_finite(), "{}.{c} is {v}", p.period);
            }
        }
        anyhow::ensure!(
            stats.rms_deviation_in.in_inch().is_finite(),
            "profile RMS deviation is not finite"
        );
        Ok(Ok(SampleRecord {
            index,
            fpr: stats.fpr,
            rms_deviation_in: stats.rms_deviation_in.in_inch(),
            periods,
            steps: r.solver.accepted,
        }))
    }
}
