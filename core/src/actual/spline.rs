//! Interpolating cubic spline on fixed-capacity buffers (Appendix C, Eqs. C-1..C-6).
//!
//! Between knots `x_i < x_{i+1}` (`h_i = x_{i+1} − x_i`, `t = x − x_i`) the spline is the
//! cubic of Eq. C-3 with the slope of Eq. C-4:
//!
//! ```text
//! S(x)   = f_i + b_i t + M_i t²/2 + d_i t³/6,     d_i = (M_{i+1} − M_i)/h_i
//! S'(x)  = b_i + M_i t + d_i t²/2,                b_i = (f_{i+1} − f_i)/h_i − h_i (2M_i + M_{i+1})/6
//! S''(x) = M_i + d_i t                            (Eq. C-1)
//! ```
//!
//! and the second derivatives `M_i = S''(x_i)` solve Eq. C-6,
//! `h_{i−1} M_{i−1} + 2(h_{i−1} + h_i) M_i + h_i M_{i+1} = 6(Δ_i − Δ_{i−1})`,
//! `Δ_i = (f_{i+1} − f_i)/h_i`, at the interior knots, closed by the end condition:
//!
//! * [`SplineEnds::Natural`]: `M = 0` at both ends (Table C-1 property 4, the thesis's
//!   choice): of all C² interpolants it has the least `∫ S''² dx`.
//! * [`SplineEnds::Curvature`]: given `S''` at both ends (a cubic is reproduced exactly
//!   when they are its own).
//! * [`SplineEnds::Periodic`]: the data cover one period, the last value repeats the
//!   first, and C-6 holds at every knot with indices taken around the period, so value,
//!   slope and curvature all match at the wrap (no step where the last interval meets
//!   the first, unlike the natural spline of VII.1(b)). The cyclic system is solved by
//!   eliminating the last unknown (bordering): three tridiagonal solves.
//!
//! Every system is symmetric, strictly diagonally dominant with positive pivots, so the
//! Thomas algorithm without pivoting is stable. The build needs one scratch array of
//! `N` values on the stack; nothing is allocated.
//!
//! Evaluation finds the interval by binary search (O(log n)); when the knots are
//! uniform (each within a quarter step of `x_0 + i h̄`, detected at build time) the
//! interval is computed from `(x − x_0)/h̄` and corrected by at most one step (O(1)).
//! A periodic spline wraps the abscissa into its period first; a non-periodic spline
//! extends its end cubics beyond the knots.

use crate::{Error, Real};
use core::fmt;

/// How a [`CubicSpline`] is closed at its ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SplineEnds<T> {
    /// `S'' = 0` at both ends (Appendix C, property 4).
    Natural,
    /// Given second derivatives at the first and last knot.
    Curvature {
        /// `S''` at the first knot.
        start: T,
        /// `S''` at the last knot.
        end: T,
    },
    /// One period: the last knot is the first plus the period, the last value equals
    /// the first (within 16 ε of the largest value; it is then set equal), and value,
    /// slope and curvature are continuous around the wrap.
    Periodic,
}

/// Why a [`CubicSpline`] could not be built.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SplineError {
    /// Fewer points than the end condition needs (2, or 4 for periodic: 3 intervals).
    TooFewPoints {
        /// Points given.
        given: usize,
        /// Points needed.
        needed: usize,
    },
    /// Knots and values differ in length.
    LengthMismatch {
        /// Number of knots.
        knots: usize,
        /// Number of values.
        values: usize,
    },
    /// `knots[index]` is not above `knots[index - 1]`.
    NotIncreasing {
        /// Index of the first offending knot.
        index: usize,
    },
    /// A non-finite input or result.
    NonFinite {
        /// `"knots"`, `"values"`, `"end curvature"`, `"step"`, `"knot spacing"` or
        /// `"second derivatives"` (an input too extreme to solve in this precision).
        what: &'static str,
        /// Index of the first offending entry (0 where there is one value).
        index: usize,
    },
    /// More points than the capacity `N`.
    Capacity {
        /// Points given.
        given: usize,
        /// The capacity.
        capacity: usize,
    },
    /// A periodic spline's last value differs from its first.
    PeriodicMismatch {
        /// The first value.
        first: f64,
        /// The last value.
        last: f64,
    },
}

impl fmt::Display for SplineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            SplineError::TooFewPoints { given, needed } => {
                write!(f, "spline: {given} points, at least {needed} needed")
            }
            SplineError::LengthMismatch { knots, values } => {
                write!(f, "spline: {knots} knots but {values} values")
            }
            SplineError::NotIncreasing { index } => {
                write!(
                    f,
                    "spline: knot {index} does not exceed knot {}",
                    index.saturating_sub(1)
                )
            }
            SplineError::NonFinite { what, index } => {
                write!(f, "spline: {what}[{index}] is not finite")
            }
            SplineError::Capacity { given, capacity } => {
                write!(
                    f,
                    "spline: {given} points, more than the capacity of {capacity}"
                )
            }
            SplineError::PeriodicMismatch { first, last } => write!(
                f,
                "periodic spline: last value {last} differs from the first {first}"
            ),
        }
    }
}

impl From<SplineError> for Error {
    fn from(e: SplineError) -> Error {
        let invalid = |field, rule, value| Error::InvalidParameter { field, rule, value };
        match e {
            SplineError::TooFewPoints { given, .. } => invalid(
                "spline points",
                "too few: at least 2, or 4 (3 intervals) for a periodic spline",
                given as f64,
            ),
            SplineError::LengthMismatch { values, .. } => invalid(
                "spline values",
                "must be as many as the knots",
                values as f64,
            ),
            SplineError::NotIncreasing { index } => invalid(
                "spline knots",
                "must increase strictly (value: the first offending index)",
                index as f64,
            ),
            SplineError::NonFinite { what, index } => invalid(
                what,
                "must be finite (value: the first offending index)",
                index as f64,
            ),
            SplineError::Capacity { capacity, .. } => Error::Capacity {
                what: "spline points",
                capacity,
            },
            SplineError::PeriodicMismatch { last, .. } => invalid(
                "spline values",
                "the last value of a periodic spline must equal the first",
                last,
            ),
        }
    }
}

