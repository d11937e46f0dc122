//! The tolerance study of VI.4.1 (Table VI.2 varies both the tolerance and the
//! waviness): the cam and roller tolerances at 0.2, 1 and 5 times VI.1's (cam ±0.0001,
//! ±0.0005, ±0.0025 in, the roller's at 1/5 of it; the eccentricity kept at VI.1's
//! ±0.001 in), by the waviness (FPR 17, 39 and 57, the thesis's cams) or by given
//! intervals. Each cell is a small Monte Carlo study ([`crate::study::montecarlo`]) whose
//! samples use the same master seed in every cell (common random numbers), reported as
//! the mean of revolution 2's time responses (RMS deviations) and inertial responses per
//! period, with the probability of a jump and its 95 % interval. A theoretical-cam row
//! (no tolerance) comes first.
//!
//! The study takes a typed [`Spec`] and returns a [`ToleranceReport`] (its types in
//! [`mod@report`], its text in [`text`], its figures in [`crate::plot::tolerance`]);
//! `camsim tolerance-study` (crate::cmd::tolerance_study) builds the spec from its
//! arguments, prints the report and draws its figures.

use anyhow::Result;
use camsim_core::SegmentKind;

use crate::actual::{Cams, NormalArg};
use crate::sim::RunSpec;
use crate::study::montecarlo::{self, Columns, Probability, Study, StudyStats, Summary};
use crate::units::{Acceleration, Length};

pub mod report;
pub mod text;

pub use report::{column_label, Cell, ToleranceReport};

/// The factors on VI.1's cam and roller tolerances (±0.0005 and ±0.0001 in) of the
/// grid's rows, largest first: cam ±0.0025, ±0.0005, ±0.0001 in.
pub const TOLERANCE_FACTORS: [f64; 3] = [5.0, 1.0, 0.2];
/// The default waviness axis: the thesis's cams (VI.4.1, Table VI.2): FPR 17 (its
/// study cams), 39 (a rougher one) and 57 (at ±0.0025/±0.0005 in).
pub const WAVINESS_FPR: [u32; 3] = [17, 39, 57];

/// A column of the grid: the waviness asked (FPR) or the profile point interval given
/// (degrees).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Column {
    /// The interval whose profile, drawn from the master seed at the cell's tolerances,
    /// has the FPR nearest this one.
    Fpr(u32),
    /// This interval, degrees.
    IntervalDeg(f64),
}

/// What the study runs.
#[derive(Clone, Debug)]
pub struct Spec {
    /// The run of every cam: the scene at the study's speed, revolution
    /// [`montecarlo::REVOLUTION`] (the vertical model with `quick`), validated.
    pub run: RunSpec,
    /// Actual cams per cell.
    pub samples: u64,
    /// The waviness axis, one column a cell of each row.
    pub columns: Vec<Column>,
    /// Camshaft-bearing and eccentricity tolerance, ± in (the same in every cell).
    pub eccentricity_tolerance: Length,
    /// Master seed (`None`: [`crate::actual::DEFAULT_SEED`]).
    pub seed: Option<u64>,
    /// Normal deviates.
    pub normal: NormalArg,
    /// `--quick`: said in the report (the vertical model is already in `run`).
    pub quick: bool,
    /// Worker threads (the result does not depend on them).
    pub threads: usize,
}

/// One cell's tolerances and waviness.
#[derive(Clone, Copy, Debug)]
struct CellSpec {
    cam: f64,
    roller: f64,
    eccentricity: f64,
    fpr: Option<u32>,
    interval: Option<f64>,
}

impl CellSpec {
    /// The theoretical cam: no tolerance.
    const THEORETICAL: CellSpec = CellSpec {
        cam: 0.0,
        roller: 0.0,
        eccentricity: 0.0,
        fpr: None,
        interval: Some(10.0),
    };

    fn theoretical(&self) -> bool {
        self.cam == 0.0 && self.roller == 0.0 && self.eccentricity == 0.0
    }
}

