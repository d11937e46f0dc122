//! Actual (machined) cams on the host: the options every study that simulates an actual
//! cam holds ([`Cams`]; their command-line group is [`crate::args::ActualArgs`]), and
//! the one function that turns them into a profile ([`build_profile`]).
//!
//! Sample `i` of a study with `--seed S` draws its profile from
//! `RandomStream::for_sample(S, i, method)`: its profile depends on `(S, i)` and the
//! options alone, never on which other samples ran or on which thread, so a study is
//! reproducible bit for bit for any thread count or sharding. `camsim run --actual` is
//! sample 0.
//!
//! The profile methods (docs/MODEL.md §8):
//! * `per-cam` (the default): the thesis's contour error at every `Δθ`, the roller
//!   radius and the follower axis's offset drawn once and applied through the exact
//!   geometry ([`DeviatedLift::draw_per_cam`]);
//! * `thesis` (IV.2.3): normal deviates of the lift with the linearised standard
//!   deviation of Appendix E at every `Δθ`, joined by a periodic spline
//!   ([`DeviatedLift::thesis`]);
//! * `envelope` (beyond the thesis): the cutter setting points of IV.2.2 with their
//!   two-dimensional errors, the roller radius and the cam's eccentric offset drawn
//!   once, and the roller centre placed by exact contact with the splined contour.

use anyhow::{bail, Context, Result};
use camsim_core::{
    choose_interval, ActualCam, Design, DeviatedLift, NormalMethod, ProfileSpec, RandomStream,
    Tolerances,
};
use clap::ValueEnum;
use serde::Serialize;

use crate::sim::{HostDeviation, PROFILE_KNOTS};
use crate::units::{Length, LengthPerRad2};

/// How an actual cam's lift is made from its tolerances.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ProfileMethod {
    /// The cam contour's error per point as the thesis's (linearised), the roller
    /// radius's error and the follower axis's offset drawn once per cam and applied
    /// through the exact geometry (docs/MODEL.md §8.9).
    #[default]
    #[value(name = "per-cam")]
    #[serde(rename = "per-cam")]
    PerCam,
    /// The thesis's one-dimensional method (IV.2.3): random lift points within the
    /// linearised tolerance band, spline-fitted; the roller and eccentricity terms drawn
    /// anew at every point.
    Thesis,
    /// Exact contact of the roller circle with the random cam contour of IV.2.2.
    Envelope,
}

impl ProfileMethod {
    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            ProfileMethod::PerCam => "per-cam",
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

/// An actual cam's options, resolved from the command line (the clap group is
/// [`crate::args::ActualArgs`], whose [`cams`](crate::args::ActualArgs::cams) makes one):
/// what every study that simulates an actual cam holds. `None` and an empty list are the
/// defaults (the thesis's VI.1 tolerances, [`DEFAULT_FPR`], [`DEFAULT_SEED`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Cams {
    /// Simulate an actual (machined) cam drawn from the tolerances below instead of the
    /// theoretical cam (`--actual`).
    pub actual: bool,
    /// Cam profile tolerance, ± in (3σ of each coordinate of a cutter setting point).
    pub cam_tolerance: Option<f64>,
    /// Roller radius tolerance, ± in.
    pub roller_tolerance: Option<f64>,
    /// Camshaft-bearing non-roundness and base-circle eccentricity together, ± in.
    pub eccentricity_tolerance: Option<f64>,
    /// Profile point interval, degrees (overrides the waviness and the rule).
    pub interval_deg: Option<f64>,
    /// The waviness FPRs asked (`design tolerance` takes a list, every other study one).
    pub waviness_fpr: Vec<u32>,
    /// How the interval is set when `interval_deg` is not given.
    pub interval: IntervalRule,
    /// Master seed: sample i's profile comes from (seed, i) alone.
    pub seed: Option<u64>,
    /// How the lift is made from the tolerances.
    pub profile_method: ProfileMethod,
    /// How the normal deviates are made.
    pub normal: NormalArg,
    /// The interval once chosen ([`Cams::resolve`]): a study's samples do not repeat
    /// the choice.
    pub resolved: Option<(usize, IntervalSource)>,
}