/// A spline's value and derivatives at one abscissa.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SplinePoint<T> {
    /// `S(x)`.
    pub y: T,
    /// `S'(x)`.
    pub dy: T,
    /// `S''(x)`.
    pub d2y: T,
    /// `S'''(x)`, constant on each interval.
    pub d3y: T,
}

/// An interpolating cubic spline through at most `N` points (see the module docs).
///
/// Holds the knots, the values and the second derivatives: `3 N` values of `T` plus
/// three words.
#[derive(Clone, Debug, PartialEq)]
pub struct CubicSpline<T, const N: usize> {
    x: [T; N],
    y: [T; N],
    m: [T; N],
    n: usize,
    periodic: bool,
    /// `1/h̄` when the knots are uniform (O(1) lookup), else 0 (binary search).
    inv_step: T,
}

/// `floor(v)` as an index for `v ≥ 0` (0 for NaN or negative, saturating above), by
/// the float-to-integer cast of `T`'s own type (no widening of `f32` to `f64`).
#[inline(always)]
fn to_index<T: Real>(v: T) -> usize {
    let any: &dyn core::any::Any = &v;
    if let Some(f) = any.downcast_ref::<f32>() {
        *f as usize
    } else if let Some(f) = any.downcast_ref::<f64>() {
        *f as usize
    } else {
        v.to_f64() as usize
    }
}

/// Solves the tridiagonal rows `k < len`:
/// `sub(k) u_{k−1} + diag(k) u_k + sup(k) u_{k+1} = rhs(k)` (`sub(0)`, `sup(len − 1)`
/// unused) into `out[..len]` with `cp[..len]` as scratch (Thomas algorithm). False if a
/// buffer is short or a pivot is not positive and finite.
fn thomas<T: Real>(
    len: usize,
    sub: impl Fn(usize) -> T,
    diag: impl Fn(usize) -> T,
    sup: impl Fn(usize) -> T,
    rhs: impl Fn(usize) -> T,
    cp: &mut [T],
    out: &mut [T],
) -> bool {
    let (Some(cp), Some(out)) = (cp.get_mut(..len), out.get_mut(..len)) else {
        return false;
    };
    let (mut prev_c, mut prev_d) = (T::ZERO, T::ZERO);
    for (k, (c_slot, d_slot)) in cp.iter_mut().zip(out.iter_mut()).enumerate() {
        let a = if k == 0 { T::ZERO } else { sub(k) };
        let pivot = diag(k) - a * prev_c;
        if !(pivot > T::ZERO && pivot.is_finite()) {
            return false;
        }
        prev_c = if k + 1 < len { sup(k) / pivot } else { T::ZERO };
        prev_d = (rhs(k) - a * prev_d) / pivot;
        *c_slot = prev_c;
        *d_slot = prev_d;
    }
    let mut next = T::ZERO;
    for (c, d) in cp.iter().zip(out.iter_mut()).rev() {
        *d -= *c * next;
        next = *d;
    }
    true
}

impl<T: Real, const N: usize> CubicSpline<T, N> {
    /// The spline through `(knots[i], values[i])` closed by `ends`.
    ///
    /// Needs at least 2 points (4 for [`SplineEnds::Periodic`], whose last knot is the
    /// first plus the period), at most `N`, all finite, knots strictly increasing.
    pub fn new(knots: &[T], values: &[T], ends: SplineEnds<T>) -> Result<Self, SplineError> {
        let mut s = Self::EMPTY;
        s.refit(knots, values, ends)?;
        Ok(s)
    }

    /// A spline without points (every value 0), to [`Self::refit`] in place: a spline
    /// in a `static` is then built where it lives, never copied through the stack (the
    /// firmware's measured profile).
    pub const EMPTY: Self = CubicSpline {
        x: [T::ZERO; N],
        y: [T::ZERO; N],
        m: [T::ZERO; N],
        n: 0,
        periodic: false,
        inv_step: T::ZERO,
    };

    /// [`Self::new`] in place: this spline becomes the one through the points (same
    /// checks, same arithmetic). On an error it is left without points
    /// ([`Self::is_empty`]).
    pub fn refit(
        &mut self,
        knots: &[T],
        values: &[T],
        ends: SplineEnds<T>,
    ) -> Result<(), SplineError> {
        let r = self.refit_inner(knots, values, ends);
        if r.is_err() {
            self.n = 0;
        }
        r
    }

    fn refit_inner(
        &mut self,
        knots: &[T],
        values: &[T],
        ends: SplineEnds<T>,
    ) -> Result<(), SplineError> {
        if knots.len() != values.len() {
            return Err(SplineError::LengthMismatch {
                knots: knots.len(),
                values: values.len(),
            });
        }
        Self::check_count(knots.len(), ends)?;
        self.x.fill(T::ZERO);
        self.y.fill(T::ZERO);
        self.m.fill(T::ZERO);
        self.n = knots.len();
        self.periodic = ends == SplineEnds::Periodic;
        self.inv_step = T::ZERO;
        for (i, ((dst, &src), (vdst, &vsrc))) in self
            .x
            .iter_mut()
            .zip(knots)
            .zip(self.y.iter_mut().zip(values))
            .enumerate()
        {
            if !src.is_finite() {
                return Err(SplineError::NonFinite {
                    what: "knots",
                    index: i,
                });
            }
            *dst = src;
            *vdst = vsrc;
        }
        self.build(ends)
    }

    /// The spline through `values[i]` at the uniform knots `start + i·step`; for
    /// [`SplineEnds::Periodic`] the period is `(values.len() − 1)·step`.
    pub fn uniform(
        start: T,
        step: T,
        values: &[T],
        ends: SplineEnds<T>,
    ) -> Result<Self, SplineError> {
        Self::uniform_from_fn(start, step, values.len(), ends, |i| {
            values.get(i).copied().unwrap_or(T::ZERO)
        })
    }