/// Runs the grid: the theoretical cam, then a row a tolerance factor (largest first), a
/// cell a column.
pub fn report(spec: &Spec) -> Result<ToleranceReport> {
    let t0 = std::time::Instant::now();
    let bar = crate::study_limits::progress_bar(
        1 + (TOLERANCE_FACTORS.len() * spec.columns.len()) as u64 * spec.samples,
        true,
        "{elapsed_precise} [{bar:40}] {pos}/{len} runs, {per_sec}, eta {eta}",
    );
    let theoretical = cell(spec, CellSpec::THEORETICAL)?;
    bar.inc(1);
    let reference = camsim_core::Tolerances::<f64>::reference();
    let mut cells = Vec::new();
    for k in TOLERANCE_FACTORS {
        for column in &spec.columns {
            let (fpr, interval) = match *column {
                Column::Fpr(f) => (Some(f), None),
                Column::IntervalDeg(d) => (None, Some(d)),
            };
            let c = CellSpec {
                cam: k * reference.cam,
                roller: k * reference.roller,
                eccentricity: spec.eccentricity_tolerance.in_inch(),
                fpr,
                interval,
            };
            cells.push(cell(spec, c)?);
            bar.inc(spec.samples);
        }
    }
    bar.finish_and_clear();
    some_cell_workable(&theoretical, &cells)?;
    Ok(ToleranceReport {
        program: [law_of(&spec.run, true), law_of(&spec.run, false)],
        rpm: camsim_core::rad_per_s_to_rpm(spec.run.design.omega0),
        samples_per_cell: spec.samples,
        seed: spec.seed.unwrap_or(crate::actual::DEFAULT_SEED),
        quick: spec.quick,
        theoretical,
        columns: cells.len() / TOLERANCE_FACTORS.len(),
        cells,
        wall_s: t0.elapsed().as_secs_f64(),
    })
}

/// One cell's Monte Carlo study (one cam for the theoretical one).
fn cell(spec: &Spec, c: CellSpec) -> Result<Cell> {
    let actual = Cams {
        actual: true,
        cam_tolerance: Some(c.cam),
        roller_tolerance: Some(c.roller),
        eccentricity_tolerance: Some(c.eccentricity),
        interval_deg: c.interval,
        waviness_fpr: c.fpr.into_iter().collect(),
        seed: spec.seed,
        normal: spec.normal,
        ..Cams::default()
    };
    let theoretical = c.theoretical();
    let n = if theoretical { 1 } else { spec.samples };
    let study = Study::from_spec(spec.run.clone(), &actual, n)?;
    // Samples that leave the model's range are counted (jumps or not workable).
    let stats = study.run_stats(montecarlo::Shard::WHOLE, spec.threads, false)?;
    let (summary, not_workable) = cell_summary(&stats, study.revolution())?;
    let acc = summary.whole_revolution.get("acc_rms_sum").map(|m| m.mean);
    Ok(Cell {
        cam_tolerance_in: Length::inch(c.cam),
        roller_tolerance_in: Length::inch(c.roller),
        eccentricity_tolerance_in: Length::inch(c.eccentricity),
        target_fpr: if theoretical { None } else { c.fpr },
        interval_deg: (!theoretical).then(|| 360.0 / study.settings.profile.intervals as f64),
        fpr: if theoretical {
            None
        } else {
            summary.profile.get("fpr").map(|m| m.mean)
        },
        acc_rms_sum_in_per_s2: acc.map(Acceleration::inch),
        not_workable,
        summary,
    })
}

/// The name of the program's rise law (`rise`) or return law, "none" without one.
fn law_of(spec: &RunSpec, rise: bool) -> String {
    spec.design
        .program
        .segments()
        .iter()
        .find_map(|s| match (s.kind, rise) {
            (SegmentKind::Rise(l), true) | (SegmentKind::Return(l), false) => Some(l.name()),
            _ => None,
        })
        .unwrap_or("none")
        .to_string()
}

/// Fails when no cell is workable (every cam of every cell left the model's valid range
/// with the follower on the cam), with the theoretical cam's reason.
fn some_cell_workable(theoretical: &Cell, cells: &[Cell]) -> Result<()> {
    let all = std::iter::once(theoretical).chain(cells);
    if let Some(why) = all
        .map(|c| c.not_workable.as_ref())
        .collect::<Option<Vec<_>>>()
    {
        anyhow::bail!(
            "no cell is workable: in every one each cam left the model's valid range with the follower on the cam (theoretical cam: {})",
            why.first().map_or("", |w| w.as_str())
        );
    }
    Ok(())
}

/// A cell's statistics, and why it is not workable when every cam left the model's
/// valid range with the follower on the cam (then an empty summary with the count).
pub fn cell_summary(stats: &StudyStats, revolution: u32) -> Result<(Summary, Option<String>)> {
    if stats.samples + stats.left_range_jumps > 0 {
        return Ok((stats.summary(revolution)?, None));
    }
    let why = stats
        .first_not_workable
        .as_ref()
        .map_or("no cam ran".to_string(), |(i, r)| {
            format!("sample {i}: {r}")
        });
    let summary = Summary {
        samples: 0,
        revolution,
        periods: Vec::new(),
        whole_revolution: Columns(Vec::new()),
        jump: Probability::of(0, 0),
        profile: Columns(Vec::new()),
        steps: None,
        left_range_jumps: 0,
        not_workable: stats.not_workable,
        not_workable_reason: Some(why.clone()),
    };
    Ok((summary, Some(why)))
}
