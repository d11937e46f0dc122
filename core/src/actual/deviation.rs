//! The program plus a profile deviation (docs/MODEL.md §8): [`DeviatedLift`], the lift of
//! an actual, machined or measured cam, and every way to build one (a spline, uniform
//! samples, the thesis's random lift of IV.2.3, the roller's exact envelope on an actual
//! contour; a measured revolution in [`crate::sampled_deviation`]).

use crate::{
    actual::follower_axis::AxisErrors, ActualCam, CamGeometry, CamProgram, CubicSpline, Error,
    FollowerLift, LiftProfile, ProfileSpec, RandomStream, Real, Result, SplinePoint,
};

/// Points a revolution at least at which the per-cam method applies the roller's and
/// the axis's exact geometry ([`DeviatedLift::draw_per_cam`]): 1440, every 0.25° (the spline
/// between them then follows the smooth per-cam lift far below 1e-9 in).
pub const AXIS_KNOTS: usize = 1440;

/// The program plus a periodic deviation spline over one revolution with at most `K`
/// knots (the last knot repeats the first at 2π).
#[derive(Clone, Debug, PartialEq)]
pub struct DeviatedLift<T, const K: usize> {
    spline: CubicSpline<T, K>,
}

impl<T: Real, const K: usize> DeviatedLift<T, K> {
    /// A deviation without knots, to [`Self::refit_periodic`] in place (a deviation in a
    /// `static`, never copied through the stack). Riding on it before a successful refit
    /// gives a zero deviation.
    pub const EMPTY: Self = Self {
        spline: CubicSpline::EMPTY,
    };

    /// [`Self::from_spline`] of [`CubicSpline::periodic`]`(knots, values)`, in place. On an
    /// error it is left without knots (as [`Self::EMPTY`]).
    pub fn refit_periodic(&mut self, knots: &[T], values: &[T]) -> Result<()> {
        self.spline
            .refit(knots, values, crate::SplineEnds::Periodic)?;
        if let Err(e) = Self::check_span(&self.spline) {
            self.spline
                .refit(&[], &[], crate::SplineEnds::Periodic)
                .ok();
            return Err(e);
        }
        Ok(())
    }

    /// Whether `spline` is periodic over one revolution (see [`Self::from_spline`]).
    fn check_span(spline: &CubicSpline<T, K>) -> Result<()> {
        let (a, b) = spline.range();
        let tol = T::from_f64(1e-9).max(T::from_i32(8) * T::EPSILON);
        let span_ok = (b - a - T::TWO * T::PI).abs() <= tol * (T::ONE + b.abs());
        if !spline.is_periodic() || !span_ok {
            return Err(Error::InvalidParameter {
                field: "profile",
                rule: "a deviation must be a periodic spline over one revolution (0..360 deg)",
                value: (b - a).to_f64().to_degrees(),
            });
        }
        Ok(())
    }

    /// A deviation from a periodic spline whose knots span exactly one revolution
    /// (`[0, 2π]`, within 1e-9 rad, or 8 ulps of `T` where that is coarser: a revolution
    /// of `f64` knots narrowed to `f32` spans 2π to an ulp, not to 1e-9).
    pub fn from_spline(spline: CubicSpline<T, K>) -> Result<Self> {
        Self::check_span(&spline)?;
        Ok(Self { spline })
    }

    /// The deviation through `value(k)` (in) at `θ_k = k·step`, `k < intervals`, closed
    /// periodically (`intervals·step` must be one revolution; `value` is called once for
    /// each `k`, in order). Needs `3 ≤ intervals < K`.
    pub fn uniform(step: T, intervals: usize, value: impl FnMut(usize) -> T) -> Result<Self> {
        if intervals < 3 || intervals >= K {
            return Err(Error::Capacity {
                what: "profile points (intervals per revolution + 1, at least 4)",
                capacity: K,
            });
        }
        let spline = CubicSpline::periodic_from_fn(step, intervals, value)?;
        Self::from_spline(spline)
    }

    /// The thesis's actual lift (IV.2.3) as a deviation from the program: at every
    /// `θ_k = 2πk/intervals` the deviate `σ_s(θ_k) z_k` (Eq. B-3 with the σ of E.5),
    /// joined by a periodic spline. It draws exactly the deviates
    /// [`ActualLift::generate`](crate::ActualLift::generate) draws from the same stream (that spline carries
    /// `y(θ_k) + σ_s z_k`; this one adds `σ_s z_k` to the program's closed form, so zero
    /// tolerances give back the theoretical cam everywhere, not only at the knots).
    /// Needs `3 ≤ intervals < K`.
    pub fn thesis<const S: usize>(
        spec: &ProfileSpec<'_, T, S>,
        rng: &mut RandomStream<T>,
    ) -> Result<Self> {
        let step = spec.step::<K>()?;
        Self::uniform(step, spec.intervals, |k| {
            let (_, sigma) = spec.lift_and_sigma(k, step);
            rng.gaussian(T::ZERO, sigma)
        })
    }