    /// The spline through `value(i)` at the uniform knots `start + i·step`,
    /// `i < points` (called once for each `i`, in order), without a buffer of values;
    /// for [`SplineEnds::Periodic`] `value(points − 1)` must repeat `value(0)`.
    pub fn uniform_from_fn(
        start: T,
        step: T,
        points: usize,
        ends: SplineEnds<T>,
        mut value: impl FnMut(usize) -> T,
    ) -> Result<Self, SplineError> {
        if !start.is_finite() {
            return Err(SplineError::NonFinite {
                what: "knots",
                index: 0,
            });
        }
        if !(step.is_finite() && step > T::ZERO) {
            return Err(if step.is_finite() {
                SplineError::NotIncreasing { index: 1 }
            } else {
                SplineError::NonFinite {
                    what: "step",
                    index: 0,
                }
            });
        }
        let mut s = Self::empty(points, ends)?;
        for (i, (dst, vdst)) in s.x.iter_mut().zip(s.y.iter_mut()).take(points).enumerate() {
            *dst = start + T::from_usize(i) * step;
            *vdst = value(i);
        }
        s.build(ends)?;
        Ok(s)
    }

    /// The periodic spline through `value(k)` at `k·step`, `k < intervals` (called once
    /// for each `k`, in order), closed by repeating `value(0)` at `intervals·step`: one
    /// period of `intervals` uniform intervals starting at 0.
    pub fn periodic_from_fn(
        step: T,
        intervals: usize,
        mut value: impl FnMut(usize) -> T,
    ) -> Result<Self, SplineError> {
        let mut first = T::ZERO;
        Self::uniform_from_fn(
            T::ZERO,
            step,
            intervals.saturating_add(1),
            SplineEnds::Periodic,
            |k| {
                if k == intervals {
                    return first;
                }
                let v = value(k);
                if k == 0 {
                    first = v;
                }
                v
            },
        )
    }

    /// [`Self::periodic_from_fn`] in place (no second spline on the stack). On an error
    /// it is left without points ([`Self::is_empty`]).
    pub fn refit_periodic_from_fn(
        &mut self,
        step: T,
        intervals: usize,
        mut value: impl FnMut(usize) -> T,
    ) -> Result<(), SplineError> {
        let r = self.refit_periodic_inner(step, intervals, &mut value);
        if r.is_err() {
            self.n = 0;
        }
        r
    }

    fn refit_periodic_inner(
        &mut self,
        step: T,
        intervals: usize,
        value: &mut impl FnMut(usize) -> T,
    ) -> Result<(), SplineError> {
        if !(step.is_finite() && step > T::ZERO) {
            return Err(SplineError::NotIncreasing { index: 1 });
        }
        let points = intervals.saturating_add(1);
        Self::check_count(points, SplineEnds::Periodic)?;
        self.x.fill(T::ZERO);
        self.y.fill(T::ZERO);
        self.m.fill(T::ZERO);
        self.n = points;
        self.periodic = true;
        self.inv_step = T::ZERO;
        let mut first = T::ZERO;
        for (i, (dst, vdst)) in self
            .x
            .iter_mut()
            .zip(self.y.iter_mut())
            .take(points)
            .enumerate()
        {
            *dst = T::from_usize(i) * step;
            *vdst = if i == intervals { first } else { value(i) };
            if i == 0 {
                first = *vdst;
            }
        }
        self.build(SplineEnds::Periodic)
    }

    /// The spline through `point(i) = (knot, value)`, `i < points` (called once for
    /// each `i`, in order), without buffers of knots and values: [`Self::new`]'s count,
    /// finiteness and order checks and its arithmetic.
    pub fn from_fn(
        points: usize,
        ends: SplineEnds<T>,
        mut point: impl FnMut(usize) -> (T, T),
    ) -> Result<Self, SplineError> {
        let mut s = Self::empty(points, ends)?;
        for (i, (dst, vdst)) in s.x.iter_mut().zip(s.y.iter_mut()).take(points).enumerate() {
            (*dst, *vdst) = point(i);
        }
        s.build(ends)?;
        Ok(s)
    }

    /// The natural spline (`S'' = 0` at both ends) through the points.
    pub fn natural(knots: &[T], values: &[T]) -> Result<Self, SplineError> {
        Self::new(knots, values, SplineEnds::Natural)
    }

    /// The periodic spline through one period of points (last knot = first + period,
    /// last value = first value).
    pub fn periodic(knots: &[T], values: &[T]) -> Result<Self, SplineError> {
        Self::new(knots, values, SplineEnds::Periodic)
    }

    /// The count checks: at least 2 points (4 periodic), at most `N`.
    fn check_count(n: usize, ends: SplineEnds<T>) -> Result<(), SplineError> {
        let needed = if ends == SplineEnds::Periodic { 4 } else { 2 };
        if n < needed {
            return Err(SplineError::TooFewPoints { given: n, needed });
        }
        if n > N {
            return Err(SplineError::Capacity {
                given: n,
                capacity: N,
            });
        }
        Ok(())
    }

    /// Zeroed buffers for `n` points after the count checks.
    fn empty(n: usize, ends: SplineEnds<T>) -> Result<Self, SplineError> {
        Self::check_count(n, ends)?;
        Ok(CubicSpline {
            x: [T::ZERO; N],
            y: [T::ZERO; N],
            m: [T::ZERO; N],
            n,
            periodic: ends == SplineEnds::Periodic,
            inv_step: T::ZERO,
        })
    }

    /// Validates the filled knots and values and solves for the second derivatives.
    fn build(&mut self, ends: SplineEnds<T>) -> Result<(), SplineError> {
        let ymax = self.check_points()?;
        self.solve_second_derivatives(ends, ymax)?;
        self.detect_uniform();
        Ok(())
    }

