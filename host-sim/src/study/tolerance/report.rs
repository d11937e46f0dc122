//! What the tolerance study reports: its cells ([`Cell`]) and the grid
//! ([`ToleranceReport`]), with the grid's column headings ([`column_label`]).

use serde::Serialize;

use crate::study::montecarlo::{Moments, Summary};
use crate::units::{Acceleration, Length};

/// One cell of the grid.
#[derive(Clone, Debug, Serialize)]
pub struct Cell {
    /// Cam profile tolerance, ±.
    pub cam_tolerance_in: Length,
    /// Roller radius tolerance, ±.
    pub roller_tolerance_in: Length,
    /// Eccentricity tolerance, ±.
    pub eccentricity_tolerance_in: Length,
    /// The waviness asked for, FPR (absent for the theoretical cam and given intervals).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub target_fpr: Option<u32>,
    /// Profile point interval, degrees (absent for the theoretical cam).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub interval_deg: Option<f64>,
    /// The waviness achieved: mean FPR of the cell's cams (absent for the theoretical
    /// cam).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fpr: Option<f64>,
    /// Revolution 2's acceleration RMS summed over the periods, mean over the cams
    /// (absent when no cam has statistics: each left the model's valid range).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub acc_rms_sum_in_per_s2: Option<Acceleration>,
    /// Why the cell is not workable: every cam left the model's valid range with the
    /// follower on the cam (docs/MODEL.md §3.20; the first cam's reason). A cell whose
    /// cams jumped and then left it is workable: P(jump) = 1.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub not_workable: Option<String>,
    /// The cell's Monte Carlo result (revolution 2).
    pub summary: Summary,
}

impl Cell {
    /// The profiles' waviness (FPR).
    pub fn fpr_moments(&self) -> Option<&Moments> {
        self.summary.profile.get("fpr")
    }
}

/// What `camsim tolerance-study` prints.
#[derive(Clone, Debug, Serialize)]
pub struct ToleranceReport {
    /// The program's laws, rise and return.
    pub program: [String; 2],
    /// Cam speed, rpm.
    pub rpm: f64,
    /// Actual cams per cell.
    pub samples_per_cell: u64,
    /// Master seed.
    pub seed: u64,
    /// Whether the vertical scene ran (--quick).
    pub quick: bool,
    /// The theoretical cam (no tolerance).
    pub theoretical: Cell,
    /// The grid, by cam tolerance (largest first), then waviness (the axis's order).
    pub cells: Vec<Cell>,
    /// Cells a row (the waviness axis's length).
    pub columns: usize,
    /// Wall-clock time, s.
    pub wall_s: f64,
}

/// The heading of column `j` of the grid (`cols` cells a row): the waviness asked (or
/// the interval) and the range of the FPR achieved (mean of each cell's cams) down it.
pub fn column_label(cells: &[Cell], cols: usize, j: usize) -> String {
    let (lo, hi) = cells
        .iter()
        .skip(j)
        .step_by(cols.max(1))
        .filter_map(|c| c.fpr)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
    let got = if !lo.is_finite() {
        "none with statistics".to_string()
    } else if hi - lo < 0.05 {
        format!("{lo:.1}")
    } else {
        format!("{lo:.1}-{hi:.1}")
    };
    match cells.get(j) {
        Some(Cell {
            target_fpr: Some(f),
            ..
        }) => format!("FPR {f} ({got})"),
        Some(c) => format!("{} deg (FPR {got})", c.interval_deg.unwrap_or(0.0)),
        None => String::new(),
    }
}
