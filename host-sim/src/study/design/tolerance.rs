//! `design tolerance`: the loosest cam tolerance at each waviness (one search each), or
//! the roughest waviness at a tolerance; a waviness at which nothing passes is a row of
//! its table.

use anyhow::{bail, Result};
use serde::Serialize;

use super::speed::{mc_search, mc_search_at, McSearchReport};
use super::McSpec;
use crate::report::Report;
use crate::stats::Probability;
use crate::study::montecarlo::ProfileSettings;
use crate::units::{self, Length};

/// `design tolerance`: the loosest cam tolerance for each FPR of --waviness-fpr (the
/// default FPR when none is given), one search each; --waviness searches the FPR.
pub fn tolerance_table(args: &McSpec) -> Result<ToleranceTable> {
    let a = &args.actual;
    a.refuse_actual_flag("design tolerance")?;
    if a.interval_deg.is_some() || a.interval == crate::actual::IntervalRule::Criteria {
        return Err(crate::args::usage(
            "--interval-deg and --interval criteria fix the profile's interval: `design tolerance` sets it from the waviness (--waviness-fpr)",
        ));
    }
    if let Some(t) = a.cam_tolerance {
        return Err(crate::args::usage(format!(
            "--cam-tolerance {t}: `design tolerance` searches the cam tolerance (with --waviness it is --tolerance-factor times VI.1's; hold the roller and eccentricity tolerances with --roller-tolerance and --eccentricity-tolerance)"
        )));
    }
    if args.waviness {
        return Ok(ToleranceTable(vec![ToleranceRow::Answer(mc_search(
            args, false,
        )?)]));
    }
    let fprs = if a.waviness_fpr.is_empty() {
        vec![crate::actual::DEFAULT_FPR]
    } else {
        a.waviness_fpr.clone()
    };
    let rows = fprs
        .iter()
        .map(|&f| {
            let r =
                mc_search_at(args, false, Some(f)).map_err(|e| e.context(format!("FPR {f}")))?;
            Ok(r.map_or_else(ToleranceRow::NothingPasses, ToleranceRow::Answer))
        })
        .collect::<Result<Vec<_>>>()?;
    // The command fails only when no FPR has an answer.
    if let Some(n) = rows
        .iter()
        .map(ToleranceRow::nothing_passes)
        .collect::<Option<Vec<_>>>()
    {
        let why: Vec<String> = n.iter().map(|n| n.error_line()).collect();
        bail!("{}", why.join("; "));
    }
    Ok(ToleranceTable(rows))
}

/// What a search that found nothing passing ran, for its report.
pub(crate) struct SearchLog {
    pub(crate) profile: ProfileSettings,
    pub(crate) criterion: String,
    pub(crate) model: String,
    pub(crate) tried: Vec<(f64, bool)>,
    pub(crate) model_runs: u64,
    pub(crate) wall_s: f64,
}

/// A `design tolerance` FPR at which nothing passes: P(jump)'s upper bound is above
/// --p-max already at the search's smallest cam tolerance (a row of the table, not the
/// command's failure while another FPR has an answer).
#[derive(Clone, Debug, Serialize)]
pub struct NothingPasses {
    /// `tolerance`.
    pub search: String,
    /// The cams' waviness, FPR.
    pub waviness_fpr: u32,
    /// Why, in words: P(jump) at the smallest tolerance against --p-max.
    pub nothing_passes: String,
    /// The smallest factor on VI.1's cam tolerance tried (the search's first).
    pub smallest_factor_tried: f64,
    /// The cam profile tolerance there, ± in.
    pub smallest_cam_tolerance_in: Length,
    /// The roller tolerance (held), ± in.
    pub roller_tolerance_in: Length,
    /// The eccentricity tolerance (held), ± in.
    pub eccentricity_tolerance_in: Length,
    /// P(jump) at the smallest tolerance with its 95 % Wilson interval.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub p_jump: Option<Probability>,
    /// The criterion.
    pub criterion: String,
    /// Actual cams a step.
    pub samples: u64,
    /// Master seed.
    pub seed: u64,
    /// The model.
    pub model: String,
    /// Every factor tried and whether it passed.
    pub tolerance_factors_tried: Vec<(f64, bool)>,
    /// Model runs (2 revolutions each).
    pub model_runs: u64,
    /// Wall time, s.
    pub wall_s: f64,
}

impl NothingPasses {
    pub(crate) fn new(
        args: &McSpec,
        fpr: Option<u32>,
        (x, p): (f64, Option<Probability>),
        n: u64,
        log: SearchLog,
    ) -> Self {
        let lu = args.units.symbol(units::LENGTH);
        let cam = args.units.q(units::LENGTH, log.profile.cam_tolerance_in, 5);
        let why = match p {
            Some(p) => format!(
                "P(jump) there {} of {n}, upper 95 % bound {:.3} above --p-max {}",
                p.count, p.hi95, args.p_max
            ),
            None => format!("P(jump) there is above --p-max {}", args.p_max),
        };
        NothingPasses {
            search: "tolerance".into(),
            waviness_fpr: fpr.unwrap_or(crate::actual::DEFAULT_FPR),
            nothing_passes: format!(
                "nothing passes down to ±{cam} {lu} ({x} x VI.1's cam tolerance): {why}"
            ),
            smallest_factor_tried: x,
            smallest_cam_tolerance_in: Length::inch(log.profile.cam_tolerance_in),
            roller_tolerance_in: Length::inch(log.profile.roller_tolerance_in),
            eccentricity_tolerance_in: Length::inch(log.profile.eccentricity_tolerance_in),
            p_jump: p,
            criterion: log.criterion,
            samples: n,
            seed: args.actual.seed(),
            model: log.model,
            tolerance_factors_tried: log.tried,
            model_runs: log.model_runs,
            wall_s: log.wall_s,
        }
    }

