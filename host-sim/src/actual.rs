//! Actual (machined) cams on the host: the command-line options every command that
//! simulates an actual cam shares ([`ActualArgs`], to be `#[command(flatten)]`ed), and
//! the one function that turns them into a profile ([`build_profile`]).
//!
//! Sample `i` of a study with `--seed S` draws its profile from
//! `RandomStream::for_sample(S, i, method)`: its profile depends on `(S, i)` and the
//! options alone, never on which other samples ran or on which thread, so a study is
//! reproducible bit for bit for any thread count or sharding. `camsim run --actual` is
//! sample 0.
//!
//! The profile methods (docs/MODEL.md §8):
//! * `thesis` (IV.2.3): normal deviates of the lift with the linearised standard
//!   deviation of Appendix E at every `Δθ`, joined by a periodic spline
//!   ([`DeviatedLift::thesis`]);
//! * `envelope` (beyond the thesis): the cutter setting points of IV.2.2 with their
//!   two-dimensional errors, the roller radius and the cam's eccentric offset drawn
//!   once, and the roller centre placed by exact contact with the splined contour.

use anyhow::{bail, Context, Result};
use camsim_core::{
    choose_interval, ActualCam, Design, DeviatedLift, NormalMethod, RandomStream, Tolerances,
};
use clap::ValueEnum;
use serde::Serialize;

use crate::sim::{HostDeviation, PROFILE_KNOTS};

/// How an actual cam's lift is made from its tolerances.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ProfileMethod {
    /// The thesis's one-dimensional method (IV.2.3): random lift points within the
    /// linearised tolerance band, spline-fitted.
    #[default]
    Thesis,
    /// Exact contact of the roller circle with the random cam contour of IV.2.2.
    Envelope,
}

impl ProfileMethod {
    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            ProfileMethod::Thesis => "thesis",
            ProfileMethod::Envelope => "envelope",
        }
    }
}

/// How the normal deviates are made (`--normal`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum, Serialize)]
pub enum NormalArg {
    /// Appendix B: the sum of 12 uniforms minus 6 (the thesis's; tails cut at ±6σ).
    #[default]
    #[value(name = "sum12")]
    #[serde(rename = "sum12")]
    Sum12,
    /// Marsaglia's polar method: exactly normal.
    #[value(name = "polar", alias = "exact")]
    #[serde(rename = "polar")]
    Polar,
}

impl NormalArg {
    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            NormalArg::Sum12 => "sum12",
            NormalArg::Polar => "polar",
        }
    }
}

impl From<NormalArg> for NormalMethod {
    fn from(n: NormalArg) -> Self {
        match n {
            NormalArg::Sum12 => NormalMethod::SumOfTwelve,
            NormalArg::Polar => NormalMethod::Polar,
        }
    }
}

/// The default `--seed`.
pub const DEFAULT_SEED: u64 = 1;

/// Command-line options of an actual cam (`#[command(flatten)]` them).
#[derive(clap::Args, Debug, Clone, Default, PartialEq)]
pub struct ActualArgs {
    /// Simulate an actual (machined) cam drawn from the tolerances below instead of the
    /// theoretical cam.
    #[arg(long)]
    pub actual: bool,
    /// Cam profile tolerance, ± in (3σ of each coordinate of a cutter setting point;
    /// default 0.0005, the thesis's VI.1).
    #[arg(long, value_name = "IN", allow_negative_numbers = true, value_parser = crate::args::tolerance_in)]
    pub cam_tolerance: Option<f64>,
    /// Roller radius tolerance, ± in (default 0.0001).
    #[arg(long, value_name = "IN", allow_negative_numbers = true, value_parser = crate::args::tolerance_in)]
    pub roller_tolerance: Option<f64>,
    /// Camshaft-bearing non-roundness and base-circle eccentricity together, ± in
    /// (default 0.001).
    #[arg(long, value_name = "IN", allow_negative_numbers = true, value_parser = crate::args::tolerance_in)]
    pub eccentricity_tolerance: Option<f64>,
    /// Profile point interval, degrees (360/interval a whole number, at most 3600
    /// points); default: the smallest whole-degree interval passing the three criteria
    /// of IV.2.3, checked on a profile drawn from the master seed.
    #[arg(long, value_name = "DEG", allow_negative_numbers = true, value_parser = interval_deg)]
    pub interval_deg: Option<f64>,
    /// Master seed: sample i's profile comes from (seed, i) alone (default 1).
    #[arg(long)]
    pub seed: Option<u64>,
    /// How the lift is made from the tolerances.
    #[arg(long, value_enum, default_value_t = ProfileMethod::Thesis)]
    pub profile_method: ProfileMethod,
    /// Normal deviates: sum12 (Appendix B) or polar (exact; alias "exact").
    #[arg(long, value_enum, default_value_t = NormalArg::Sum12)]
    pub normal: NormalArg,
}

