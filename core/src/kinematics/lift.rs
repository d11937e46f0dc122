//! The lift the roller rides on: the theoretical program, or the program plus a profile
//! deviation (an actual, machined or measured cam; docs/MODEL.md §8).
//!
//! The dynamic model ([`crate::CamModel`]) asks its [`LiftProfile`] for the follower lift
//! `y(θ)`, `dy/dθ`, `d²y/dθ²` wherever the equations use the program (the contact
//! approach, the pressure angle, the surface curvature in the Hertz stiffness, the output
//! torque and the relative coordinates). [`TheoreticalLift`] is the program itself, at no
//! cost; [`DeviatedLift`] adds a periodic spline of the deviation `e(θ)`:
//!
//! ```text
//! y_actual(θ) = y(θ) + e(θ),  dy_actual/dθ = y'(θ) + e'(θ),  …
//! ```
//!
//! Keeping the program's closed form and splining only the deviation means a zero
//! deviation gives back the theoretical cam exactly (not a spline through its points),
//! and the motion law's own discontinuities in acceleration stay where they are.
//!
//! ```
//! use camsim_core::{CamProgram, DeviatedLift, LiftProfile};
//! let program = CamProgram::<f64>::reference();
//! // 0.001 in of once-per-revolution runout, sampled every 10 degrees.
//! let n = 36;
//! let step = 2.0 * core::f64::consts::PI / n as f64;
//! let dev = DeviatedLift::<f64, 64>::uniform(step, n, |k| 1e-3 * (k as f64 * step).cos()).unwrap();
//! let l = dev.follower(&program, 0.0);
//! assert!((l.y - (program.follower(0.0).y + 1e-3)).abs() < 1e-12);
//! ```

use crate::{
    CamProgram, ContactTerms, CubicSpline, Error, FollowerLift, Real, Result, SplinePoint,
};

/// Where the dynamic model takes the follower lift from.
pub trait LiftProfile<T: Real> {
    /// The lift and its cam-angle derivatives at `theta` (rad, any real) for `program`.
    fn follower<const K: usize>(&self, program: &CamProgram<T, K>, theta: T) -> FollowerLift<T>;

    /// [`Self::follower`] and, where the profile tabulates them ([`crate::LiftTable`]),
    /// the Hertz contact stiffness and the pressure angle's inverse hypotenuse
    /// ([`ContactTerms`]); `None` leaves them to the closed forms (the model's Eqs.
    /// V.9-V.12 at the lift's curvature, and a square root).
    #[inline(always)]
    fn follower_and_contact<const K: usize>(
        &self,
        program: &CamProgram<T, K>,
        theta: T,
    ) -> (FollowerLift<T>, Option<ContactTerms<T>>) {
        (self.follower(program, theta), None)
    }
}

/// The theoretical cam: the program's closed-form lift (the default of every model).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TheoreticalLift;

impl<T: Real> LiftProfile<T> for TheoreticalLift {
    #[inline(always)]
    fn follower<const K: usize>(&self, program: &CamProgram<T, K>, theta: T) -> FollowerLift<T> {
        program.follower(theta)
    }
}

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

impl<T: Real, L: LiftProfile<T>> LiftProfile<T> for &L {
    #[inline(always)]
    fn follower<const K: usize>(&self, program: &CamProgram<T, K>, theta: T) -> FollowerLift<T> {
        (**self).follower(program, theta)
    }
    #[inline(always)]
    fn follower_and_contact<const K: usize>(
        &self,
        program: &CamProgram<T, K>,
        theta: T,
    ) -> (FollowerLift<T>, Option<ContactTerms<T>>) {
        (**self).follower_and_contact(program, theta)
    }
}