    /// The per-cam method's draws (docs/MODEL.md §8.9), in place: this deviation becomes
    /// the cam contour's error per point as the thesis has it (`σ_c z_k / cos φ` at
    /// `θ_k = 2πk/intervals`, the contour term of Eq. E.5, drawn first, so that with no
    /// roller or axis error this is [`Self::thesis`] bit for bit); then once per cam
    /// the roller radius's error `Δr = σ_r z` and the follower axis's offset
    /// `e = σ_e z` are drawn and returned. [`Self::refit_per_cam`] adds them through the
    /// exact geometry. Needs `3 ≤ intervals < K`.
    pub fn draw_per_cam<const S: usize>(
        &mut self,
        spec: &ProfileSpec<'_, T, S>,
        rng: &mut RandomStream<T>,
    ) -> Result<AxisErrors<T>> {
        let step = spec.step::<K>()?;
        let (_, sr, se) = spec.tolerances.sigmas();
        let cam_only = crate::Tolerances {
            roller: T::ZERO,
            eccentricity: T::ZERO,
            ..*spec.tolerances
        };
        self.spline
            .refit_periodic_from_fn(step, spec.intervals, |k| {
                let f = spec.program.follower(T::from_usize(k) * step);
                rng.gaussian(T::ZERO, cam_only.lift_sigma(spec.geometry, f.y, f.dy))
            })?;
        Ok(AxisErrors {
            roller: rng.gaussian(T::ZERO, sr),
            offset: rng.gaussian(T::ZERO, se),
        })
    }

    /// Points a revolution of the per-cam lift for `intervals` contour points: the
    /// smallest multiple of `intervals` of at least [`AXIS_KNOTS`], at most `K − 1`.
    pub fn per_cam_points(intervals: usize) -> usize {
        let n = intervals.max(1);
        let per = AXIS_KNOTS.div_ceil(n).min(K.saturating_sub(1) / n).max(1);
        per * n
    }

    /// This deviation becomes the per-cam lift: `contour` (from [`Self::draw_per_cam`])
    /// plus `axis` applied through the exact geometry ([`AxisErrors::lift_deviation`])
    /// at [`Self::per_cam_points`] points, splined (the contour's knots are among them).
    /// With both errors zero it becomes `contour` itself. In place: a `K`-knot spline is
    /// large, and the contour is read while this one is built.
    pub fn refit_per_cam<const S: usize>(
        &mut self,
        contour: &Self,
        axis: &AxisErrors<T>,
        spec: &ProfileSpec<'_, T, S>,
    ) -> Result<()> {
        if axis.is_zero() {
            self.clone_from(contour);
            return Ok(());
        }
        let n = Self::per_cam_points(spec.intervals);
        let fine = T::TWO * T::PI / T::from_usize(n);
        let mut failed = None;
        self.spline.refit_periodic_from_fn(fine, n, |j| {
            let th = T::from_usize(j) * fine;
            let a = axis
                .lift_deviation(spec.program, spec.geometry, th)
                .unwrap_or_else(|e| {
                    failed.get_or_insert(e);
                    T::ZERO
                });
            contour.spline.value(th) + a
        })?;
        if let Err(e) = Self::check_span(&self.spline) {
            self.spline
                .refit(&[], &[], crate::SplineEnds::Periodic)
                .ok();
            return Err(e);
        }
        match failed {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    /// The lift deviation of the exact envelope on `cam`: at `θ_k = 2πk/intervals`,
    /// `e_k = d(θ_k) − (R_a + y(θ_k))` ([`ActualCam::roller_centre`], `R_a` the nominal
    /// prime radius of `geometry`), joined by a periodic spline. Needs
    /// `3 ≤ intervals < K`.
    pub fn envelope<const S: usize, const N: usize>(
        program: &CamProgram<T, S>,
        geometry: &CamGeometry<T>,
        cam: &ActualCam<T, N>,
        intervals: usize,
    ) -> Result<Self> {
        if intervals < 3 {
            return Err(Error::InvalidParameter {
                field: "intervals",
                rule: "must be at least 3 per revolution",
                value: intervals as f64,
            });
        }
        let step = T::TWO * T::PI / T::from_usize(intervals);
        let ra = geometry.prime_radius();
        let mut failed = None;
        let dev = Self::uniform(step, intervals, |k| {
            let th = T::from_usize(k) * step;
            match cam.roller_centre(th) {
                Ok(d) => d - ra - program.follower(th).y,
                Err(e) => {
                    failed.get_or_insert(e);
                    T::ZERO
                }
            }
        })?;
        match failed {
            Some(e) => Err(e),
            None => Ok(dev),
        }
    }

    /// The deviation spline (knots in rad over `[0, 2π]`, values in in).
    pub fn spline(&self) -> &CubicSpline<T, K> {
        &self.spline
    }

    /// The deviation and its derivatives at `theta` (rad, any real).
    #[inline]
    pub fn deviation(&self, theta: T) -> SplinePoint<T> {
        self.spline.eval(theta)
    }

    /// The RMS deviation over one revolution, sampled at `samples` equal steps (in).
    pub fn rms(&self, samples: usize) -> T {
        let n = samples.max(1);
        let step = T::TWO * T::PI / T::from_usize(n);
        let mut sum = T::ZERO;
        for k in 0..n {
            let e = self.spline.value(T::from_usize(k) * step);
            sum += e * e;
        }
        (sum / T::from_usize(n)).sqrt()
    }

    /// The largest |deviation| at the spline's knots (in) and its knot (rad): the first
    /// knot of the largest, or of a NaN (then NaN); `(0, 0)` for an all-zero deviation.
    pub fn largest_at_knots(&self) -> (T, T) {
        let s = &self.spline;
        s.knots()
            .iter()
            .zip(s.values())
            .fold((T::ZERO, T::ZERO), |(w, at), (&k, &v)| {
                if v.abs() > w || v.is_nan() {
                    (v.abs(), k)
                } else {
                    (w, at)
                }
            })
    }
}

impl<T: Real, const K: usize> LiftProfile<T> for DeviatedLift<T, K> {
    #[inline]
    fn follower<const P: usize>(&self, program: &CamProgram<T, P>, theta: T) -> FollowerLift<T> {
        let f = program.follower(theta);
        let e = self.spline.eval(theta);
        FollowerLift {
            y: f.y + e.y,
            dy: f.dy + e.dy,
            d2y: f.d2y + e.d2y,
            d3y: f.d3y + e.d3y,
        }
    }
}