/// How the profile point interval is chosen (`--interval`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum IntervalRule {
    /// The waviness stated by `--waviness-fpr` (default 17, the thesis's study cams).
    #[default]
    Waviness,
    /// The three criteria of IV.2.3.
    Criteria,
}

/// The default waviness: FPR 17, the thesis's study cams at VI.1's tolerances
/// (VI.4.1, Table VI.2, Figs. VI.15-VI.16).
pub const DEFAULT_FPR: u32 = 17;

impl Cams {
    /// The tolerances (the thesis's VI.1 values where not given).
    pub fn tolerances(&self) -> Result<Tolerances<f64>> {
        let r = Tolerances::<f64>::reference();
        Ok(Tolerances::new(
            self.cam_tolerance.unwrap_or(r.cam),
            self.roller_tolerance.unwrap_or(r.roller),
            self.eccentricity_tolerance.unwrap_or(r.eccentricity),
        )?)
    }

    /// The one waviness `--waviness-fpr` states (None: not given); a list is refused
    /// (a usage error: only `design tolerance` takes one).
    pub fn fpr(&self) -> Result<Option<u32>> {
        match self.waviness_fpr.as_slice() {
            [] => Ok(None),
            [f] => Ok(Some(*f)),
            list => Err(crate::args::usage(format!(
                "--waviness-fpr {}: one FPR here (only `design tolerance` takes a list)",
                fpr_list(list)
            ))),
        }
    }

    /// The same options at the one waviness `fpr` (None: the default).
    pub fn at_fpr(&self, fpr: Option<u32>) -> Cams {
        Cams {
            waviness_fpr: fpr.into_iter().collect(),
            resolved: None,
            ..self.clone()
        }
    }

    /// The master seed.
    pub fn seed(&self) -> u64 {
        self.seed.unwrap_or(DEFAULT_SEED)
    }

    /// The options with the interval chosen once ([`intervals_for`]), so that the
    /// samples built from them do not repeat the choice.
    pub fn resolve(&self, design: &Design<f64>) -> Result<Cams> {
        let mut a = self.clone();
        a.resolved = Some(intervals_for(design, self)?);
        Ok(a)
    }
}