impl ActualArgs {
    /// The tolerances (the thesis's VI.1 values where not given).
    pub fn tolerances(&self) -> Result<Tolerances<f64>> {
        let r = Tolerances::<f64>::reference();
        Ok(Tolerances::new(
            self.cam_tolerance.unwrap_or(r.cam),
            self.roller_tolerance.unwrap_or(r.roller),
            self.eccentricity_tolerance.unwrap_or(r.eccentricity),
        )?)
    }

    /// The master seed.
    pub fn seed(&self) -> u64 {
        self.seed.unwrap_or(DEFAULT_SEED)
    }

    /// Whether any option other than `--actual` was given (a caller that simulates
    /// the theoretical cam refuses them).
    pub fn any_profile_option(&self) -> bool {
        let d = ActualArgs::default();
        self.cam_tolerance.is_some()
            || self.roller_tolerance.is_some()
            || self.eccentricity_tolerance.is_some()
            || self.interval_deg.is_some()
            || self.seed.is_some()
            || self.profile_method != d.profile_method
            || self.normal != d.normal
    }
}

/// `--interval-deg`: positive, and 360/interval a whole number of points (within
/// 1e-9), at most `PROFILE_KNOTS − 1`.
pub fn interval_deg(s: &str) -> Result<f64, String> {
    let x: f64 = s.trim().parse().map_err(|_| "not a number".to_string())?;
    if !(x.is_finite() && x > 0.0) {
        return Err("must be positive and finite".into());
    }
    intervals_of(x).map(|_| x)
}

/// Intervals per revolution of an interval in degrees.
fn intervals_of(deg: f64) -> Result<usize, String> {
    let q = 360.0 / deg;
    let n = q.round();
    if (q - n).abs() > 1e-9 * q || n < 3.0 {
        return Err("must divide 360 degrees into a whole number (at least 3) of intervals".into());
    }
    if n >= PROFILE_KNOTS as f64 {
        return Err(format!(
            "at most {} intervals per revolution (at least {} degrees)",
            PROFILE_KNOTS - 1,
            360.0 / (PROFILE_KNOTS - 1) as f64
        ));
    }
    Ok(n as usize)
}

/// How the interval was set.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum IntervalSource {
    /// `--interval-deg`.
    Given,
    /// The three criteria of IV.2.3 (`choose_interval` on the master seed's stream).
    Criteria,
}

impl IntervalSource {
    /// How a report says it.
    pub fn name(self) -> &'static str {
        match self {
            IntervalSource::Given => "given",
            IntervalSource::Criteria => "by the criteria of IV.2.3",
        }
    }
}

/// What a profile is and how it came about (the JSON `profile` of `camsim run --actual`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ProfileStats {
    /// The profile method.
    pub method: ProfileMethod,
    /// The normal deviates' method.
    pub normal: NormalArg,
    /// The master seed.
    pub seed: u64,
    /// The sample index (its stream is `RandomStream::for_sample(seed, sample, ..)`).
    pub sample: u64,
    /// Cam profile tolerance, ± in.
    pub cam_tolerance_in: f64,
    /// Roller radius tolerance, ± in.
    pub roller_tolerance_in: f64,
    /// Eccentricity tolerance, ± in.
    pub eccentricity_tolerance_in: f64,
    /// Profile points per revolution.
    pub intervals: usize,
    /// The interval, degrees.
    pub interval_deg: f64,
    /// How the interval was set.
    pub interval_source: IntervalSource,
    /// RMS of the lift deviation over one revolution, in.
    pub rms_deviation_in: f64,
    /// Mean of the lift deviation, in.
    pub mean_deviation_in: f64,
    /// Largest |lift deviation|, in.
    pub max_abs_deviation_in: f64,
    /// RMS of the deviation's second derivative d²e/dθ², in/rad².
    pub rms_curvature_in_per_rad2: f64,
    /// Waviness frequency per revolution (VI.4.1): local extrema of the velocity
    /// deviation `de/dθ` over one revolution (see [`FPR_SAMPLES`], [`FPR_THRESHOLD`]).
    pub fpr: usize,
    /// Knots of the deviation spline over one revolution (`intervals` for the thesis's
    /// method, [`envelope_knots`] for the envelope).
    pub deviation_knots: usize,
    /// The envelope's actual roller radius, in (None for the thesis's method).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub roller_radius_in: Option<f64>,
    /// The envelope's rotation-centre offset (x, y) in the cam frame, in (None for the
    /// thesis's method).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub centre_offset_in: Option<[f64; 2]>,
}