    /// The filled knots and values finite, the knots strictly increasing with finite
    /// spacings; returns the largest |value|.
    fn check_points(&self) -> Result<T, SplineError> {
        let n = self.n;
        let mut ymax = T::ZERO;
        for (i, (&xi, &yi)) in self.x.iter().zip(&self.y).take(n).enumerate() {
            if !xi.is_finite() {
                return Err(SplineError::NonFinite {
                    what: "knots",
                    index: i,
                });
            }
            if !yi.is_finite() {
                return Err(SplineError::NonFinite {
                    what: "values",
                    index: i,
                });
            }
            ymax = ymax.max(yi.abs());
        }
        for (i, w) in self.x.windows(2).take(n - 1).enumerate() {
            if let [a, b] = *w {
                if b <= a {
                    return Err(SplineError::NotIncreasing { index: i + 1 });
                }
                if !(b - a).is_finite() {
                    return Err(SplineError::NonFinite {
                        what: "knot spacing",
                        index: i,
                    });
                }
            }
        }
        Ok(ymax)
    }

    /// The second derivatives `m` for the `ends` (a periodic spline's last value set to
    /// its first, which it must equal within `16 ε` times the largest |value| `ymax`),
    /// all finite.
    fn solve_second_derivatives(
        &mut self,
        ends: SplineEnds<T>,
        ymax: T,
    ) -> Result<(), SplineError> {
        let n = self.n;
        let mut scratch = [T::ZERO; N];
        let (x, y) = (&self.x, &mut self.y);
        let h = |j: usize| {
            x.get(j + 1).copied().unwrap_or(T::ZERO) - x.get(j).copied().unwrap_or(T::ZERO)
        };
        let ok = match ends {
            SplineEnds::Natural | SplineEnds::Curvature { .. } => {
                let (ma, mb) = match ends {
                    SplineEnds::Curvature { start, end } => (start, end),
                    _ => (T::ZERO, T::ZERO),
                };
                if !ma.is_finite() || !mb.is_finite() {
                    return Err(SplineError::NonFinite {
                        what: "end curvature",
                        index: usize::from(ma.is_finite()),
                    });
                }
                let y = &*y;
                let delta = |j: usize| {
                    (y.get(j + 1).copied().unwrap_or(T::ZERO)
                        - y.get(j).copied().unwrap_or(T::ZERO))
                        / h(j)
                };
                let six = T::from_i32(6);
                // Unknowns M_1..M_{n−2}: row k is knot k + 1.
                let len = n - 2;
                let rhs = |k: usize| {
                    let mut r = six * (delta(k + 1) - delta(k));
                    if k == 0 {
                        r -= h(0) * ma;
                    }
                    if k + 1 == len {
                        r -= h(n - 2) * mb;
                    }
                    r
                };
                let ok = thomas(
                    len,
                    h,
                    |k| T::TWO * (h(k) + h(k + 1)),
                    |k| h(k + 1),
                    rhs,
                    &mut scratch,
                    self.m.get_mut(1..).unwrap_or(&mut []),
                );
                if let Some(m0) = self.m.first_mut() {
                    *m0 = ma;
                }
                if let Some(mn) = self.m.get_mut(n - 1) {
                    *mn = mb;
                }
                ok
            }
            SplineEnds::Periodic => {
                let (first, last) = (
                    y.first().copied().unwrap_or(T::ZERO),
                    y.get(n - 1).copied().unwrap_or(T::ZERO),
                );
                if (last - first).abs() > T::from_i32(16) * T::EPSILON * ymax {
                    return Err(SplineError::PeriodicMismatch {
                        first: first.to_f64(),
                        last: last.to_f64(),
                    });
                }
                if let Some(l) = y.get_mut(n - 1) {
                    *l = first;
                }
                let y = &*y;
                solve_periodic(
                    n - 1,
                    h,
                    |j| y.get(j).copied().unwrap_or(T::ZERO),
                    &mut scratch,
                    &mut self.m,
                )
            }
        };
        if !ok {
            return Err(SplineError::NonFinite {
                what: "second derivatives",
                index: 0,
            });
        }
        if let Some(i) = self.m.iter().take(n).position(|v| !v.is_finite()) {
            return Err(SplineError::NonFinite {
                what: "second derivatives",
                index: i,
            });
        }
        Ok(())
    }

    /// Records `1/h̄` when the knots are uniform (every knot within a quarter step of
    /// `x_0 + i h̄`), for the direct interval lookup; 0 otherwise.
    fn detect_uniform(&mut self) {
        let n = self.n;
        let x0 = self.x.first().copied().unwrap_or(T::ZERO);
        let step = (self.x.get(n - 1).copied().unwrap_or(T::ZERO) - x0) / T::from_usize(n - 1);
        let quarter = step * T::from_f64(0.25);
        let uniform = self
            .x
            .iter()
            .take(n)
            .enumerate()
            .all(|(i, &xi)| (xi - (x0 + T::from_usize(i) * step)).abs() <= quarter);
        let inv = T::ONE / step;
        self.inv_step = if uniform && inv.is_finite() {
            inv
        } else {
            T::ZERO
        };
    }

    /// Number of points.
    #[inline]
    pub fn len(&self) -> usize {
        self.n
    }

    /// Always false (a spline has at least 2 points).
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// True for a periodic spline.
    #[inline]
    pub fn is_periodic(&self) -> bool {
        self.periodic
    }

    /// True when the knots were found uniform (O(1) interval lookup).
    #[inline]
    pub fn is_uniform(&self) -> bool {
        self.inv_step > T::ZERO
    }

    /// The knots.
    pub fn knots(&self) -> &[T] {
        self.x.get(..self.n).unwrap_or(&[])
    }

    /// The values at the knots.
    pub fn values(&self) -> &[T] {
        self.y.get(..self.n).unwrap_or(&[])
    }

    /// The second derivatives at the knots, `M_i = S''(x_i)`.
    pub fn second_derivatives(&self) -> &[T] {
        self.m.get(..self.n).unwrap_or(&[])
    }

    /// First and last knot.
    pub fn range(&self) -> (T, T) {
        let k = self.knots();
        (
            k.first().copied().unwrap_or(T::ZERO),
            k.last().copied().unwrap_or(T::ZERO),
        )
    }

