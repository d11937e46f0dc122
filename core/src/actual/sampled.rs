//! A revolution sampled at uneven angles (a measured cam, docs/MODEL.md §8.4) as the
//! follower's lift deviation: the periodic spline through the samples, and for contour
//! points the exact envelope of the roller circle on the contour they give. Works on
//! slices, without buffers: the splines are filled from the samples in place.

use core::fmt;

use crate::{
    ActualCam, ActualContour, CamGeometry, CamProgram, CubicSpline, DeviatedLift, Error,
    LiftProfile, Real, SplineEnds, SplineError,
};

/// Envelope knots a sampled contour row ([`envelope_intervals`]): the roller's lift is
/// sampled 8 times an interval between rows, so the envelope resolves what the contour
/// spline does between them (the host's `--actual` envelope uses the same rule).
pub const ENVELOPE_KNOTS_PER_ROW: usize = 8;

/// What a revolution's samples are, one a sample angle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Samples<'a, T> {
    /// The follower's lift deviation from the program (in) at the cam angle.
    Deviation(&'a [T]),
    /// The follower's lift (in) at the cam angle; the deviation is it minus the
    /// program's lift.
    Lift(&'a [T]),
    /// Points of the cam surface (in) in the cam's own frame, `y` along the follower
    /// axis at cam angle 0, at a parameter angle that grows once around the cam (a polar
    /// profile's polar angle: `x = r sin φ`, `y = r cos φ`, the caller's conversion);
    /// the lift follows by the exact envelope of the design's roller circle on the
    /// contour through them.
    Contour {
        /// x (in).
        x: &'a [T],
        /// y (in).
        y: &'a [T],
    },
}

/// Why a sampled revolution gives no deviation, or an implausible one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SampledError {
    /// A periodic spline through the samples was refused.
    Spline(SplineError),
    /// The deviation, the contour or the actual cam built from the splines was refused.
    Profile(Error),
    /// The roller's envelope on the contour failed.
    Envelope(Error),
    /// The envelope implies a lift outside the allowed range ([`EnvelopeLimits::lift`]).
    ImpliedLift {
        /// The lift, in.
        lift: f64,
        /// The cam angle, rad (not reduced to one revolution).
        at_rad: f64,
    },
    /// The roller's path has a convex cam surface radius below
    /// [`EnvelopeLimits::min_surface_radius`] (or NaN): an edge, not a cam surface.
    SurfaceRadius {
        /// The smallest convex surface radius, in.
        radius: f64,
        /// The cam angle where it is, rad (not reduced to one revolution).
        at_rad: f64,
    },
}

impl fmt::Display for SampledError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SampledError::Spline(e) => write!(f, "{e}"),
            SampledError::Profile(e) => write!(f, "{e}"),
            SampledError::Envelope(e) => write!(f, "the roller's envelope: {e}"),
            SampledError::ImpliedLift { lift, at_rad } => write!(
                f,
                "the envelope implies a lift of {lift} in at {at_rad} rad, outside the allowed range"
            ),
            SampledError::SurfaceRadius { radius, at_rad } => write!(
                f,
                "the roller's path has a convex cam surface radius of {radius} in at {at_rad} rad, below the smallest allowed"
            ),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for SampledError {}

/// What a contour's envelope must imply ([`check_envelope`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvelopeLimits<T> {
    /// The allowed lift range `(lowest, highest)`, in.
    pub lift: (T, T),
    /// The smallest convex cam surface radius along the roller's path, in.
    pub min_surface_radius: T,
}

/// The envelope's output intervals for a contour of `rows` samples:
/// [`ENVELOPE_KNOTS_PER_ROW`] a row, within a deviation spline of `K` knots (3 to `K − 1`).
pub fn envelope_intervals<const K: usize>(rows: usize) -> usize {
    rows.saturating_mul(ENVELOPE_KNOTS_PER_ROW)
        .clamp(3, K.saturating_sub(1).max(3))
}

/// One revolution's periodic spline through `(angles_deg[i], value(i))`, closed at the
/// first angle + 360° by `value(0)`; knots in rad.
fn periodic<T: Real, const N: usize>(
    angles_deg: &[T],
    value: impl Fn(usize, T) -> T,
) -> Result<CubicSpline<T, N>, SampledError> {
    let n = angles_deg.len();
    let first = angles_deg.first().copied().unwrap_or(T::ZERO);
    let close = first.to_radians() + T::TWO * T::PI;
    let v0 = value(0, first);
    CubicSpline::from_fn(
        n.saturating_add(1),
        SplineEnds::Periodic,
        |i| match angles_deg.get(i) {
            Some(&a) => (a.to_radians(), value(i, a)),
            None => (close, v0),
        },
    )
    .map_err(SampledError::Spline)
}

