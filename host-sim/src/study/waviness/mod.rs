//! The waviness (FPR) an actual cam gets against its profile point
//! interval, for both profile methods, on the master seeds' profiles (the ones the
//! interval choice looks at), and the three criteria of IV.2.3 at each interval, with a
//! second reading of criterion 1: the table of docs/MODEL.md §9.6. The study takes a
//! [`Spec`] and returns a [`WavinessReport`] (its text in [`text`]); `camsim waviness`
//! (crate::cmd::waviness) builds the spec from its arguments and prints the report.
//!
//! FPR (VI.4.1, Fig. VI.14): curve portions between inflection points of the
//! displacement a revolution, counted as the local extrema of the velocity deviation
//! `de/dθ`; a single harmonic of n undulations a revolution (UPR, ISO 12181) has FPR 2n.
//!
//! Criterion 1 as read (`camsim_core::check_interval`): the actual pitch curve's
//! smallest radius of curvature is at least the roller's radius. The second reading
//! here: the radius of curvature of the actual *displacement* curve, drawn with the
//! prime circle's arc `s = R_p θ` as abscissa (both axes in inches),
//! `ρ = (1 + (y'/R_p)²)^{3/2} / |y''/R_p²|`, at least the roller's radius.

use anyhow::Result;
use camsim_core::{check_interval, Design, ProfileSpec, RandomStream};
use serde::Serialize;

use crate::actual::{self, Cams, ProfileMethod};
use crate::measured::{MeasuredProfile, MeasuredWaviness};
use crate::units::Length;

pub mod text;

/// What the table runs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Spec {
    /// The master seeds whose profiles it reads (the command's default: 1, 2, 3).
    pub seeds: Vec<u64>,
}

/// The whole-degree intervals of the table.
pub const INTERVALS_DEG: [usize; 15] = [1, 2, 3, 4, 5, 6, 8, 9, 10, 12, 15, 18, 20, 24, 30];

/// Samples of a revolution for the displacement's radius of curvature (0.05°).
const CURVATURE_SAMPLES: usize = 7200;

/// One interval.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    /// The interval, degrees.
    pub interval_deg: usize,
    /// Whether it divides every period of the reference program (criterion 3).
    pub divides_program: bool,
    /// FPR of the thesis method's master profile, one per seed.
    pub fpr_thesis: Vec<usize>,
    /// FPR of the envelope method's master profile, one per seed.
    pub fpr_envelope: Vec<usize>,
    /// Criterion 1 as read (pitch curve's radius ≥ roller radius), first seed, thesis
    /// method.
    pub pitch_curvature_ok: bool,
    /// Smallest radius of curvature of the actual pitch curve, in (first seed).
    pub min_pitch_radius_in: Length,
    /// Criterion 2 (RMS deviation ≤ mean σ), first seed.
    pub rms_ok: bool,
    /// The second reading of criterion 1: smallest radius of curvature of the actual
    /// displacement curve (abscissa `R_p θ`), in, first seed, thesis method.
    pub min_displacement_radius_in: Length,
}

/// What `camsim waviness` prints.
#[derive(Clone, Debug, Serialize)]
pub struct WavinessReport {
    /// The master seeds.
    pub seeds: Vec<u64>,
    /// The roller's radius, in.
    pub roller_radius_in: Length,
    /// The prime circle's radius, in.
    pub prime_radius_in: Length,
    /// Smallest radius of curvature of the theoretical displacement curve, in.
    pub theoretical_min_displacement_radius_in: Length,
    /// One row per interval, smallest first.
    pub rows: Vec<Row>,
}

/// Smallest radius of curvature of the displacement curve `y(θ)` + `e(θ)` drawn with
/// abscissa `R_p θ`.
fn min_displacement_radius(design: &Design<f64>, dev: Option<&crate::sim::HostDeviation>) -> f64 {
    let rp = design.geometry.prime_radius();
    let step = 2.0 * std::f64::consts::PI / CURVATURE_SAMPLES as f64;
    (0..CURVATURE_SAMPLES)
        .map(|k| {
            let th = k as f64 * step;
            let f = design.program.follower(th);
            let (mut dy, mut d2y) = (f.dy, f.d2y);
            if let Some(d) = dev {
                let e = d.deviation(th);
                dy += e.dy;
                d2y += e.d2y;
            }
            let slope = dy / rp;
            let kappa = (d2y / (rp * rp)).abs();
            (1.0 + slope * slope).powf(1.5) / kappa
        })
        .fold(f64::INFINITY, f64::min)
}

