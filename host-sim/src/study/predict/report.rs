//! `camsim predict`'s report: the scene and the chip's configuration, the boot-time table,
//! the interpolation checks and every reading of the scripted machine, each number with
//! its raw bits as computed. Forces and lengths carry their quantity ([`Force`],
//! [`Length`]): the text and the JSON print them in the output's family.

use anyhow::{bail, Result};
use serde::Serialize;

use camsim_chip::CHIP_GRID;
use camsim_core::Real;

use crate::units::measure::kind;
use crate::units::{Bits, Force, Length, Units};

/// A number of the report, the `f64` it is. A report is printed only when every number in
/// it is finite (`ensure_reached`, `report::ensure_finite`), so no `null` reaches the output;
/// a value that does not exist (the speed margin with no jump onset) is an absent field
/// with its reason, never an infinity. The text output formats the `f64` itself.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Num(pub f64);

impl Num {
    pub(super) fn of(x: impl Real) -> Self {
        Num(x.to_f64())
    }
}

impl Serialize for Num {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_f64(self.0)
    }
}

/// The raw bits of a value as computed: `0x` + 8 hex digits under `--f32`, 16 under f64.
pub(super) fn bits_of<T: Real>(x: T, single: bool) -> String {
    if single {
        format!("{:#010x}", (x.to_f64() as f32).to_bits())
    } else {
        format!("{:#018x}", x.to_f64().to_bits())
    }
}

/// The scene the predictor ran and its fixed configuration (`camsim-chip`).
#[derive(Clone, Debug, Serialize)]
pub struct SceneReport {
    /// The scene file given with `--scene`, or "reference" (the reference design).
    pub design: String,
    /// The measured profile given with `--measured` (absent: the theoretical cam).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub measured: Option<String>,
    /// Knots of its deviation spline (the closing knot included).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub measured_knots: Option<usize>,
    /// State size of the chip's model.
    pub states: usize,
    /// Degrees of freedom of the chip's scene.
    pub dofs: &'static str,
    /// Solver relative tolerance.
    pub rtol: f64,
    /// Solver absolute tolerance (a length).
    pub atol_in: Length,
    /// Largest step, fraction of a revolution.
    pub max_step_fraction: f64,
    /// Step control (the chip's choice, `"thesis"`: England's rule, uncapped).
    pub step_control: &'static str,
    /// Grid speeds of the table, rpm.
    pub grid_rpm: [f64; CHIP_GRID],
    /// Upper limit of the jump search, rpm.
    pub max_rpm: f64,
    /// Resolution of the jump-onset bisection, rpm.
    pub resolution_rpm: f64,
    /// Alarm-on speed margin, rpm.
    pub alarm_on_margin_rpm: f64,
    /// Alarm-off speed margin, rpm.
    pub alarm_off_margin_rpm: f64,
}

/// Raw bits of a table row.
#[derive(Clone, Debug, Serialize)]
pub struct TableBits {
    /// Grid speed.
    pub rpm: String,
    /// Smallest contact force.
    pub min_force_lb: Bits<kind::Force>,
    /// Timing errors.
    pub timing_deg: [String; 6],
}

/// One grid speed of the boot-time table.
#[derive(Clone, Debug, Serialize)]
pub struct TableRow {
    /// Grid speed, rpm.
    pub rpm: Num,
    /// Smallest contact force in revolution 2.
    pub min_force_lb: Force,
    /// Its cam angle, degrees.
    pub min_force_deg: Num,
    /// Whether the follower separated.
    pub jumped: bool,
    /// Timing errors (rise 10/50/90 %, return 10/50/90 %), degrees.
    pub timing_deg: [Num; 6],
    /// The same as raw bits.
    pub bits: TableBits,
}

/// Raw bits of an interpolation check.
#[derive(Clone, Debug, Serialize)]
pub struct CheckBits {
    /// Direct smallest contact force.
    pub direct_force_lb: Bits<kind::Force>,
    /// Direct timing errors.
    pub direct_timing_deg: [String; 6],
}

/// One interpolation check: the table's prediction against a direct simulation.
#[derive(Clone, Debug, Serialize)]
pub struct CheckRow {
    /// Speed, rpm.
    pub rpm: Num,
    /// Interpolated smallest contact force.
    pub interp_force_lb: Force,
    /// Directly simulated smallest contact force.
    pub direct_force_lb: Force,
    /// Whether the direct run separated.
    pub direct_jumped: bool,
    /// |interpolated − direct| force.
    pub abs_err_force_lb: Force,
    /// Largest |interpolated − direct| timing error, degrees.
    pub max_abs_err_timing_deg: f64,
    /// Direct timing errors, degrees.
    pub direct_timing_deg: [Num; 6],
    /// The direct values as raw bits.
    pub bits: CheckBits,
}

