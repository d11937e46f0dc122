//! Measured profiles: `camsim run --measured FILE.csv` (and `camsim predict
//! --measured`).
//!
//! The file format, the reader and the deviation spline are `camsim_scene_file::measured`
//! (re-exported here), shared with the firmware's build script (`CAMSIM_PROFILE`); this
//! module adds the host's file loading and statistics.
//!
//! Every error names the line it is about: `line 7: angle_deg "1O" is not a number`.

use std::path::Path;

use anyhow::Result;
use serde::Serialize;

use crate::actual::deviation_stats;
use crate::sim::{HostDeviation, PROFILE_KNOTS};

pub use camsim_scene_file::measured::{
    parse, parse_limited, Column, Measured, ParseError, MAX_MEASURED_BYTES, MAX_POINTS,
    MEASURED_KNOTS,
};

// The shared reader's spline is the host's deviation spline.
const _: () = assert!(MEASURED_KNOTS == PROFILE_KNOTS);

/// Reads and parses a measured file as `predict --measured` and the firmware's build
/// script do (`camsim_scene_file::measured::load_limited`: at most
/// [`MAX_MEASURED_BYTES`] read, a non-UTF-8 byte named by its line); errors name the
/// option, the file and the line.
pub fn load(path: &Path) -> Result<Measured> {
    camsim_scene_file::measured::load_limited(path, MAX_POINTS)
        .map_err(|e| anyhow::anyhow!("--measured {e}"))
}

/// What a measured profile is (the JSON `profile` of `camsim run --measured`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeasuredStats {
    /// Always "measured".
    pub method: &'static str,
    /// The file's second column.
    pub column: Column,
    /// Rows of the revolution (a closing row not counted).
    pub points: usize,
    /// Knots of the deviation spline over one revolution (the rows, or for radii the
    /// envelope's output points).
    pub deviation_knots: usize,
    /// RMS of the lift deviation over one revolution, in.
    pub rms_deviation_in: f64,
    /// Mean of the lift deviation, in.
    pub mean_deviation_in: f64,
    /// Largest |lift deviation|, in.
    pub max_abs_deviation_in: f64,
    /// RMS of the deviation's second derivative d²e/dθ², in/rad².
    pub rms_curvature_in_per_rad2: f64,
    /// Waviness frequency per revolution (as for `--actual`).
    pub fpr: usize,
}

/// The host's view of a measured revolution: its deviation with statistics.
pub trait MeasuredProfile {
    /// The lift deviation this revolution gives on `design` (see
    /// `camsim_scene_file::measured`) and its statistics.
    fn profile(&self, design: &camsim_core::Design<f64>) -> Result<(HostDeviation, MeasuredStats)>;
}

impl MeasuredProfile for Measured {
    fn profile(&self, design: &camsim_core::Design<f64>) -> Result<(HostDeviation, MeasuredStats)> {
        let dev: HostDeviation = *self.deviation(design).map_err(anyhow::Error::msg)?;
        let ds = deviation_stats(&dev)?;
        let knots = dev.spline().len().saturating_sub(1);
        Ok((
            dev,
            MeasuredStats {
                method: "measured",
                column: self.column,
                points: self.angles_deg.len(),
                deviation_knots: knots,
                rms_deviation_in: ds.rms_deviation_in,
                mean_deviation_in: ds.mean_deviation_in,
                max_abs_deviation_in: ds.max_abs_deviation_in,
                rms_curvature_in_per_rad2: ds.rms_curvature_in_per_rad2,
                fpr: ds.fpr,
            },
        ))
    }
}

/// A measured revolution's waviness as a study takes it (`camsim waviness --measured`,
/// `camsim run --measured`): its FPR, RMS deviation, the equivalent ± cam tolerance
/// (three times the RMS, as a tolerance is three standard deviations, IV.2.2) and the
/// `--waviness-fpr` that studies cams of that waviness.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeasuredWaviness {
    /// Waviness frequency per revolution (VI.4.1).
    pub fpr: usize,
    /// RMS of the lift deviation over one revolution, in.
    pub rms_deviation_in: f64,
    /// The equivalent ± cam tolerance, 3 × RMS, in.
    pub equivalent_tolerance_in: f64,
    /// The `--waviness-fpr` to study it with: the FPR, within the option's 2..=2000.
    pub waviness_fpr: u32,
}

impl MeasuredWaviness {
    /// From a measured profile's statistics.
    pub fn of(stats: &MeasuredStats) -> Self {
        MeasuredWaviness {
            fpr: stats.fpr,
            rms_deviation_in: stats.rms_deviation_in,
            equivalent_tolerance_in: 3.0 * stats.rms_deviation_in,
            waviness_fpr: stats.fpr.clamp(2, 2000) as u32,
        }
    }

    /// The one line both commands print, its lengths in `units`.
    pub fn line(&self, units: crate::units::Units) -> String {
        use crate::units::LENGTH;
        let unit = units.symbol(LENGTH);
        format!(
            "measured waviness: FPR {}, RMS deviation {:.3e} {unit}, equivalent cam tolerance \
             ±{:.3e} {unit} (3 sigma); study cams like it with --waviness-fpr {}",
            self.fpr,
            units.value(LENGTH, self.rms_deviation_in),
            units.value(LENGTH, self.equivalent_tolerance_in),
            self.waviness_fpr
        )
    }
}