/// The table.
pub fn report(spec: &Spec) -> Result<WavinessReport> {
    let design = Design::<f64>::reference();
    let seeds = spec.seeds.clone();
    let tol = camsim_core::Tolerances::<f64>::reference();
    let mut rows = Vec::new();
    for deg in INTERVALS_DEG {
        let n = 360 / deg;
        let mut fpr = [Vec::new(), Vec::new()];
        for &seed in &seeds {
            for (k, method) in [ProfileMethod::Thesis, ProfileMethod::Envelope]
                .into_iter()
                .enumerate()
            {
                let a = Cams {
                    seed: Some(seed),
                    profile_method: method,
                    ..Cams::default()
                };
                if let Some(v) = fpr.get_mut(k) {
                    v.push(actual::master_fpr(&design, &a, n)?);
                }
            }
        }
        let first = Cams {
            seed: seeds.first().copied(),
            profile_method: ProfileMethod::Thesis,
            ..Cams::default()
        };
        let mut rng = RandomStream::<f64>::new(first.seed(), first.normal.into());
        let check = check_interval::<f64, 361, 8>(
            &ProfileSpec {
                program: &design.program,
                geometry: &design.geometry,
                tolerances: &tol,
                intervals: n,
            },
            &mut rng,
        )?;
        let dev = actual::master_profile(&design, &first, n)?;
        let [fpr_thesis, fpr_envelope] = fpr;
        rows.push(Row {
            interval_deg: deg,
            divides_program: check.divides_program,
            fpr_thesis,
            fpr_envelope,
            pitch_curvature_ok: check.curvature_ok,
            min_pitch_radius_in: Length::inch(check.min_pitch_radius),
            rms_ok: check.rms_ok,
            min_displacement_radius_in: Length::inch(min_displacement_radius(&design, Some(&dev))),
        });
    }
    Ok(WavinessReport {
        seeds,
        roller_radius_in: Length::inch(design.geometry.roller_radius),
        prime_radius_in: Length::inch(design.geometry.prime_radius()),
        theoretical_min_displacement_radius_in: Length::inch(min_displacement_radius(
            &design, None,
        )),
        rows,
    })
}

/// `--measured FILE`: the revolution's waviness on the reference design.
pub fn measured(path: &std::path::Path) -> Result<MeasuredWaviness> {
    let design = Design::<f64>::reference();
    let (_, stats) = crate::measured::load(path)?
        .profile(&design)
        .map_err(|e| anyhow::anyhow!("--measured {}: {e:#}", path.display()))?;
    Ok(MeasuredWaviness::of(&stats))
}

#[cfg(test)]
mod measured_tests {
    use super::*;

    #[test]
    fn n_sinusoidal_waves_have_fpr_2n() {
        // e = a sin nθ: e' = a n cos nθ has 2n extrema a revolution (FPR 2n), RMS a/√2,
        // the equivalent tolerance 3a/√2.
        let dir = std::env::temp_dir().join(format!("camsim-wav-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let a = 2e-4;
        for n in [3usize, 7, 20, 45] {
            let mut csv = String::from("angle_deg,deviation_in\n");
            for k in 0..720 {
                let th = (k as f64 * 0.5).to_radians();
                csv.push_str(&format!(
                    "{},{:e}\n",
                    k as f64 * 0.5,
                    a * (n as f64 * th).sin()
                ));
            }
            let f = dir.join(format!("w{n}.csv"));
            std::fs::write(&f, csv).unwrap();
            let w = measured(&f).unwrap();
            assert_eq!((w.fpr, w.waviness_fpr), (2 * n, 2 * n as u32), "n {n}");
            let rms = a / 2f64.sqrt();
            assert!((w.rms_deviation_in - rms).abs() < 1e-3 * rms, "{w:?}");
            assert_eq!(w.equivalent_tolerance_in, 3.0 * w.rms_deviation_in);
            assert!(w
                .line(crate::units::Units::Inch)
                .contains(&format!("--waviness-fpr {}", 2 * n)));
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