/// Points of the envelope's deviation spline for a contour of `intervals` setting
/// points: 8 a setting interval (the contact jumps between the bumps of the contour,
/// which are about a setting interval apart), at most `PROFILE_KNOTS − 1` (0.1°).
pub fn envelope_knots(intervals: usize) -> usize {
    // One rule with measured radius profiles (the shared reader's).
    camsim_scene_file::measured::envelope_knots(intervals)
}

/// Samples of one revolution at which the statistics are taken (0.05°).
pub const FPR_SAMPLES: usize = 7200;

/// The FPR's hysteresis, as a fraction of the velocity deviation's peak-to-peak range
/// (ripples smaller than that are not counted; a zero deviation has FPR 0), but at
/// least [`FPR_FLOOR`].
pub const FPR_THRESHOLD: f64 = 0.01;

/// The smallest FPR hysteresis, in/rad: ripples of the velocity deviation below it
/// (a lift ripple of 1e-6 in/rad × 1° ≈ 2e-8 in, far below any tolerance) are the
/// interpolation noise of a perfect profile, not waviness.
pub const FPR_FLOOR: f64 = 1e-6;

/// Statistics of a lift deviation `e(θ)` over one revolution, from [`FPR_SAMPLES`]
/// equal steps.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct DeviationStats {
    /// RMS of `e`, in.
    pub rms_deviation_in: f64,
    /// Mean of `e`, in (a roller riding on the crests of a wavy contour sits high).
    pub mean_deviation_in: f64,
    /// Largest `|e|`, in.
    pub max_abs_deviation_in: f64,
    /// RMS of `d²e/dθ²`, in/rad² (what the waviness adds to the follower's
    /// acceleration, times ω²).
    pub rms_curvature_in_per_rad2: f64,
    /// Local extrema of `de/dθ` (VI.4.1, see [`FPR_THRESHOLD`]).
    pub fpr: usize,
}

/// The statistics of a deviation (see [`DeviationStats`]).
pub fn deviation_stats(dev: &HostDeviation) -> Result<DeviationStats> {
    let step = 2.0 * std::f64::consts::PI / FPR_SAMPLES as f64;
    let (mut sum, mut sq, mut sq2, mut max) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for k in 0..FPR_SAMPLES {
        let e = dev.deviation(k as f64 * step);
        sum += e.y;
        sq += e.y * e.y;
        sq2 += e.d2y * e.d2y;
        max = max.max(e.y.abs());
        lo = lo.min(e.dy);
        hi = hi.max(e.dy);
    }
    let threshold = (FPR_THRESHOLD * (hi - lo)).max(FPR_FLOOR);
    let fpr = camsim_core::waviness_fpr_of(FPR_SAMPLES, threshold, |k| {
        dev.deviation(k as f64 * step).dy
    })?;
    let n = FPR_SAMPLES as f64;
    Ok(DeviationStats {
        rms_deviation_in: (sq / n).sqrt(),
        mean_deviation_in: sum / n,
        max_abs_deviation_in: max,
        rms_curvature_in_per_rad2: (sq2 / n).sqrt(),
        fpr,
    })
}

