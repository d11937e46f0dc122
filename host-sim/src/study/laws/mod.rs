//! The peak dimensionless coefficients of every Appendix A motion law for a unit rise
//! over a unit angle, and the largest pressure angle each gives on the reference cam
//! (VI.1 geometry and timing, the law used for both rise and return). The study has no
//! inputs: [`report()`] returns the [`LawsReport`] (its text in [`mod@text`], its figure in
//! [`mod@figure`]); `camsim laws` (crate::cmd::laws) prints it and draws the figure.

use camsim_core::{CamGeometry, CamProgram, LawValue, MotionLaw, PeakScan, ScanEnds};
use serde::Serialize;

pub mod figure;
pub mod text;

pub use figure::{figure, PLOT_SIZE};

/// One law's peak coefficients (unit rise over a unit angle) and reference-cam pressure angle.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct LawRow {
    /// The law's name ([`MotionLaw::name`]).
    pub name: &'static str,
    /// Largest velocity coefficient, max ds/du.
    pub cv: f64,
    /// Largest acceleration coefficient, max d²s/du².
    pub ca_max: f64,
    /// Smallest acceleration coefficient, min d²s/du².
    pub ca_min: f64,
    /// Largest jerk coefficient, max d³s/du³ (impulses at jumps excluded).
    pub cj_max: f64,
    /// Smallest jerk coefficient, min d³s/du³ (impulses at jumps excluded).
    pub cj_min: f64,
    /// Largest pressure angle on the reference cam with this law for rise and return (deg).
    pub pressure_angle_max_deg: f64,
}

/// Grid intervals per unit of `u` (a power of two, a multiple of 8 so every junction is a
/// grid point).
const GRID: usize = 8 * 4096;
/// Cam-angle samples for the pressure-angle scan (before refinement).
const PHI_SAMPLES: usize = 36_000;

/// Supremum of `f(law(u))` over `[0, 1]`: dense grid, then golden section between the
/// best point's neighbours ([`PeakScan`]), keeping the best value seen (so a one-sided
/// limit at an acceleration jump is approached, and a maximum at a junction is kept).
fn sup(law: MotionLaw, f: impl Fn(LawValue<f64>) -> f64) -> f64 {
    let scan = PeakScan {
        start: 0.0,
        // Exact: GRID is a power of two, so the grid points are exactly k / GRID.
        step: 1.0 / GRID as f64,
        points: GRID + 1,
        ends: ScanEnds::Clamped,
        iterations: 100,
    };
    scan.maximize(|u| f(law.eval(u)))
        .map_or(f64::NEG_INFINITY, |p| p.value)
}

/// The table `camsim laws` prints, one row per law in the order of [`MotionLaw::ALL`].
pub fn table() -> Vec<LawRow> {
    let geometry = CamGeometry::<f64>::reference();
    MotionLaw::ALL
        .iter()
        .map(|&law| {
            let program = CamProgram::<f64>::with_laws(law, law);
            let (phi, _) = geometry.max_pressure_angle(&program, PHI_SAMPLES);
            // `+ 0.0` turns a -0 (a maximum of -sin at u = 0) into 0.
            LawRow {
                name: law.name(),
                cv: sup(law, |x| x.v) + 0.0,
                ca_max: sup(law, |x| x.a) + 0.0,
                ca_min: -sup(law, |x| -x.a) + 0.0,
                cj_max: sup(law, |x| x.j) + 0.0,
                cj_min: -sup(law, |x| -x.j) + 0.0,
                pressure_angle_max_deg: phi.to_degrees(),
            }
        })
        .collect()
}

/// Everything `camsim laws` prints: `{"laws":[{"name":..,"cv":..,..}, ..]}` with
/// `--json` (compact, keys in field order), the table without.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct LawsReport {
    /// One row per law, in the order of [`MotionLaw::ALL`].
    pub laws: Vec<LawRow>,
}

/// Computes the report.
pub fn report() -> LawsReport {
    LawsReport { laws: table() }
}