    /// The row as the command's one-line error: `FPR 57: nothing passes down to ...`.
    pub fn error_line(&self) -> String {
        format!("FPR {}: {}", self.waviness_fpr, self.nothing_passes)
    }
}

/// A row of `design tolerance`'s table: the search's answer, or nothing passes.
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
pub enum ToleranceRow {
    /// The loosest passing cam tolerance.
    Answer(McSearchReport),
    /// Nothing passes at this FPR.
    NothingPasses(NothingPasses),
}

impl ToleranceRow {
    /// The answer, if the row has one.
    pub fn answer(&self) -> Option<&McSearchReport> {
        match self {
            ToleranceRow::Answer(r) => Some(r),
            ToleranceRow::NothingPasses(_) => None,
        }
    }

    fn model_runs(&self) -> u64 {
        self.answer().map_or_else(
            || self.nothing_passes().map_or(0, |n| n.model_runs),
            |r| r.model_runs,
        )
    }

    fn wall_s(&self) -> f64 {
        self.answer().map_or_else(
            || self.nothing_passes().map_or(0.0, |n| n.wall_s),
            |r| r.wall_s,
        )
    }

    /// Why nothing passes, if so.
    pub fn nothing_passes(&self) -> Option<&NothingPasses> {
        match self {
            ToleranceRow::Answer(_) => None,
            ToleranceRow::NothingPasses(n) => Some(n),
        }
    }

    fn json_value(&self) -> serde_json::Result<serde_json::Value> {
        match self {
            ToleranceRow::Answer(r) => r.json_value(),
            ToleranceRow::NothingPasses(n) => serde_json::to_value(n),
        }
    }
}

/// `design tolerance`'s answers, one a waviness (JSON: an array of the searches).
#[derive(Clone, Debug, Serialize)]
#[serde(transparent)]
pub struct ToleranceTable(pub Vec<ToleranceRow>);

impl Report for ToleranceTable {
    fn json(&self) -> serde_json::Result<String> {
        let rows = self
            .0
            .iter()
            .map(ToleranceRow::json_value)
            .collect::<serde_json::Result<Vec<_>>>()?;
        crate::report::sorted_pretty_json(&rows)
    }
    fn text(&self, units: crate::units::Units) -> String {
        use std::fmt::Write;
        let answers: Vec<&McSearchReport> =
            self.0.iter().filter_map(ToleranceRow::answer).collect();
        if self.0.len() == 1 || answers.iter().any(|r| r.search != "tolerance") {
            return answers.iter().map(|r| r.text(units)).collect();
        }
        let lu = units.symbol(units::LENGTH);
        let mut out = String::new();
        let _ = writeln!(
            out,
            "camsim design tolerance: the loosest cam tolerance at each waviness"
        );
        let _ = writeln!(
            out,
            "  {:>5}  {:>12}  {:>14}  {:>22}  {:>9}",
            "FPR",
            "x VI.1's cam",
            format!("cam ± {lu}"),
            "P(jump) there",
            "fails at"
        );
        for row in &self.0 {
            let r = match row {
                ToleranceRow::Answer(r) => r,
                ToleranceRow::NothingPasses(n) => {
                    let _ = writeln!(out, "  {:>5}  {}", n.waviness_fpr, n.nothing_passes);
                    continue;
                }
            };
            let p = r.p_jump.map_or_else(|| "-".to_string(), |p| p.text(3));
            let fails = r
                .failing
                .map_or_else(|| "none".to_string(), |f| format!("{f:.3}"));
            let _ = writeln!(
                out,
                "  {:>5}  {:>12.3}  {:>14}  {:>22}  {:>9}",
                r.waviness_fpr.unwrap_or(0),
                r.answer,
                units
                    .q(
                        units::LENGTH,
                        r.cam_tolerance_in.map_or(0.0, Length::in_inch),
                        5
                    )
                    .to_string(),
                p,
                fails
            );
        }
        if let Some(r) = answers.first() {
            let _ = writeln!(
                out,
                "  held: roller ±{} {lu}, eccentricity ±{} {lu}",
                units.q(
                    units::LENGTH,
                    r.roller_tolerance_in.map_or(0.0, Length::in_inch),
                    6
                ),
                units.q(
                    units::LENGTH,
                    r.eccentricity_tolerance_in.map_or(0.0, Length::in_inch),
                    5
                ),
            );
            let fpr = format!("waviness FPR {}", r.waviness_fpr.unwrap_or(0));
            let criterion = r.criterion.replace(&fpr, "waviness the row's FPR");
            let _ = writeln!(out, "  criterion: {criterion}");
            let _ = writeln!(out, "  model: {}", r.model);
        }
        let runs: u64 = self.0.iter().map(ToleranceRow::model_runs).sum();
        let wall: f64 = self.0.iter().map(ToleranceRow::wall_s).sum();
        let _ = writeln!(out, "  {runs} model runs of 2 revolutions, {wall:.1} s");
        out
    }
}
