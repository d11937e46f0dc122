//! `camsim waviness`: the waviness (FPR) an actual cam gets against its profile point
//! interval, for both profile methods, on the master seeds' profiles (the ones the
//! interval choice looks at), and the three criteria of IV.2.3 at each interval, with a
//! second reading of criterion 1. It prints the table of docs/MODEL.md §9.6.
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

use crate::actual::{self, ActualArgs, ProfileMethod};
use crate::measured::{MeasuredProfile, MeasuredWaviness};
use crate::report::Report;

/// Command-line options.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Master seeds (default 1,2,3).
    #[arg(long, value_delimiter = ',', value_parser = crate::args::seed)]
    pub seeds: Vec<u64>,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Instead of the table, a measured revolution's waviness (the CSV of `run
    /// --measured`, on the reference design): its FPR, RMS deviation, the equivalent
    /// ± cam tolerance (3 sigma) and the --waviness-fpr to study cams like it with.
    #[arg(long, value_name = "FILE", conflicts_with = "seeds")]
    pub measured: Option<std::path::PathBuf>,
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
    pub min_pitch_radius_in: f64,
    /// Criterion 2 (RMS deviation ≤ mean σ), first seed.
    pub rms_ok: bool,
    /// The second reading of criterion 1: smallest radius of curvature of the actual
    /// displacement curve (abscissa `R_p θ`), in, first seed, thesis method.
    pub min_displacement_radius_in: f64,
}

/// What `camsim waviness` prints.
#[derive(Clone, Debug, Serialize)]
pub struct WavinessReport {
    /// The master seeds.
    pub seeds: Vec<u64>,
    /// The roller's radius, in.
    pub roller_radius_in: f64,
    /// The prime circle's radius, in.
    pub prime_radius_in: f64,
    /// Smallest radius of curvature of the theoretical displacement curve, in.
    pub theoretical_min_displacement_radius_in: f64,
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
pub fn report(args: &Args) -> Result<WavinessReport> {
    let design = Design::<f64>::reference();
    let seeds = if args.seeds.is_empty() {
        vec![1, 2, 3]
    } else {
        args.seeds.clone()
    };
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
                let a = ActualArgs {
                    seed: Some(seed),
                    profile_method: method,
                    ..ActualArgs::default()
                };
                if let Some(v) = fpr.get_mut(k) {
                    v.push(actual::master_fpr(&design, &a, n)?);
                }
            }
        }
        let first = ActualArgs {
            seed: seeds.first().copied(),
            profile_method: ProfileMethod::Thesis,
            ..ActualArgs::default()
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
            min_pitch_radius_in: check.min_pitch_radius,
            rms_ok: check.rms_ok,
            min_displacement_radius_in: min_displacement_radius(&design, Some(&dev)),
        });
    }
    Ok(WavinessReport {
        seeds,
        roller_radius_in: design.geometry.roller_radius,
        prime_radius_in: design.geometry.prime_radius(),
        theoretical_min_displacement_radius_in: min_displacement_radius(&design, None),
        rows,
    })
}

/// Runs the command.
pub fn run(args: Args, units: crate::units::Units) -> Result<()> {
    if let Some(path) = &args.measured {
        return crate::report::print(&measured(path)?, args.json, units);
    }
    crate::report::print(&report(&args)?, args.json, units)
}

/// `--measured FILE`: the revolution's waviness on the reference design.
pub fn measured(path: &std::path::Path) -> Result<MeasuredWaviness> {
    let design = Design::<f64>::reference();
    let (_, stats) = crate::measured::load(path)?
        .profile(&design)
        .map_err(|e| anyhow::anyhow!("--measured {}: {e:#}", path.display()))?;
    Ok(MeasuredWaviness::of(&stats))
}

impl Report for MeasuredWaviness {
    fn text(&self, units: crate::units::Units) -> String {
        format!("{}\n", self.line(units))
    }
}

fn range(v: &[usize]) -> String {
    let lo = v.iter().min().copied().unwrap_or(0);
    let hi = v.iter().max().copied().unwrap_or(0);
    if lo == hi {
        format!("{lo}")
    } else {
        format!("{lo}-{hi}")
    }
}

impl Report for WavinessReport {
    fn text(&self, _units: crate::units::Units) -> String {
        use crate::units::{given, q, symbol, LENGTH};
        use std::fmt::Write;
        let mut out = String::new();
        // Lengths in the output's family (`--units`); the tolerances as given (VI.1's).
        let unit = symbol(LENGTH);
        let tol = camsim_core::Tolerances::<f64>::reference();
        let seeds: Vec<String> = self.seeds.iter().map(|s| s.to_string()).collect();
        let _ = writeln!(
            out,
            "camsim waviness: the reference design at VI.1's tolerances (cam ±{}, roller ±{}, eccentricity ±{} {unit}); \
             FPR of the master seeds' profiles ({}) against the interval, both profile methods; the criteria of IV.2.3 on seed {}'s \
             (thesis method). Roller radius {} {unit}, prime radius {} {unit}; the theoretical displacement's smallest radius of \
             curvature (abscissa R_p theta) {} {unit}. FPR 2n = a single harmonic of n undulations a revolution (UPR).",
            given(LENGTH, tol.cam),
            given(LENGTH, tol.roller),
            given(LENGTH, tol.eccentricity),
            seeds.join(", "),
            seeds.first().cloned().unwrap_or_default(),
            q(LENGTH, self.roller_radius_in, 4),
            q(LENGTH, self.prime_radius_in, 4),
            q(LENGTH, self.theoretical_min_displacement_radius_in, 4)
        );
        let _ = writeln!(
            out,
            "{:>8} {:>8} {:>11} {:>12} {:>10} {:>8} {:>10} {:>10} {:>8}",
            "deg",
            "points",
            "FPR thesis",
            "FPR envelope",
            "crit. 3",
            "rho_p",
            "crit. 1",
            "crit. 2",
            "rho_y"
        );
        let yn = |b: bool| if b { "yes" } else { "no" };
        for r in &self.rows {
            let _ = writeln!(
                out,
                "{:>8} {:>8} {:>11} {:>12} {:>10} {:>8} {:>10} {:>10} {:>8}",
                r.interval_deg,
                360 / r.interval_deg,
                range(&r.fpr_thesis),
                range(&r.fpr_envelope),
                yn(r.divides_program),
                q(LENGTH, r.min_pitch_radius_in, 3),
                yn(r.pitch_curvature_ok),
                yn(r.rms_ok),
                q(LENGTH, r.min_displacement_radius_in, 3)
            );
        }
        let _ = writeln!(
            out,
            "crit. 3: divides every period of the program; rho_p: smallest radius of curvature of the actual pitch curve, {unit} \
             (crit. 1 as read: rho_p >= roller radius); crit. 2: RMS deviation <= mean sigma; rho_y: smallest radius of \
             curvature of the actual displacement curve, {unit} (the second reading of crit. 1: rho_y >= roller radius)"
        );
        out
    }
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