/// Raw bits of a sample's prediction.
#[derive(Clone, Debug, Serialize)]
pub struct SampleBits {
    /// Force margin.
    pub force_margin_lb: Bits<kind::Force>,
    /// Speed margin.
    pub speed_margin_rpm: String,
    /// Timing errors.
    pub timing_deg: [String; 6],
}

/// A vouched speed reading of the scripted machine and the prediction for it.
#[derive(Clone, Debug, Serialize)]
pub struct SampleRow {
    /// Index of the reading (among all readings, faults included).
    pub reading: usize,
    /// Measured speed, rpm.
    pub rpm: Num,
    /// Interpolated smallest contact force.
    pub force_margin_lb: Force,
    /// Jump-onset speed minus the measured speed, rpm (absent when no jump onset was found
    /// up to the search limit: `speed_margin_absent` says so).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speed_margin_rpm: Option<Num>,
    /// Why `speed_margin_rpm` is absent.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speed_margin_absent: Option<String>,
    /// Whether the speed lies on the grid.
    pub in_grid: bool,
    /// Alarm state after this sample.
    pub alarm: bool,
    /// Interpolated timing errors, degrees.
    pub timing_deg: [Num; 6],
    /// The prediction as raw bits.
    pub bits: SampleBits,
}

/// A reading that does not vouch for the speed: the predictor makes no prediction and
/// asserts the alarm.
#[derive(Clone, Debug, Serialize)]
pub struct FaultRow {
    /// Index of the reading (among all readings).
    pub reading: usize,
    /// What it is: `out_of_range`, `too_short`, `bounce`, `step`, `lost`, `acquiring`,
    /// `overrun` (`camsim_core::SpeedReading::kind`).
    pub kind: &'static str,
    /// The measured speed of an `out_of_range` reading, rpm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rpm: Option<Num>,
    /// The period of a rejected pulse, ticks of the 1 MHz capture timer.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub period_ticks: Option<u32>,
    /// Alarm state after this reading.
    pub alarm: bool,
}

/// A reading at which the alarm switched.
#[derive(Clone, Debug, Serialize)]
pub struct AlarmTransition {
    /// Index of the reading.
    pub reading: usize,
    /// What it is (`camsim_core::SpeedReading::kind`).
    pub kind: &'static str,
    /// Its speed, rpm, if it measured one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rpm: Option<Num>,
    /// The new alarm state (true: asserted).
    pub alarm: bool,
}

/// What `camsim predict` prints: the text output and `--json` are both this report.
#[derive(Clone, Debug, Serialize)]
pub struct PredictReport {
    /// "f32" or "f64".
    pub precision: &'static str,
    /// The scene run and the chip's configuration.
    pub scene: SceneReport,
    /// Jump-onset speed, rpm (absent: none up to the search limit).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump_rpm: Option<Num>,
    /// Its raw bits (absent with it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump_rpm_bits: Option<String>,
    /// The boot-time table.
    pub table: Vec<TableRow>,
    /// The interpolation checks.
    pub interp_checks: Vec<CheckRow>,
    /// Every vouched reading of the scripted machine with its prediction.
    pub samples: Vec<SampleRow>,
    /// Every other reading (faults and acquisitions): no prediction, alarm asserted.
    pub faults: Vec<FaultRow>,
    /// The readings at which the alarm switched.
    pub alarm_transitions: Vec<AlarmTransition>,
}

/// The six timing points of a row, in the order of `timing_deg`.
const TIMING_POINTS: [&str; 6] = [
    "rise 10 %",
    "rise 50 %",
    "rise 90 %",
    "return 10 %",
    "return 50 %",
    "return 90 %",
];

/// Refuses a table with a timing point the follower never crossed (its timing error is
/// not a number): the first such row and point, with the row's contact (its force in
/// `units`), as the error.
pub(super) fn ensure_reached(r: &PredictReport, units: Units) -> Result<()> {
    for row in &r.table {
        let missing = row.timing_deg.iter().zip(TIMING_POINTS);
        if let Some((_, point)) = missing.into_iter().find(|(v, _)| !v.0.is_finite()) {
            bail!(
                "not reached: at {:.1} rpm the follower never crosses the {point} lift point ({}, smallest contact force {} {}), so the timing table has no value there; nothing was reported (a stiffer spring or a lower speed range keeps the follower on the cam)",
                row.rpm.0,
                if row.jumped { "it left the cam" } else { "it stayed on the cam" },
                units.show(row.min_force_lb, 4),
                units.unit_of(row.min_force_lb)
            );
        }
    }
    Ok(())
}