    /// The period (last knot − first) of a periodic spline, 0 otherwise.
    pub fn period(&self) -> T {
        if self.periodic {
            let (a, b) = self.range();
            b - a
        } else {
            T::ZERO
        }
    }

    /// `x` wrapped into `[x_0, x_0 + period)` for a periodic spline, unchanged
    /// otherwise (NaN stays NaN).
    #[inline]
    pub fn wrap(&self, x: T) -> T {
        if !self.periodic {
            return x;
        }
        let (x0, xn) = self.range();
        let p = xn - x0;
        let mut u = x - x0;
        if !(u >= T::ZERO && u < p) {
            u -= p * (u / p).floor();
            if u >= p {
                u -= p;
            } else if u < T::ZERO {
                u = T::ZERO;
            }
        }
        x0 + u
    }

    /// Index `i` of the interval `[x_i, x_{i+1})` holding `x` (the first or last
    /// interval outside the knots); `x` already wrapped.
    #[inline]
    fn locate(&self, x: T) -> usize {
        let last = self.n.saturating_sub(2);
        if self.inv_step > T::ZERO {
            let x0 = self.x.first().copied().unwrap_or(T::ZERO);
            let mut i = to_index((x - x0) * self.inv_step).min(last);
            // The guess is within one interval (knots within h̄/4 of uniform).
            for _ in 0..2 {
                if i > 0 && x < self.x.get(i).copied().unwrap_or(T::ZERO) {
                    i -= 1;
                } else if i < last && x >= self.x.get(i + 1).copied().unwrap_or(T::ZERO) {
                    i += 1;
                } else {
                    return i;
                }
            }
            self.locate_binary(x)
        } else {
            self.locate_binary(x)
        }
    }

    /// [`Self::locate`] by binary search.
    #[inline]
    fn locate_binary(&self, x: T) -> usize {
        self.x
            .get(1..self.n.saturating_sub(1))
            .unwrap_or(&[])
            .partition_point(|&k| k <= x)
    }

    /// Value and derivatives on interval `i` at `t = x − x_i` (Eqs. C-1..C-4).
    #[inline]
    fn piece(&self, i: usize, t: T) -> SplinePoint<T> {
        let g = |a: &[T; N], j: usize| a.get(j).copied().unwrap_or(T::ZERO);
        let (y0, y1, m0, m1) = (
            g(&self.y, i),
            g(&self.y, i + 1),
            g(&self.m, i),
            g(&self.m, i + 1),
        );
        let h = g(&self.x, i + 1) - g(&self.x, i);
        let d = (m1 - m0) / h;
        let b = (y1 - y0) / h - h * (T::TWO * m0 + m1) / T::from_i32(6);
        let half = T::HALF;
        SplinePoint {
            y: y0 + t * (b + t * (half * m0 + t * d / T::from_i32(6))),
            dy: b + t * (m0 + t * half * d),
            d2y: m0 + t * d,
            d3y: d,
        }
    }

    /// Value, slope, curvature and third derivative at `x` (wrapped into the period
    /// for a periodic spline).
    #[inline]
    pub fn eval(&self, x: T) -> SplinePoint<T> {
        let x = self.wrap(x);
        let i = self.locate(x);
        self.piece(i, x - self.x.get(i).copied().unwrap_or(T::ZERO))
    }

    /// `S(x)`.
    #[inline]
    pub fn value(&self, x: T) -> T {
        self.eval(x).y
    }

    /// `∫ S''(x)² dx` over the knots (exact: `S''` is linear on each interval), the
    /// bending energy that the natural spline minimizes (Table C-1, property 4).
    pub fn bending_energy(&self) -> T {
        let mut e = T::ZERO;
        for (xs, ms) in self
            .knots()
            .windows(2)
            .zip(self.second_derivatives().windows(2))
        {
            if let (&[x0, x1], &[m0, m1]) = (xs, ms) {
                e += (x1 - x0) * (m0 * m0 + m0 * m1 + m1 * m1) / T::from_i32(3);
            }
        }
        e
    }
}