/// The lift deviation a revolution's samples give on the program and geometry:
/// `angles_deg` strictly increasing over less than one revolution, as many samples. A
/// [`Samples::Contour`] is the roller circle's exact envelope
/// ([`DeviatedLift::envelope`]) on the contour through the points, with
/// [`envelope_intervals`] intervals; check it with [`check_envelope`].
pub fn sampled_deviation<T: Real, const S: usize, const K: usize>(
    angles_deg: &[T],
    samples: Samples<'_, T>,
    program: &CamProgram<T, S>,
    geometry: &CamGeometry<T>,
) -> Result<DeviatedLift<T, K>, SampledError> {
    let n = angles_deg.len();
    let short = match samples {
        Samples::Deviation(v) | Samples::Lift(v) => (v.len() != n).then_some(v.len()),
        Samples::Contour { x, y } => (x.len() != n || y.len() != n).then_some(x.len().min(y.len())),
    };
    if let Some(values) = short {
        return Err(SampledError::Spline(SplineError::LengthMismatch {
            knots: n,
            values,
        }));
    }
    let at = |v: &[T], i: usize| v.get(i).copied().unwrap_or(T::ZERO);
    let from = |s| DeviatedLift::from_spline(s).map_err(SampledError::Profile);
    match samples {
        Samples::Deviation(v) => from(periodic(angles_deg, |i, _| at(v, i))?),
        Samples::Lift(v) => from(periodic(angles_deg, |i, a| {
            at(v, i) - program.follower(a.to_radians()).y
        })?),
        Samples::Contour { x, y } => {
            let contour = ActualContour::<T, K>::from_splines(
                periodic(angles_deg, |i, _| at(x, i))?,
                periodic(angles_deg, |i, _| at(y, i))?,
            )
            .map_err(SampledError::Profile)?;
            let cam = ActualCam::new(contour, geometry.roller_radius, (T::ZERO, T::ZERO))
                .map_err(SampledError::Profile)?;
            let out = envelope_intervals::<K>(n);
            DeviatedLift::envelope(program, geometry, &cam, out).map_err(SampledError::Envelope)
        }
    }
}

/// What a contour's envelope implies, scanned at 4 points an interval of
/// its deviation spline: the lift within `limits.lift` everywhere (the first point
/// outside is the error), and a convex cam surface radius of at least
/// `limits.min_surface_radius` along the roller's path (the smallest is the error):
/// where the roller bridges a notch or rides over a ridge narrower than itself the path
/// has a corner, an edge with an unbounded Hertz stress.
pub fn check_envelope<T: Real, const S: usize, const K: usize>(
    dev: &DeviatedLift<T, K>,
    program: &CamProgram<T, S>,
    geometry: &CamGeometry<T>,
    limits: EnvelopeLimits<T>,
) -> Result<(), SampledError> {
    let (lo, hi) = limits.lift;
    let mut worst: Option<(T, T)> = None;
    for w in dev.spline().knots().windows(2) {
        let [a, b] = *w else { continue };
        for k in 0..4 {
            let th = a + (b - a) * T::from_usize(k) / T::from_f64(4.0);
            let l = dev.follower(program, th);
            if !(l.y >= lo && l.y <= hi) {
                return Err(SampledError::ImpliedLift {
                    lift: l.y.to_f64(),
                    at_rad: th.to_f64(),
                });
            }
            let rho = geometry.pitch_curvature_radius(l.y, l.dy, l.d2y);
            if rho > T::ZERO {
                let surface = rho - geometry.roller_radius;
                if worst.is_none_or(|(r, _)| surface < r) {
                    worst = Some((surface, th));
                }
            }
        }
    }
    match worst {
        Some((r, th)) if r < limits.min_surface_radius || r.is_nan() => {
            Err(SampledError::SurfaceRadius {
                radius: r.to_f64(),
                at_rad: th.to_f64(),
            })
        }
        _ => Ok(()),
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used, clippy::indexing_slicing)]
mod tests {
    use super::*;
    use crate::Design;

    /// The in-place fill builds the spline `new` builds from buffers, bit for bit.
    #[test]
    fn from_fn_is_new() {
        let x = [0.1, 0.7, 1.9, 3.0, 4.4, 0.1 + 2.0 * core::f64::consts::PI];
        let y = [0.3, -0.2, 0.5, 0.0, 0.1, 0.3];
        let a = CubicSpline::<f64, 8>::periodic(&x, &y).unwrap();
        let b = CubicSpline::<f64, 8>::from_fn(6, SplineEnds::Periodic, |i| (x[i], y[i])).unwrap();
        assert_eq!(a, b);
    }

    /// A lift sampled at uneven angles gives the deviation it was offset by, exactly at
    /// the samples: the program's lift at each angle plus `0.001 sin 3θ`.
    #[test]
    fn lift_samples_give_their_offset() {
        let d = Design::<f64>::reference();
        let angles: [f64; 7] = [5.0, 50.0, 95.0, 170.0, 200.0, 290.0, 330.0];
        let off = |a: f64| 0.001 * (3.0 * a.to_radians()).sin();
        let lift = angles.map(|a| d.program.follower(a.to_radians()).y + off(a));
        let dev: DeviatedLift<f64, 16> =
            sampled_deviation(&angles, Samples::Lift(&lift), &d.program, &d.geometry).unwrap();
        for (k, a) in dev.spline().values().iter().zip(angles) {
            assert!((k - off(a)).abs() < 1e-15, "{k} {}", off(a));
        }
        assert_eq!(dev.spline().len(), 8);
        let e: Result<DeviatedLift<f64, 16>, _> = sampled_deviation(
            &angles,
            Samples::Deviation(&lift[..3]),
            &d.program,
            &d.geometry,
        );
        assert!(matches!(
            e,
            Err(SampledError::Spline(SplineError::LengthMismatch { .. }))
        ));
    }

    /// The envelope's intervals: 8 a row, at least 3, below the capacity.
    #[test]
    fn envelope_intervals_clamp() {
        assert_eq!(envelope_intervals::<3601>(720), 3600);
        assert_eq!(envelope_intervals::<3601>(100), 800);
        assert_eq!(envelope_intervals::<3601>(0), 3);
        assert_eq!(envelope_intervals::<3601>(usize::MAX), 3600);
    }
}