/// An FPR list as the user writes it (`17,39,57`).
pub fn fpr_list(fprs: &[u32]) -> String {
    fprs.iter()
        .map(u32::to_string)
        .collect::<Vec<_>>()
        .join(",")
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
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum IntervalSource {
    /// `--interval-deg`.
    Given,
    /// The three criteria of IV.2.3 (`choose_interval` on the master seed's stream).
    Criteria,
    /// The stated waviness (`--waviness-fpr`, default [`DEFAULT_FPR`]): the mean FPR of
    /// the study's first [`FPR_PROBE_SAMPLES`] cams nearest it ([`interval_for_fpr`]).
    Waviness {
        /// The FPR asked for.
        target_fpr: u32,
        /// The mean FPR of the first [`FPR_PROBE_SAMPLES`] cams at the chosen interval.
        probe_fpr: f64,
    },
}

impl IntervalSource {
    /// How a report says it.
    pub fn name(self) -> &'static str {
        match self {
            IntervalSource::Given => "given",
            IntervalSource::Criteria => "by the criteria of IV.2.3",
            IntervalSource::Waviness { .. } => "for the waviness asked",
        }
    }

    /// The short text a report prints: `given`, `criteria`, `waviness FPR 17 (master
    /// seed's profile FPR 17)`.
    pub fn label(self) -> String {
        match self {
            IntervalSource::Given => "given".into(),
            IntervalSource::Criteria => "criteria".into(),
            IntervalSource::Waviness {
                target_fpr,
                probe_fpr,
            } => format!(
                "for waviness FPR {target_fpr}: samples 0-{} have FPR {probe_fpr:.2} on average",
                FPR_PROBE_SAMPLES - 1
            ),
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
    pub cam_tolerance_in: Length,
    /// Roller radius tolerance, ± in.
    pub roller_tolerance_in: Length,
    /// Eccentricity tolerance, ± in.
    pub eccentricity_tolerance_in: Length,
    /// Profile points per revolution.
    pub intervals: usize,
    /// The interval, degrees.
    pub interval_deg: f64,
    /// How the interval was set.
    pub interval_source: IntervalSource,
    /// RMS of the lift deviation over one revolution, in.
    pub rms_deviation_in: Length,
    /// Mean of the lift deviation, in.
    pub mean_deviation_in: Length,
    /// Largest |lift deviation|, in.
    pub max_abs_deviation_in: Length,
    /// RMS of the deviation's second derivative d²e/dθ², in/rad².
    pub rms_curvature_in_per_rad2: LengthPerRad2,
    /// Waviness frequency per revolution (VI.4.1): local extrema of the velocity
    /// deviation `de/dθ` over one revolution (see [`FPR_SAMPLES`], [`FPR_THRESHOLD`]).
    pub fpr: usize,
    /// Knots of the deviation spline over one revolution (`intervals` for the thesis's
    /// method, a multiple of it of at least 1440 for the per-cam method when the roller or
    /// the axis is off, [`envelope_knots`] for the envelope).
    pub deviation_knots: usize,
    /// The actual roller radius drawn once, in (the per-cam method and the envelope;
    /// None for the thesis's method).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub roller_radius_in: Option<Length>,
    /// The per-cam method's follower-axis offset, in (None for the other methods).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub axis_offset_in: Option<Length>,
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

/// Intervals per revolution for `args` on `design`: `--interval-deg`; else with
/// `--interval criteria` the smallest whole-degree interval passing the three criteria
/// of IV.2.3 on a profile drawn from the master seed's own stream
/// (`RandomStream::new(seed, method)`, the same for every sample); else the interval
/// of the waviness `--waviness-fpr` asks ([`interval_for_fpr`], default
/// [`DEFAULT_FPR`]). Options already resolved ([`Cams::resolve`]) keep their
/// choice.
pub fn intervals_for(design: &Design<f64>, args: &Cams) -> Result<(usize, IntervalSource)> {
    if let Some(r) = args.resolved {
        return Ok(r);
    }
    let fpr = args.fpr()?;
    if let Some(deg) = args.interval_deg {
        let n = intervals_of(deg).map_err(|e| anyhow::anyhow!("--interval-deg {deg}: {e}"))?;
        return Ok((n, IntervalSource::Given));
    }
    if args.interval == IntervalRule::Criteria {
        if let Some(f) = fpr {
            bail!("--waviness-fpr {f}: not with --interval criteria (the criteria choose the interval; give one or the other)");
        }
        return criteria_intervals(design, args);
    }
    let target = fpr.unwrap_or(DEFAULT_FPR);
    let (n, probe_fpr) = interval_for_fpr(design, args, target)?;
    Ok((
        n,
        IntervalSource::Waviness {
            target_fpr: target,
            probe_fpr,
        },
    ))
}

fn criteria_intervals(design: &Design<f64>, args: &Cams) -> Result<(usize, IntervalSource)> {
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

/// The FPR of the profile `args` make with `intervals` points a revolution from the
/// master seed's own stream (`RandomStream::new(seed, method)`, as the criteria use).
pub fn master_fpr(design: &Design<f64>, args: &Cams, intervals: usize) -> Result<usize> {
    Ok(deviation_stats(&master_profile(design, args, intervals)?)?.fpr)
}

/// Cams whose mean FPR sets the interval for a stated waviness: samples 0 to 7 of the
/// study's seed (the mean's standard error is then about 0.5 at FPR 17).
pub const FPR_PROBE_SAMPLES: u64 = 8;

/// The mean FPR of samples 0 to [`FPR_PROBE_SAMPLES`] − 1 with `intervals` points.
pub fn probe_fpr(design: &Design<f64>, args: &Cams, intervals: usize) -> Result<f64> {
    let mut sum = 0.0;
    for i in 0..FPR_PROBE_SAMPLES {
        let mut rng = RandomStream::<f64>::for_sample(args.seed(), i, args.normal.into());
        let (dev, _) = profile_from(design, args, intervals, &mut rng)?;
        sum += deviation_stats(&dev)?.fpr as f64;
    }
    Ok(sum / FPR_PROBE_SAMPLES as f64)
}

/// The deviation `args` make with `intervals` points a revolution from the master
/// seed's own stream (`RandomStream::new(seed, method)`).
pub fn master_profile(
    design: &Design<f64>,
    args: &Cams,
    intervals: usize,
) -> Result<HostDeviation> {
    let mut rng = RandomStream::<f64>::new(args.seed(), args.normal.into());
    Ok(profile_from(design, args, intervals, &mut rng)?.0)
}

/// The interval for a stated waviness: the whole number n of points a revolution
/// (interval 360/n degrees, any n from 3 to 720: a free interval, not only the
/// divisors of the program's periods that criterion 3 allows, which reach FPR 18-20,
/// 28-30 and 44-48 but not 39 on the reference program) whose first
/// [`FPR_PROBE_SAMPLES`] cams (samples 0-7 of the seed, the study's own) have the mean
/// FPR nearest `target` (within 0.5 ends the search); of equals the smallest n (the
/// smoothest cam). Returns n and that mean.
///
/// The FPR grows about 0.8 a point (docs/MODEL.md §9.6), so n is searched from
/// target/2 to 2·target + 8 (clamped to 3..=720). With the envelope only the n whose
/// perfect contour the spline follows within [`ENVELOPE_FIT`] of σ_c are tried (n up to
/// 360): at VI.1's tolerances 8° and finer, FPR 36 and more, so a smoother envelope cam
/// than that is not made (the nearest is, and the reports give its FPR).
pub fn interval_for_fpr(design: &Design<f64>, args: &Cams, target: u32) -> Result<(usize, f64)> {
    let t = target as usize;
    let lo = (t / 2).max(3);
    let hi = (2 * t + 8).min(720).max(lo);
    let mut best: Option<(f64, usize, f64)> = None; // (|fpr - t|, n, fpr)
                                                    // The envelope's contour is splined through the setting points: too few of them and
                                                    // the perfect cam itself is not followed (at VI.1's tolerances its RMS error passes
                                                    // the tolerance's σ at 15°). Only the n whose zero-tolerance contour follows the lift
                                                    // within ENVELOPE_FIT of σ_c are tried (8° and finer on the reference design).
    let fits = |n: usize| -> Result<bool> {
        if args.profile_method != ProfileMethod::Envelope {
            return Ok(true);
        }
        let perfect = Cams {
            cam_tolerance: Some(0.0),
            roller_tolerance: Some(0.0),
            eccentricity_tolerance: Some(0.0),
            ..args.clone()
        };
        let sigma = args.tolerances()?.cam / 3.0;
        let rms = deviation_stats(&master_profile(design, &perfect, n)?)?.rms_deviation_in;
        Ok(rms <= ENVELOPE_FIT * sigma.max(1e-6))
    };
    let hi = if args.profile_method == ProfileMethod::Envelope {
        hi.max(360)
    } else {
        hi
    };
    for n in lo..=hi {
        if !fits(n)? {
            continue;
        }
        let fpr = probe_fpr(design, args, n)
            .with_context(|| format!("--waviness-fpr {target}: the profiles with {n} points"))?;
        let d = (fpr - t as f64).abs();
        if best.is_none_or(|b| d < b.0) {
            best = Some((d, n, fpr));
        }
        // The FPR grows with n (about 0.8 a point): past the target by more than the
        // best's miss plus a margin, no larger n comes nearer.
        if d < 0.5 || best.is_some_and(|b| fpr > t as f64 && d > b.0 + 8.0) {
            break;
        }
    }
    best.map(|b| (b.1, b.2))
        .ok_or_else(|| anyhow::anyhow!("--waviness-fpr {target}: no interval to try"))
}

/// The errors drawn once per cam: the roller radius (in), the envelope's rotation-centre
/// offset (x, y, in) and the per-cam method's axis offset (in).
#[derive(Clone, Copy, Debug, Default)]
struct CamParts {
    roller_radius: Option<f64>,
    centre: Option<[f64; 2]>,
    axis_offset: Option<f64>,
}

/// The envelope's largest interpolation error of the perfect cam, as a fraction of the
/// cam tolerance's σ, for an interval [`interval_for_fpr`] may choose: 0.1 (the
/// contour's spline then adds under 1 % to the profile's variance).
pub const ENVELOPE_FIT: f64 = 0.1;

/// The deviation `args`' profile method makes with `intervals` points from `rng`, and
/// the envelope's roller radius and centre offset.
fn profile_from(
    design: &Design<f64>,
    args: &Cams,
    intervals: usize,
    rng: &mut RandomStream<f64>,
) -> Result<(HostDeviation, CamParts)> {
    let tol = args.tolerances()?;
    let (program, geometry) = (&design.program, &design.geometry);
    let spec = ProfileSpec {
        program,
        geometry,
        tolerances: &tol,
        intervals,
    };
    Ok(match args.profile_method {
        ProfileMethod::PerCam => per_cam_profile(&spec, rng)?,
        ProfileMethod::Thesis => (DeviatedLift::thesis(&spec, rng)?, CamParts::default()),
        ProfileMethod::Envelope => {
            let cam = Box::new(ActualCam::<f64, PROFILE_KNOTS>::generate(&spec, rng)?);
            let dev = DeviatedLift::envelope(program, geometry, &cam, envelope_knots(intervals))
                .context("the roller's envelope on the actual contour")?;
            let parts = CamParts {
                roller_radius: Some(cam.roller_radius),
                centre: Some([cam.centre.0, cam.centre.1]),
                axis_offset: None,
            };
            (dev, parts)
        }
    })
}

/// The per-cam method's deviation and its drawn roller radius and axis offset (its own
/// frame, not inlined: two revolution-long splines are large on a small stack).
#[inline(never)]
fn per_cam_profile(
    spec: &ProfileSpec<'_, f64, 8>,
    rng: &mut RandomStream<f64>,
) -> Result<(HostDeviation, CamParts)> {
    let mut contour = Box::new(HostDeviation::EMPTY);
    let axis = contour.draw_per_cam(spec, rng)?;
    let mut dev = Box::new(HostDeviation::EMPTY);
    dev.refit_per_cam(&contour, &axis, spec)
        .context("the roller and the follower axis on the actual cam")?;
    let parts = CamParts {
        roller_radius: Some(spec.geometry.roller_radius + axis.roller),
        axis_offset: Some(axis.offset),
        centre: None,
    };
    Ok((*dev, parts))
}

/// The actual cam of sample `sample` for `args` on `design`, and its statistics.
///
/// Its random numbers come from `RandomStream::for_sample(seed, sample, method)` alone.
/// `args.actual` is not looked at (the caller decided to build a profile).
pub fn build_profile(
    design: &Design<f64>,
    args: &Cams,
    sample: u64,
) -> Result<(HostDeviation, ProfileStats)> {
    let tol = args.tolerances()?;
    let (intervals, source) = intervals_for(design, args)?;
    let seed = args.seed();
    let mut rng = RandomStream::<f64>::for_sample(seed, sample, args.normal.into());
    let (dev, cam_parts) = profile_from(design, args, intervals, &mut rng)?;
    let ds = deviation_stats(&dev).context("profile statistics")?;
    let stats = ProfileStats {
        method: args.profile_method,
        normal: args.normal,
        seed,
        sample,
        cam_tolerance_in: Length::inch(tol.cam),
        roller_tolerance_in: Length::inch(tol.roller),
        eccentricity_tolerance_in: Length::inch(tol.eccentricity),
        intervals,
        interval_deg: 360.0 / intervals as f64,
        interval_source: source,
        rms_deviation_in: Length::inch(ds.rms_deviation_in),
        mean_deviation_in: Length::inch(ds.mean_deviation_in),
        max_abs_deviation_in: Length::inch(ds.max_abs_deviation_in),
        rms_curvature_in_per_rad2: LengthPerRad2::inch(ds.rms_curvature_in_per_rad2),
        fpr: ds.fpr,
        deviation_knots: dev.spline().len().saturating_sub(1),
        roller_radius_in: cam_parts.roller_radius.map(Length::inch),
        axis_offset_in: cam_parts.axis_offset.map(Length::inch),
        centre_offset_in: cam_parts.centre,
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
        let a = Cams {
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
            (0.5e-4..4e-4).contains(&s3.rms_deviation_in.in_inch()),
            "{s3:?}"
        );
        assert!(s3.max_abs_deviation_in.in_inch() >= s3.rms_deviation_in.in_inch());
        assert!(s3.fpr > 100 && s3.fpr < 200 && s3.fpr % 2 == 0, "{s3:?}");
        // Zero tolerances: zero deviation, FPR 0.
        let z = Cams {
            cam_tolerance: Some(0.0),
            roller_tolerance: Some(0.0),
            eccentricity_tolerance: Some(0.0),
            ..a
        };
        let (_, s) = build_profile(&d, &z, 0).unwrap();
        assert_eq!(
            (
                s.rms_deviation_in.in_inch(),
                s.max_abs_deviation_in.in_inch(),
                s.fpr
            ),
            (0.0, 0.0, 0)
        );
    }

    #[test]
    fn the_default_interval_has_the_study_cams_waviness() {
        // FPR 17 by default: the mean FPR of the first 8 cams at the chosen n is within
        // 0.5 of 17 or the nearest of every n from 3 to 60 (a wider range than the
        // search's), and every smaller n is farther (the smoothest of equals).
        let d = Design::<f64>::reference();
        let a = Cams::default();
        let (n, src) = intervals_for(&d, &a).unwrap();
        let IntervalSource::Waviness {
            target_fpr,
            probe_fpr: got,
        } = src
        else {
            panic!("{src:?}")
        };
        assert_eq!(target_fpr, DEFAULT_FPR);
        assert_eq!(got, probe_fpr(&d, &a, n).unwrap());
        let miss = |m: usize| (probe_fpr(&d, &a, m).unwrap() - 17.0).abs();
        let best = (3..=60).map(miss).fold(f64::INFINITY, f64::min);
        assert!(
            (got - 17.0).abs() < 0.5 || (got - 17.0).abs() == best,
            "n {n}: {got}"
        );
        assert!(
            (3..n).all(|m| miss(m) > (got - 17.0).abs()),
            "a smaller n is as near"
        );
        // Resolved once, the samples keep it; --interval-deg overrides; --interval
        // criteria with a stated waviness is refused on one line naming both.
        let r = a.resolve(&d).unwrap();
        assert_eq!(intervals_for(&d, &r).unwrap(), (n, src));
        let (_, s0) = build_profile(&d, &r, 0).unwrap();
        assert_eq!((s0.intervals, s0.interval_source), (n, src));
        let g = Cams {
            interval_deg: Some(5.0),
            waviness_fpr: vec![57],
            ..Cams::default()
        };
        assert_eq!(intervals_for(&d, &g).unwrap(), (72, IntervalSource::Given));
        let bad = Cams {
            interval: IntervalRule::Criteria,
            waviness_fpr: vec![39],
            ..Cams::default()
        };
        let e = intervals_for(&d, &bad).unwrap_err().to_string();
        assert!(
            e.contains("--waviness-fpr 39") && e.contains("--interval criteria"),
            "{e}"
        );
    }

    #[test]
    fn the_criteria_interval_comes_from_the_master_seed() {
        // Criterion 2 is decided by the sample (camsim-core's profile docs): the
        // choice depends on the master seed, the same for every sample of a study.
        let d = Design::<f64>::reference();
        let a = Cams {
            interval: IntervalRule::Criteria,
            ..Cams::default()
        };
        let (n, src) = intervals_for(&d, &a).unwrap();
        assert_eq!(src, IntervalSource::Criteria);
        assert!(360 % n == 0 && n <= 360, "{n}");
        let (_, s0) = build_profile(&d, &a, 0).unwrap();
        let (_, s9) = build_profile(&d, &a, 9).unwrap();
        assert_eq!((s0.intervals, s9.intervals), (n, n));
    }
}