/// Intervals per revolution for `args` on `design`: `--interval-deg`, or the smallest
/// whole-degree interval passing the three criteria of IV.2.3 on a profile drawn from
/// the master seed's own stream (`RandomStream::new(seed, method)`, the same for every
/// sample).
pub fn intervals_for(design: &Design<f64>, args: &ActualArgs) -> Result<(usize, IntervalSource)> {
    if let Some(deg) = args.interval_deg {
        let n = intervals_of(deg).map_err(|e| anyhow::anyhow!("--interval-deg {deg}: {e}"))?;
        return Ok((n, IntervalSource::Given));
    }
    let tol = args.tolerances()?;
    let choice = choose_interval::<f64, 361, 8>(
        &design.program,
        &design.geometry,
        &tol,
        args.seed(),
        args.normal.into(),
    )?;
    match choice.chosen() {
        Some(c) => Ok((c.intervals, IntervalSource::Criteria)),
        None => bail!(
            "no whole-degree interval passes the three criteria of IV.2.3 for these \
             tolerances and seed (tried {}); give --interval-deg",
            choice
                .candidates
                .iter()
                .map(|c| format!("{}", c.interval_deg))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// The actual cam of sample `sample` for `args` on `design`, and its statistics.
///
/// Its random numbers come from `RandomStream::for_sample(seed, sample, method)` alone.
/// `args.actual` is not looked at (the caller decided to build a profile).
pub fn build_profile(
    design: &Design<f64>,
    args: &ActualArgs,
    sample: u64,
) -> Result<(HostDeviation, ProfileStats)> {
    let tol = args.tolerances()?;
    let (intervals, source) = intervals_for(design, args)?;
    let seed = args.seed();
    let mut rng = RandomStream::<f64>::for_sample(seed, sample, args.normal.into());
    let (program, geometry) = (&design.program, &design.geometry);
    let (dev, cam_parts): (HostDeviation, _) = match args.profile_method {
        ProfileMethod::Thesis => (
            DeviatedLift::thesis(program, geometry, &tol, intervals, &mut rng)?,
            None,
        ),
        ProfileMethod::Envelope => {
            let cam = Box::new(ActualCam::<f64, PROFILE_KNOTS>::generate(
                program, geometry, &tol, intervals, &mut rng,
            )?);
            let dev = DeviatedLift::envelope(program, geometry, &cam, envelope_knots(intervals))
                .context("the roller's envelope on the actual contour")?;
            (dev, Some((cam.roller_radius, [cam.centre.0, cam.centre.1])))
        }
    };
    let ds = deviation_stats(&dev).context("profile statistics")?;
    let stats = ProfileStats {
        method: args.profile_method,
        normal: args.normal,
        seed,
        sample,
        cam_tolerance_in: tol.cam,
        roller_tolerance_in: tol.roller,
        eccentricity_tolerance_in: tol.eccentricity,
        intervals,
        interval_deg: 360.0 / intervals as f64,
        interval_source: source,
        rms_deviation_in: ds.rms_deviation_in,
        mean_deviation_in: ds.mean_deviation_in,
        max_abs_deviation_in: ds.max_abs_deviation_in,
        rms_curvature_in_per_rad2: ds.rms_curvature_in_per_rad2,
        fpr: ds.fpr,
        deviation_knots: dev.spline().len().saturating_sub(1),
        roller_radius_in: cam_parts.map(|c| c.0),
        centre_offset_in: cam_parts.map(|c| c.1),
    };
    Ok((dev, stats))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interval_values() {
        assert_eq!(interval_deg("1"), Ok(1.0));
        assert_eq!(interval_deg("0.5"), Ok(0.5));
        assert_eq!(interval_deg("0.1"), Ok(0.1));
        for bad in ["0", "-1", "7", "0.05", "NaN", "200", "x"] {
            assert!(interval_deg(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn a_sample_depends_on_its_seed_and_index_alone() {
        let d = Design::<f64>::reference();
        let a = ActualArgs {
            actual: true,
            interval_deg: Some(2.0),
            ..Default::default()
        };
        let (p3, s3) = build_profile(&d, &a, 3).unwrap();
        // Built again, after other samples: the same profile.
        let _ = build_profile(&d, &a, 7).unwrap();
        let (q3, t3) = build_profile(&d, &a, 3).unwrap();
        assert_eq!((&p3, &s3), (&q3, &t3));
        let (p4, _) = build_profile(&d, &a, 4).unwrap();
        assert_ne!(p3, p4);
        assert_eq!(
            (s3.intervals, s3.interval_source),
            (180, IntervalSource::Given)
        );
        assert_eq!((s3.seed, s3.sample), (DEFAULT_SEED, 3));
        // The RMS deviation is of the order of the tolerance band's σ (0.0005/3 on a
        // dwell, more on the flanks), and FPR ≈ 0.8 per interval (see camsim-core's
        // profile tests): a loose sanity range here.
        assert!(
            s3.rms_deviation_in > 0.5e-4 && s3.rms_deviation_in < 4e-4,
            "{s3:?}"
        );
        assert!(s3.max_abs_deviation_in >= s3.rms_deviation_in);
        assert!(s3.fpr > 100 && s3.fpr < 200 && s3.fpr % 2 == 0, "{s3:?}");
        // Zero tolerances: zero deviation, FPR 0.
        let z = ActualArgs {
            cam_tolerance: Some(0.0),
            roller_tolerance: Some(0.0),
            eccentricity_tolerance: Some(0.0),
            ..a
        };
        let (_, s) = build_profile(&d, &z, 0).unwrap();
        assert_eq!(
            (s.rms_deviation_in, s.max_abs_deviation_in, s.fpr),
            (0.0, 0.0, 0)
        );
    }

    #[test]
    fn the_default_interval_comes_from_the_master_seed() {
        // Criterion 2 is decided by the sample (camsim-core's profile docs): the
        // choice depends on the master seed, the same for every sample of a study.
        let d = Design::<f64>::reference();
        let a = ActualArgs::default();
        let (n, src) = intervals_for(&d, &a).unwrap();
        assert_eq!(src, IntervalSource::Criteria);
        assert!(360 % n == 0 && n <= 360, "{n}");
        let (_, s0) = build_profile(&d, &a, 0).unwrap();
        let (_, s9) = build_profile(&d, &a, 9).unwrap();
        assert_eq!((s0.intervals, s9.intervals), (n, n));
    }
}