/// The cyclic system of a periodic spline with `k` intervals (`k ≥ 3`) into `m[..=k]`
/// (`m[k] = m[0]`): rows `i < k`, indices mod `k`, `a_i = h_{i−1}`, `b_i = 2(a_i + h_i)`,
/// `c_i = h_i`, `r_i = 6(Δ_i − Δ_{i−1})`. The last unknown `μ = M_{k−1}` is eliminated:
/// the first `k − 1` rows read `T u = r − μ w`, `w = a_0 e_0 + c_{k−2} e_{k−2}`; with
/// `T p = r`, `T q = w` the last row gives
/// `μ = (r_{k−1} − a_{k−1} p_{k−2} − c_{k−1} p_0) / (b_{k−1} − a_{k−1} q_{k−2} − c_{k−1} q_0)`,
/// and `T u = r − μ w` is solved again (so `p` and `q` are never stored whole).
fn solve_periodic<T: Real>(
    k: usize,
    h: impl Fn(usize) -> T,
    y: impl Fn(usize) -> T,
    scratch: &mut [T],
    m: &mut [T],
) -> bool {
    let hm = |i: usize| h((i + k - 1) % k);
    let delta = |i: usize| (y(i + 1) - y(i)) / h(i);
    let r = |i: usize| T::from_i32(6) * (delta(i) - delta((i + k - 1) % k));
    let diag = |i: usize| T::TWO * (hm(i) + h(i));
    let len = k - 1;
    let w = |i: usize| {
        let mut v = T::ZERO;
        if i == 0 {
            v += hm(0);
        }
        if i + 1 == len {
            v += h(len - 1);
        }
        v
    };
    let ends = |m: &[T]| {
        (
            m.first().copied().unwrap_or(T::ZERO),
            m.get(len - 1).copied().unwrap_or(T::ZERO),
        )
    };
    if !thomas(len, hm, diag, &h, r, scratch, m) {
        return false;
    }
    let (p0, pl) = ends(m);
    if !thomas(len, hm, diag, &h, w, scratch, m) {
        return false;
    }
    let (q0, ql) = ends(m);
    let (a, c) = (hm(k - 1), h(k - 1));
    let den = diag(k - 1) - a * ql - c * q0;
    if !(den > T::ZERO && den.is_finite()) {
        return false;
    }
    let mu = (r(k - 1) - a * pl - c * p0) / den;
    if !thomas(len, hm, diag, &h, |i| r(i) - mu * w(i), scratch, m) {
        return false;
    }
    let m0 = m.first().copied().unwrap_or(T::ZERO);
    match m.get_mut(k - 1..=k) {
        Some([last, wrap]) => {
            *last = mu;
            *wrap = m0;
            true
        }
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::PI;

    type S<const N: usize> = CubicSpline<f64, N>;

    /// A cubic and its derivatives.
    fn cubic(x: f64) -> [f64; 4] {
        [
            1.0 + 2.0 * x - 3.0 * x * x + 0.5 * x * x * x,
            2.0 - 6.0 * x + 1.5 * x * x,
            -6.0 + 3.0 * x,
            3.0,
        ]
    }

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * (1.0 + b.abs())
    }

    #[test]
    fn reproduces_a_cubic_with_its_own_end_curvatures() {
        // Non-uniform knots: binary-search lookup.
        let x = [-1.0, -0.7, -0.2, 0.1, 0.15, 0.9, 1.3, 2.0, 2.05, 3.0];
        let y = x.map(|v| cubic(v)[0]);
        let ends = SplineEnds::Curvature {
            start: cubic(-1.0)[2],
            end: cubic(3.0)[2],
        };
        let s = S::<16>::new(&x, &y, ends).unwrap();
        assert!(!s.is_uniform() && !s.is_periodic());
        for k in 0..=400 {
            let v = -1.0 + 4.0 * k as f64 / 400.0;
            let p = s.eval(v);
            let c = cubic(v);
            assert!(close(p.y, c[0], 1e-13), "y at {v}: {} vs {}", p.y, c[0]);
            assert!(close(p.dy, c[1], 1e-12), "dy at {v}");
            assert!(close(p.d2y, c[2], 1e-12), "d2y at {v}");
            assert!(close(p.d3y, c[3], 1e-11), "d3y at {v}");
        }
        // Uniform knots: the O(1) lookup, same exactness; beyond the knots the end
        // cubics extend the same polynomial.
        let y: [f64; 9] = core::array::from_fn(|i| cubic(-1.0 + 0.5 * i as f64)[0]);
        let s = S::<9>::uniform(-1.0, 0.5, &y, ends).unwrap();
        assert!(s.is_uniform());
        for k in 0..=500 {
            let v = -2.0 + 6.0 * k as f64 / 500.0;
            let (p, c) = (s.eval(v), cubic(v));
            assert!(
                close(p.y, c[0], 1e-12) && close(p.d2y, c[2], 1e-12),
                "at {v}"
            );
        }
    }

    #[test]
    fn natural_ends_and_minimum_bending_energy() {
        let x = [0.0, 0.3, 1.0, 1.1, 2.5, 3.0];
        let y = [0.0, 1.0, -0.5, 0.2, 2.0, 1.0];
        let s = S::<8>::natural(&x, &y).unwrap();
        assert_eq!(s.eval(0.0).d2y, 0.0);
        assert!(s.eval(3.0).d2y.abs() < 1e-14);
        assert_eq!(s.second_derivatives()[0], 0.0);
        assert_eq!(s.second_derivatives()[5], 0.0);
        // Interpolates and is C² at the interior knots.
        for i in 0..6 {
            assert!((s.value(x[i]) - y[i]).abs() < 1e-14);
        }
        for &k in &x[1..5] {
            let i = x.iter().position(|&v| v == k).unwrap();
            let (l, r) = (s.piece(i - 1, k - x[i - 1]), s.piece(i, 0.0));
            assert!((l.y - r.y).abs() < 1e-13 && (l.dy - r.dy).abs() < 1e-12);
            assert!((l.d2y - r.d2y).abs() < 1e-12);
        }
        // Property 4: any other C² interpolant of the same points bends more, for
        // example splines with other end curvatures.
        let e = s.bending_energy();
        for (a, b) in [(1.0, 0.0), (0.0, -1.0), (0.1, 0.1), (-3.0, 2.0)] {
            let o = S::<8>::new(&x, &y, SplineEnds::Curvature { start: a, end: b }).unwrap();
            assert!(o.bending_energy() > e, "{a}, {b}");
        }
        // A natural spline reproduces a straight line exactly; two points are enough.
        let s = S::<8>::natural(&[1.0, 4.0], &[2.0, 8.0]).unwrap();
        let p = s.eval(2.5);
        assert_eq!((p.y, p.dy, p.d2y), (5.0, 2.0, 0.0));
        let s = S::<8>::natural(&x, &x.map(|v| 3.0 - 2.0 * v)).unwrap();
        for k in 0..50 {
            let v = k as f64 * 0.07 - 0.2;
            assert!((s.value(v) - (3.0 - 2.0 * v)).abs() < 1e-13);
        }
    }

    fn trig(x: f64) -> [f64; 5] {
        // f = sin x + 0.5 cos 3x and its first four derivatives.
        [
            x.sin() + 0.5 * (3.0 * x).cos(),
            x.cos() - 1.5 * (3.0 * x).sin(),
            -x.sin() - 4.5 * (3.0 * x).cos(),
            -x.cos() + 13.5 * (3.0 * x).sin(),
            x.sin() + 40.5 * (3.0 * x).cos(),
        ]
    }

    /// Largest errors of the uniform periodic spline with `n` intervals against `trig`
    /// on a dense grid: value, slope, curvature, and the largest |f''''|.
    fn periodic_errors<const N: usize>(n: usize) -> (f64, f64, f64, f64) {
        let h = 2.0 * PI / n as f64;
        let y: [f64; N] = core::array::from_fn(|i| trig(i as f64 * h)[0]);
        let s = CubicSpline::<f64, N>::uniform(0.0, h, &y[..=n], SplineEnds::Periodic).unwrap();
        let (mut e0, mut e1, mut e2, mut f4) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for k in 0..n * 32 {
            let x = k as f64 * h / 32.0;
            let (p, f) = (s.eval(x), trig(x));
            e0 = e0.max((p.y - f[0]).abs());
            e1 = e1.max((p.dy - f[1]).abs());
            e2 = e2.max((p.d2y - f[2]).abs());
            f4 = f4.max(f[4].abs());
        }
        (e0, e1, e2, f4)
    }

    #[test]
    fn periodic_converges_at_fourth_order_to_the_derived_constant() {
        // On uniform knots the periodic spline's curvature errors at the knots are
        // M_i − f''_i = −h² f''''/12 + O(h⁴) (Taylor expansion of C-6), and between knots
        // the error is e(t) = h⁴ f''''(x) t²(1 − t)²/24 + O(h⁵), t = (x − x_i)/h: the
        // Lidstone interpolant (values and curvatures at both ends) leaves
        // h⁴f'''' t(1−t)(1+t−t²)/24, the curvature error adds −h⁴f'''' t(1−t)/24. So
        // max|e| → h⁴ max|f''''|/384 (at mid-interval), inside Hall's rigorous bound
        // 5h⁴ max|f''''|/384, and halving h divides it by 16.
        let mut last = None;
        for (n, (e0, e1, e2, f4)) in [
            (16, periodic_errors::<17>(16)),
            (32, periodic_errors::<33>(32)),
            (64, periodic_errors::<65>(64)),
            (128, periodic_errors::<129>(128)),
            (256, periodic_errors::<257>(256)),
        ] {
            let h = 2.0 * PI / n as f64;
            let lead = h.powi(4) * f4 / 384.0;
            assert!(
                e0 <= 5.0 * lead,
                "n = {n}: {e0} above Hall's bound {}",
                5.0 * lead
            );
            if n >= 64 {
                assert!(
                    e0 / lead > 0.95 && e0 / lead < 1.05,
                    "n = {n}: {}",
                    e0 / lead
                );
            }
            if let Some((l0, l1, l2)) = last {
                let (r0, r1, r2): (f64, f64, f64) = (l0 / e0, l1 / e1, l2 / e2);
                if n >= 64 {
                    assert!(
                        r0.log2() > 3.9 && r0.log2() < 4.1,
                        "n = {n}: order {}",
                        r0.log2()
                    );
                    assert!(
                        r1.log2() > 2.8 && r1.log2() < 3.2,
                        "n = {n}: slope order {}",
                        r1.log2()
                    );
                    assert!(
                        r2.log2() > 1.9 && r2.log2() < 2.1,
                        "n = {n}: curvature order {}",
                        r2.log2()
                    );
                }
            }
            last = Some((e0, e1, e2));
        }
    }

    #[test]
    fn periodic_closes_smoothly_and_wraps() {
        // Non-uniform knots over a period 2π; values not from a smooth function.
        let x = [0.0, 0.5, 1.4, 2.0, 3.3, 4.0, 5.5, 2.0 * PI];
        let y = [0.3, -1.0, 0.8, 0.1, 0.0, 1.2, -0.4, 0.3];
        let s = S::<8>::periodic(&x, &y).unwrap();
        assert!(s.is_periodic() && !s.is_uniform());
        assert_eq!(s.period(), 2.0 * PI);
        let end = s.piece(6, x[7] - x[6]);
        let start = s.piece(0, 0.0);
        assert!((end.y - start.y).abs() < 1e-14, "{end:?} {start:?}");
        assert!((end.dy - start.dy).abs() < 1e-13, "{end:?} {start:?}");
        assert!((end.d2y - start.d2y).abs() < 1e-13, "{end:?} {start:?}");
        // C² at the interior knots too.
        for i in 1..7 {
            let (l, r) = (s.piece(i - 1, x[i] - x[i - 1]), s.piece(i, 0.0));
            assert!((l.y - r.y).abs() < 1e-13 && (l.dy - r.dy).abs() < 1e-12);
            assert!((l.d2y - r.d2y).abs() < 1e-12);
        }
        // Wrapping: any number of periods away gives the same point.
        for k in [-3.0, -1.0, 1.0, 5.0] {
            for v in [0.0, 0.2, 3.0, 6.0] {
                let (a, b) = (s.eval(v + k * 2.0 * PI), s.eval(v));
                assert!(
                    (a.y - b.y).abs() < 1e-12 && (a.dy - b.dy).abs() < 1e-11,
                    "{k} {v}"
                );
            }
        }
        assert_eq!(s.eval(2.0 * PI), s.eval(0.0));
        // A constant is reproduced with zero curvature.
        let c = S::<8>::periodic(&x, &[2.5; 8]).unwrap();
        assert!(c.second_derivatives().iter().all(|&m| m == 0.0));
        assert_eq!(c.value(1.0), 2.5);
        // A natural spline on the same data steps in slope at the wrap (VII.1(b)).
        let nat = S::<8>::natural(&x, &y).unwrap();
        let (ns, ne) = (nat.eval(0.0), nat.piece(6, x[7] - x[6]));
        assert!((ns.dy - ne.dy).abs() > 0.1);
    }

    #[test]
    fn uniform_lookup_matches_binary_search() {
        // Knots jittered by up to a fifth of a step still take the O(1) path.
        let mut x = [0.0f64; 101];
        for (i, v) in x.iter_mut().enumerate() {
            *v = i as f64 * 0.1
                + if i % 3 == 1 {
                    0.02
                } else if i % 3 == 2 {
                    -0.015
                } else {
                    0.0
                };
        }
        x[100] = 10.0;
        let y = x.map(|v| v.sin());
        let s = S::<101>::natural(&x, &y).unwrap();
        assert!(s.is_uniform());
        for k in 0..20_000 {
            let v = -1.0 + 12.0 * k as f64 / 20_000.0;
            assert_eq!(s.locate(v), s.locate_binary(v), "at {v}");
        }
        for &k in &x {
            assert_eq!(s.locate(k), s.locate_binary(k), "at knot {k}");
        }
        // Strongly graded knots are not uniform.
        let g: [f64; 10] = core::array::from_fn(|i| (i as f64).powi(2));
        assert!(!S::<10>::natural(&g, &g).unwrap().is_uniform());
    }

    #[test]
    fn shape_errors_are_typed() {
        let ok = [0.0, 1.0, 2.0, 3.0];
        assert_eq!(
            S::<8>::natural(&[0.0], &[1.0]),
            Err(SplineError::TooFewPoints {
                given: 1,
                needed: 2
            })
        );
        assert_eq!(
            S::<8>::natural(&[], &[]),
            Err(SplineError::TooFewPoints {
                given: 0,
                needed: 2
            })
        );
        assert_eq!(
            S::<8>::periodic(&[0.0, 1.0, 2.0], &[0.0, 1.0, 0.0]),
            Err(SplineError::TooFewPoints {
                given: 3,
                needed: 4
            })
        );
        assert_eq!(
            S::<8>::natural(&ok, &ok[..3]),
            Err(SplineError::LengthMismatch {
                knots: 4,
                values: 3
            })
        );
        assert_eq!(
            S::<8>::natural(&[0.0, 1.0, 1.0, 2.0], &ok),
            Err(SplineError::NotIncreasing { index: 2 })
        );
        assert_eq!(
            S::<8>::natural(&[0.0, 1.0, 0.5, 2.0], &ok),
            Err(SplineError::NotIncreasing { index: 2 })
        );
    }

    #[test]
    fn value_and_capacity_errors_are_typed() {
        let ok = [0.0, 1.0, 2.0, 3.0];
        assert_eq!(
            S::<8>::natural(&[0.0, f64::NAN, 2.0, 3.0], &ok),
            Err(SplineError::NonFinite {
                what: "knots",
                index: 1
            })
        );
        assert_eq!(
            S::<8>::natural(&ok, &[0.0, 1.0, f64::INFINITY, 3.0]),
            Err(SplineError::NonFinite {
                what: "values",
                index: 2
            })
        );
        assert_eq!(
            S::<3>::natural(&ok, &ok),
            Err(SplineError::Capacity {
                given: 4,
                capacity: 3
            })
        );
        assert!(matches!(
            S::<8>::periodic(&ok, &[0.0, 1.0, 2.0, 0.1]),
            Err(SplineError::PeriodicMismatch { .. })
        ));
        assert_eq!(
            S::<8>::new(
                &ok,
                &ok,
                SplineEnds::Curvature {
                    start: 0.0,
                    end: f64::NAN
                }
            ),
            Err(SplineError::NonFinite {
                what: "end curvature",
                index: 1
            })
        );
        assert_eq!(
            S::<8>::uniform(0.0, -1.0, &ok, SplineEnds::Natural),
            Err(SplineError::NotIncreasing { index: 1 })
        );
        assert_eq!(
            S::<8>::uniform(0.0, f64::NAN, &ok, SplineEnds::Natural),
            Err(SplineError::NonFinite {
                what: "step",
                index: 0
            })
        );
        assert_eq!(
            S::<8>::natural(&[-f64::MAX, f64::MAX], &[0.0, 1.0]),
            Err(SplineError::NonFinite {
                what: "knot spacing",
                index: 0
            })
        );
        // Finite spacings whose sums overflow in the system.
        assert!(matches!(
            S::<8>::natural(&[-f64::MAX, 0.0, f64::MAX], &[0.0, 1.0, 0.0]),
            Err(SplineError::NonFinite {
                what: "second derivatives",
                ..
            })
        ));
        // Knots so close that the slopes overflow.
        assert!(matches!(
            S::<8>::natural(&[0.0, 1e-320, 1.0], &[0.0, 1e300, 0.0]),
            Err(SplineError::NonFinite { .. })
        ));
    }

    #[test]
    fn spline_errors_convert_and_odd_abscissae_never_panic() {
        let ok = [0.0, 1.0, 2.0, 3.0];
        // Into the crate's error.
        let e: Error = SplineError::Capacity {
            given: 4,
            capacity: 3,
        }
        .into();
        assert_eq!(
            e,
            Error::Capacity {
                what: "spline points",
                capacity: 3
            }
        );
        let e: Error = SplineError::NotIncreasing { index: 2 }.into();
        assert!(matches!(
            e,
            Error::InvalidParameter {
                field: "spline knots",
                ..
            }
        ));
        // Evaluation of odd abscissae returns values, not panics.
        let s = S::<8>::natural(&ok, &[0.0, 1.0, 0.0, 1.0]).unwrap();
        let p = S::<8>::periodic(&ok, &[0.0, 1.0, 2.0, 0.0]).unwrap();
        for v in [f64::NAN, f64::INFINITY, -f64::INFINITY, 1e300, -1e300, 0.0] {
            let _ = (s.eval(v), p.eval(v));
        }
        assert!(s.value(f64::NAN).is_nan());
        assert!(p.value(1e300).is_finite());
    }

    #[test]
    fn single_precision_matches_double() {
        let n = 64;
        let h = 2.0 * PI / n as f64;
        let y64: [f64; 65] = core::array::from_fn(|i| trig(i as f64 * h)[0]);
        let y32 = y64.map(|v| v as f32);
        let s64 = S::<65>::uniform(0.0, h, &y64, SplineEnds::Periodic).unwrap();
        let s32 =
            CubicSpline::<f32, 65>::uniform(0.0, h as f32, &y32, SplineEnds::Periodic).unwrap();
        assert!(s32.is_uniform());
        for k in 0..1000 {
            let x = k as f64 * 0.00731 * 2.0 * PI / 7.31;
            let (a, b) = (s64.eval(x), s32.eval(x as f32));
            assert!((a.y - b.y as f64).abs() < 2e-6, "{x}");
            assert!((a.dy - b.dy as f64).abs() < 2e-5, "{x}");
            assert!((a.d2y - b.d2y as f64).abs() < 1e-3, "{x}");
        }
    }
}
