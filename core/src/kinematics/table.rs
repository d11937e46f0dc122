//! The lift table (issue 21): the lift the roller rides on, its cam-angle derivatives and
//! the Hertz contact stiffness, tabulated once on a fine grid of cam angle and
//! interpolated in every right-hand-side evaluation instead of the motion laws' closed
//! forms (sines, cosines, polynomials) and the Hertz stiffness (three square roots and the
//! surface curvature). docs/MODEL.md §3.21 gives the construction and its error bound.
//!
//! Each segment of the program gets its own uniform grid whose interval count is a
//! multiple of [`TABLE_SEGMENT_MULTIPLE`] (8), so that every junction of Appendix A's
//! piecewise laws (all at multiples of 1/8 of the segment) and every segment bound is a
//! knot: inside an interval the tabulated functions are smooth. At every knot the table
//! keeps `y, y', y'', y'''` (from the profile, closed form or measured) and `K_h` (from
//! the same [`crate::HertzContact::stiffness_fast`] the model calls). Between knots:
//!
//! - `y` is the cubic Hermite interpolant of `(y, y')`, `y'` that of `(y', y'')`, `y''`
//!   that of `(y'', y''')`; on an interval of length `h` each errs by at most
//!   `h⁴/384 · max|f⁽⁴⁾|` of the function it interpolates (`y⁽⁴⁾`, `y⁽⁵⁾`, `y⁽⁶⁾`);
//! - `y'''` is the derivative of the `y''` interpolant (error `O(h³)`, outputs only);
//! - `K_h` is linear between knots, error at most `h²/8 · max|K_h''|`.
//!
//! A law whose `y'''` jumps at an internal junction (parabolic, cubic No. 1, trapezoidal)
//! has one side's `y'''` at that knot: `y''` then errs by `O(h · jump)` in the intervals
//! next to it. A measured profile's deviation spline is only `C²` at its own knots; its
//! table error is measured, not bounded (docs/FIRMWARE.md).
//!
//! The table serves the design it was built for ([`LiftTable::fill`]): its `follower`
//! ignores the program it is given. Nothing panics: an empty (unfilled) table gives a
//! flat lift and leaves the stiffness to the closed form.

use crate::{Design, Error, FollowerLift, LiftProfile, Real, Result};

/// Every segment's interval count is a multiple of this: Appendix A's laws switch
/// pieces only at multiples of 1/8 of a segment.
pub const TABLE_SEGMENT_MULTIPLE: usize = 8;

/// Quantities kept at each knot: `y, y', y'', y'''`, `K_h` and `w = 1/√((R_a + y)² + y'²)`
/// (its slope `w' = -y' (R_a + y + y'') w³` is computed from them where it is needed:
/// the same expression, so the same bits, as when it was kept, for 4 B a knot less).
pub const TABLE_PER_KNOT: usize = 6;
const PER_KNOT: usize = TABLE_PER_KNOT;

/// What the table gives beside the lift for the model's contact (docs/MODEL.md §3.21).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactTerms<T> {
    /// Hertz contact stiffness K_h, lb/in.
    pub k_h: T,
    /// `1/√((R_a + y)² + y'²)`, 1/in: the pressure angle's cosine and sine are
    /// `(R_a + y) w` and `y' w`.
    pub inv_hyp: T,
}

/// One knot's quantities, in the order of [`TABLE_PER_KNOT`]'s list.
pub type TableKnot<T> = [T; PER_KNOT];
type Knot<T> = TableKnot<T>;

/// The interval holding a cam angle: its two knots, the position `t ∈ [0, 1]` in it, its
/// length and the inverse.
struct Interval<'a, T> {
    a: &'a Knot<T>,
    b: &'a Knot<T>,
    t: T,
    h: T,
    inv_h: T,
}

/// One program segment's run of knots (public so that a build script can write a filled
/// table out as source: [`LiftTable::from_parts`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TablePiece<T> {
    /// Segment start, rad.
    pub start: T,
    /// Segment end, rad.
    pub end: T,
    /// Interval length, rad.
    pub h: T,
    /// Its inverse, 1/rad.
    pub inv_h: T,
    /// Index of the segment's first knot.
    pub first: usize,
    /// Number of intervals in the segment.
    pub n: usize,
}
type Piece<T> = TablePiece<T>;

impl<T: Real> TablePiece<T> {
    const EMPTY: Self = Self {
        start: T::ZERO,
        end: T::ZERO,
        h: T::ZERO,
        inv_h: T::ZERO,
        first: 0,
        n: 0,
    };
}

/// The lift, its derivatives and the Hertz stiffness on a per-segment uniform grid of at
/// most `K` knots (`S` program segments at most). Memory: `24 K + 24 S + 12` bytes in `f32`
/// (plus alignment). Built in place ([`Self::fill`]) so that a `static` table is never
/// copied through the stack.
#[derive(Clone, Debug, PartialEq)]
pub struct LiftTable<T, const K: usize, const S: usize = 8> {
    knots: [Knot<T>; K],
    pieces: [Piece<T>; S],
    pieces_len: usize,
    knots_len: usize,
    /// The design's prime radius R_a, in (for `w'`).
    prime_radius: T,
}

/// The slope `w' = -y' (R_a + y + y'') w³` of the knot's `w`, rad⁻¹ in⁻¹, from its own
/// `y, y', y''` and `w`.
#[inline(always)]
fn hyp_slope<T: Real>(prime_radius: T, k: &Knot<T>) -> T {
    let [y, dy, d2y, _, _, w] = *k;
    let rpy = prime_radius + y;
    -dy * (rpy + d2y) * w * w * w
}

/// Cubic Hermite interpolant on `t ∈ [0, 1]` of values `f0, f1` and slopes `d0, d1`
/// (already times the interval): its value and its derivative in `t`.
#[inline(always)]
fn hermite<T: Real>(f0: T, d0: T, f1: T, d1: T, t: T) -> (T, T) {
    let delta = f1 - f0;
    let c2 = T::from_i32(3) * delta - T::TWO * d0 - d1;
    let c3 = d0 + d1 - T::TWO * delta;
    let value = f0 + t * (d0 + t * (c2 + t * c3));
    let slope = d0 + t * (T::TWO * c2 + T::from_i32(3) * t * c3);
    (value, slope)
}

impl<T: Real, const K: usize, const S: usize> LiftTable<T, K, S> {
    /// A table without knots, to [`Self::fill`] in place.
    pub const EMPTY: Self = Self {
        knots: [[T::ZERO; PER_KNOT]; K],
        pieces: [Piece::EMPTY; S],
        pieces_len: 0,
        knots_len: 0,
        prime_radius: T::ZERO,
    };

    /// Knots in use.
    pub fn knots(&self) -> usize {
        self.knots_len
    }

    /// A filled table from the parts of another ([`Self::knots_used`],
    /// [`Self::pieces_used`]), usually of the exact capacity: what the firmware's build
    /// script writes into a `static` in flash, so that the chip keeps no table in RAM and
    /// interpolates the very bits the host's table holds; `prime_radius` is the design's
    /// ([`Self::prime_radius`]). Counts beyond the capacity are taken as the capacity.
    /// Parts that do not come from a filled table give a wrong lift, but nothing panics:
    /// every access is checked.
    pub const fn from_parts(
        knots: [TableKnot<T>; K],
        pieces: [TablePiece<T>; S],
        knots_len: usize,
        pieces_len: usize,
        prime_radius: T,
    ) -> Self {
        Self {
            knots,
            pieces,
            pieces_len: if pieces_len < S { pieces_len } else { S },
            knots_len: if knots_len < K { knots_len } else { K },
            prime_radius,
        }
    }

    /// The prime radius R_a of the design the table was filled for, in.
    pub fn prime_radius(&self) -> T {
        self.prime_radius
    }

    /// The knots in use (what [`Self::from_parts`] takes back).
    pub fn knots_used(&self) -> &[TableKnot<T>] {
        self.knots.get(..self.knots_len).unwrap_or(&[])
    }

    /// The program segments' runs of knots in use (what [`Self::from_parts`] takes back).
    pub fn pieces_used(&self) -> &[TablePiece<T>] {
        self.pieces.get(..self.pieces_len).unwrap_or(&[])
    }

    /// The largest interval, rad (0 for an empty table).
    pub fn max_interval(&self) -> T {
        let mut h = T::ZERO;
        for p in self.pieces.iter().take(self.pieces_len) {
            h = h.max(p.h);
        }
        h
    }

    /// Bytes the table occupies (its `K` knots' capacity and its pieces).
    pub const fn bytes() -> usize {
        core::mem::size_of::<Self>()
    }

    /// Tabulates `profile` (the theoretical program, or the program plus a measured
    /// deviation) for `design`, with intervals of at most `max_step` rad: every segment
    /// of the design's program gets the fewest intervals, a multiple of
    /// [`TABLE_SEGMENT_MULTIPLE`], that keep to `max_step`. On an error (a step that is
    /// not positive and finite, more than `K` knots or `S` segments) the table is left
    /// empty.
    pub fn fill<P: LiftProfile<T>>(
        &mut self,
        design: &Design<T>,
        profile: &P,
        max_step: T,
    ) -> Result<()> {
        self.pieces_len = 0;
        self.knots_len = 0;
        let r = self.fill_inner(design, profile, max_step);
        if r.is_err() {
            self.pieces_len = 0;
            self.knots_len = 0;
        }
        r
    }

    fn fill_inner<P: LiftProfile<T>>(
        &mut self,
        design: &Design<T>,
        profile: &P,
        max_step: T,
    ) -> Result<()> {
        if !(max_step > T::ZERO && max_step.is_finite()) {
            return Err(Error::InvalidParameter {
                field: "lift table step",
                rule: "must be positive and finite (rad)",
                value: max_step.to_f64(),
            });
        }
        let program = &design.program;
        let g = &design.geometry;
        let prime_radius = g.prime_radius();
        self.prime_radius = prime_radius;
        let multiple = T::from_usize(TABLE_SEGMENT_MULTIPLE);
        let mut first = 0usize;
        for (si, seg) in program.segments().iter().enumerate() {
            let start = seg.start_deg.to_radians();
            let end = seg.end_deg.to_radians();
            let span = end - start;
            // The fewest multiples of 8 intervals that keep to max_step (at least 8).
            let groups = -((-(span / (max_step * multiple))).floor());
            let n = groups.max(T::ONE).to_usize_trunc() * TABLE_SEGMENT_MULTIPLE;
            let capacity = Error::Capacity {
                what: "lift table knots",
                capacity: K,
            };
            if first.checked_add(n + 1).is_none_or(|need| need > K) {
                return Err(capacity);
            }
            let Some(piece) = self.pieces.get_mut(si) else {
                return Err(Error::Capacity {
                    what: "lift table segments",
                    capacity: S,
                });
            };
            let h = span / T::from_usize(n);
            *piece = Piece {
                start,
                end,
                h,
                inv_h: T::from_usize(n) / span,
                first,
                n,
            };
            self.pieces_len = si + 1;
            for j in 0..=n {
                // The last knot just inside the segment: a bound belongs to the segment
                // it starts, so `end` itself would give the next segment's derivatives.
                let theta = if j == n {
                    end - end * T::EPSILON
                } else {
                    start + T::from_usize(j) * h
                };
                let l = profile.follower(program, theta);
                let k_h = design.hertz.stiffness_fast(
                    g.roller_radius,
                    g.surface_curvature_radius(l.y, l.dy, l.d2y),
                );
                let rpy = prime_radius + l.y;
                let w = T::ONE / (rpy * rpy + l.dy * l.dy).sqrt();
                if let Some(k) = self.knots.get_mut(first + j) {
                    *k = [l.y, l.dy, l.d2y, l.d3y, k_h, w];
                }
            }
            first += n + 1;
            self.knots_len = first;
        }
        Ok(())
    }

    /// The interval holding `theta` (rad, any real): its two knots, the position `t` in
    /// it and its length.
    #[inline(always)]
    fn locate(&self, theta: T) -> Option<Interval<'_, T>> {
        let th = crate::kinematics::program::wrap_angle(theta);
        let pieces = self.pieces.get(..self.pieces_len)?;
        let p = pieces.iter().find(|p| th < p.end).or(pieces.last())?;
        let u = (th - p.start) * p.inv_h;
        let i = u.to_usize_trunc().min(p.n.saturating_sub(1));
        let t = u - T::from_usize(i);
        let a = self.knots.get(p.first + i)?;
        let b = self.knots.get(p.first + i + 1)?;
        Some(Interval {
            a,
            b,
            t,
            h: p.h,
            inv_h: p.inv_h,
        })
    }

    /// The interpolated lift and contact terms at `theta`; `None` for an empty table.
    #[inline(always)]
    fn interpolate(&self, theta: T) -> Option<(FollowerLift<T>, ContactTerms<T>)> {
        let Interval { a, b, t, h, inv_h } = self.locate(theta)?;
        let (dw0, dw1) = (
            hyp_slope(self.prime_radius, a),
            hyp_slope(self.prime_radius, b),
        );
        let [y0, d0, a0, j0, k0, w0] = *a;
        let [y1, d1, a1, j1, k1, w1] = *b;
        let (y, _) = hermite(y0, h * d0, y1, h * d1, t);
        let (dy, _) = hermite(d0, h * a0, d1, h * a1, t);
        let (d2y, slope) = hermite(a0, h * j0, a1, h * j1, t);
        let (inv_hyp, _) = hermite(w0, h * dw0, w1, h * dw1, t);
        let k_h = k0 + t * (k1 - k0);
        Some((
            FollowerLift {
                y,
                dy,
                d2y,
                d3y: slope * inv_h,
            },
            ContactTerms { k_h, inv_hyp },
        ))
    }
}

impl<T: Real, const K: usize, const S: usize> LiftProfile<T> for LiftTable<T, K, S> {
    /// The tabulated lift (the program argument is ignored: the table serves the design it
    /// was filled for). An empty table gives a flat lift at 0.
    #[inline]
    fn follower<const P: usize>(
        &self,
        _program: &crate::CamProgram<T, P>,
        theta: T,
    ) -> FollowerLift<T> {
        self.interpolate(theta).map(|(l, _)| l).unwrap_or_default()
    }

    #[inline]
    fn follower_and_contact<const P: usize>(
        &self,
        _program: &crate::CamProgram<T, P>,
        theta: T,
    ) -> (FollowerLift<T>, Option<ContactTerms<T>>) {
        match self.interpolate(theta) {
            Some((l, c)) => (l, Some(c)),
            None => (FollowerLift::default(), None),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{MotionLaw, TheoreticalLift};
    use std::vec::Vec;

    /// The closed-form bound of a law's n-th derivative in u (n = 4, 5, 6), for the laws
    /// of the reference design: modified trapezoidal (acceleration pieces `A sin(4πu)`,
    /// constants: |s⁽ⁿ⁾| ≤ A (4π)^(n-2)) and 4-5-6-7 (s = 35u⁴ - 84u⁵ + 70u⁶ - 20u⁷, its
    /// derivatives' maxima on [0, 1]).
    fn law_derivative_bound(law: MotionLaw, n: i32) -> f64 {
        let pi4 = 4.0 * core::f64::consts::PI;
        match law {
            MotionLaw::ModifiedTrapezoidal => {
                // A: the law's own peak acceleration.
                let a = (0..=8000)
                    .map(|i| law.eval(i as f64 / 8000.0).a.abs())
                    .fold(0.0, f64::max);
                a * pi4.powi(n - 2)
            }
            MotionLaw::Poly4567 => {
                let d = |u: f64| match n {
                    4 => 840.0 - 10080.0 * u + 25200.0 * u * u - 16800.0 * u * u * u,
                    5 => -10080.0 + 50400.0 * u - 50400.0 * u * u,
                    _ => 50400.0 - 100800.0 * u,
                };
                (0..=100_000)
                    .map(|i| d(i as f64 / 100_000.0).abs())
                    .fold(0.0, f64::max)
            }
            _ => f64::NAN,
        }
    }

    /// Largest error of the table against the closed form over every segment, and the
    /// segment's bound: (y, y', y'') errors and bounds, `K_h` relative error and bound.
    #[allow(clippy::type_complexity)]
    fn errors<T: Real>(step_deg: f64) -> Vec<([f64; 3], [f64; 3], [f64; 2], [f64; 2])> {
        let d = Design::<T>::reference();
        let d64 = Design::<f64>::reference();
        let mut table = Box::new(LiftTable::<T, 1200>::EMPTY);
        table
            .fill(&d, &TheoreticalLift, T::from_f64(step_deg.to_radians()))
            .unwrap();
        let mut out = Vec::new();
        for (si, seg) in d64.program.segments().iter().enumerate() {
            let p = table.pieces[si];
            let h = p.h.to_f64();
            let (a, b) = (seg.start_deg.to_radians(), seg.end_deg.to_radians());
            let beta = b - a;
            let mut err = [0.0f64; 3];
            let mut k_err = 0.0f64;
            let mut w_err = 0.0f64;
            let mut w4 = 0.0f64;
            let w_closed = |th: f64| {
                let l = d64.program.follower(th);
                let rpy = d64.geometry.prime_radius() + l.y;
                1.0 / (rpy * rpy + l.dy * l.dy).sqrt()
            };
            let mut k2 = 0.0f64;
            let k_closed = |th: f64| {
                let l = d64.program.follower(th);
                let g = &d64.geometry;
                d64.hertz.stiffness_fast(
                    g.roller_radius,
                    g.surface_curvature_radius(l.y, l.dy, l.d2y),
                )
            };
            let m = 40 * p.n;
            for i in 1..m {
                let th = a + beta * i as f64 / m as f64;
                let exact = d64.program.follower(th);
                let (l, c) = table.follower_and_contact(&d.program, T::from_f64(th));
                let c = c.unwrap();
                let k = c.k_h.to_f64();
                let rpy = d64.geometry.prime_radius() + exact.y;
                let w = 1.0 / (rpy * rpy + exact.dy * exact.dy).sqrt();
                w_err = w_err.max(((c.inv_hyp.to_f64() - w) / w).abs());
                err[0] = err[0].max((l.y.to_f64() - exact.y).abs());
                err[1] = err[1].max((l.dy.to_f64() - exact.dy).abs());
                err[2] = err[2].max((l.d2y.to_f64() - exact.d2y).abs());
                let kc = k_closed(th);
                k_err = k_err.max(((k - kc) / kc).abs());
                // K_h'' / K_h by second differences at h/4 (inside the segment).
                let e = h / 4.0;
                // max|w''''| / w by fourth differences at h/2 (inside the segment).
                let f = h / 2.0;
                if th - 2.0 * f > a && th + 2.0 * f < b {
                    let d4 = w_closed(th + 2.0 * f) - 4.0 * w_closed(th + f) + 6.0 * w_closed(th)
                        - 4.0 * w_closed(th - f)
                        + w_closed(th - 2.0 * f);
                    w4 = w4.max((d4 / f.powi(4) / w_closed(th)).abs());
                }
                if th - e > a && th + e < b {
                    k2 = k2.max(
                        ((k_closed(th + e) - 2.0 * kc + k_closed(th - e)) / (e * e * kc)).abs(),
                    );
                }
            }
            let bound = match seg.kind {
                SegmentKind::Dwell => [0.0; 3],
                SegmentKind::Rise(law) | SegmentKind::Return(law) => {
                    let c = h.powi(4) / 384.0 * seg.lift;
                    [4, 5, 6].map(|n| c * law_derivative_bound(law, n) / beta.powi(n))
                }
            };
            // Linear interpolation: h²/8 max|K_h''| (relative: over K_h, 10 % margin on
            // the second differences' estimate).
            out.push((
                err,
                bound,
                [k_err, w_err],
                [1.1 * h * h / 8.0 * k2, 1.1 * h.powi(4) / 384.0 * w4],
            ));
        }
        out
    }

    use crate::SegmentKind;

    /// In `f32` (the chip's table) the same bounds hold up to `f32`'s rounding: the knots'
    /// values and the Hermite sum's few operations (16 ulps of the largest of |f| and
    /// h |f'| of the segment, f = y, y', y''), and the cam angle itself rounded to `f32`
    /// (half an ulp of 2π times the largest |f'|). With the micromath backend the laws'
    /// own sin and cos err by far more than the table (about 1e-4 relative), so the
    /// bound is checked on libm only.
    #[test]
    #[cfg(not(feature = "micromath"))]
    fn f32_table_keeps_within_the_bound_plus_rounding() {
        let d64 = Design::<f64>::reference();
        let scale = |q: usize, si: usize| {
            let seg = d64.program.segments()[si];
            let (a, b) = (seg.start_deg.to_radians(), seg.end_deg.to_radians());
            (0..=1000)
                .map(|i| {
                    let l = d64.program.follower(a + (b - a) * i as f64 / 1000.0);
                    [l.y, l.dy, l.d2y, l.d3y][q].abs()
                })
                .fold(0.0, f64::max)
        };
        for (si, (err, bound, rel, rel_bound)) in errors::<f32>(1.0).into_iter().enumerate() {
            let h = 1f64.to_radians();
            let eps = f32::EPSILON as f64;
            for q in 0..3 {
                let rounding = 16.0 * eps * scale(q, si).max(h * scale(q + 1, si))
                    + scale(q + 1, si) * core::f64::consts::PI * eps;
                assert!(
                    err[q] <= bound[q] + rounding,
                    "segment {si} q {q}: {} > {} + {rounding}",
                    err[q],
                    bound[q]
                );
            }
            for q in 0..2 {
                assert!(rel[q] <= rel_bound[q] + 16.0 * f32::EPSILON as f64);
            }
        }
    }

    /// The grid: every segment's interval count a multiple of 8 with intervals at most the
    /// step; a table too small for the program, or a bad step, is an error and leaves it
    /// empty (a flat lift, the stiffness left to the closed form).
    #[test]
    fn grid_counts_and_refusals() {
        let d = Design::<f64>::reference();
        let mut t = Box::new(LiftTable::<f64, 400>::EMPTY);
        t.fill(&d, &TheoreticalLift, 1f64.to_radians()).unwrap();
        // 30° -> 32 intervals, 150° -> 152: 32 + 152 + 32 + 152 intervals, 4 closing knots.
        assert_eq!(t.knots(), 372);
        for p in &t.pieces[..t.pieces_len] {
            assert_eq!(p.n % TABLE_SEGMENT_MULTIPLE, 0);
            assert!(p.h <= 1f64.to_radians() * (1.0 + 1e-12));
        }
        let mut small = Box::new(LiftTable::<f64, 371>::EMPTY);
        assert!(matches!(
            small.fill(&d, &TheoreticalLift, 1f64.to_radians()),
            Err(Error::Capacity { capacity: 371, .. })
        ));
        assert_eq!(small.knots(), 0);
        assert_eq!(small.follower(&d.program, 1.0), FollowerLift::default());
        assert!(small.follower_and_contact(&d.program, 1.0).1.is_none());
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(t.fill(&d, &TheoreticalLift, bad).is_err());
            assert_eq!(t.knots(), 0);
        }
        // At a knot the table gives the closed form's own values (t = 0).
        t.fill(&d, &TheoreticalLift, 1f64.to_radians()).unwrap();
        let th = 30f64.to_radians() + 5.0 * t.pieces[1].h;
        let (l, _) = t.follower_and_contact(&d.program, th);
        let e = d.program.follower(th);
        assert!((l.y - e.y).abs() < 1e-15 && (l.d2y - e.d2y).abs() < 1e-12);
        // Wrapped: a revolution later, the same lift.
        let (l2, _) = t.follower_and_contact(&d.program, th + 2.0 * core::f64::consts::PI);
        assert!((l2.y - l.y).abs() < 1e-12);
    }

    /// A table rebuilt from another's parts at exactly its size (what the firmware keeps in
    /// flash) interpolates the very same bits as the table it came from, at every cam angle
    /// tried (knots, interval interiors, segment bounds, wrapped angles); counts beyond the
    /// capacity are clamped, and an empty table's parts give an empty table.
    #[test]
    fn table_from_its_parts_gives_the_same_bits() {
        let d = Design::<f32>::reference();
        let mut t = Box::new(LiftTable::<f32, 432>::EMPTY);
        t.fill(&d, &TheoreticalLift, 1f32.to_radians()).unwrap();
        let (n, p) = (t.knots_used().len(), t.pieces_used().len());
        assert_eq!((n, p), (372, 4));
        let mut knots = [[0.0f32; TABLE_PER_KNOT]; 372];
        knots.copy_from_slice(t.knots_used());
        let mut pieces = [TablePiece::EMPTY; 4];
        pieces.copy_from_slice(t.pieces_used());
        let r = t.prime_radius();
        assert_eq!(r, d.geometry.prime_radius());
        let exact = LiftTable::<f32, 372, 4>::from_parts(knots, pieces, n, p, r);
        assert_eq!(
            (exact.knots(), exact.max_interval()),
            (372, t.max_interval())
        );
        let bits = |x: (FollowerLift<f32>, Option<ContactTerms<f32>>)| {
            let c = x.1.unwrap_or_default();
            [x.0.y, x.0.dy, x.0.d2y, x.0.d3y, c.k_h, c.inv_hyp].map(f32::to_bits)
        };
        for i in -50..=3650 {
            let th = (i as f32 * 0.1 + 0.037).to_radians();
            assert_eq!(
                bits(exact.follower_and_contact(&d.program, th)),
                bits(t.follower_and_contact(&d.program, th)),
                "at {th} rad"
            );
        }
        let clamped = LiftTable::<f32, 372, 4>::from_parts(knots, pieces, 9999, 9999, r);
        assert_eq!(clamped, exact);
        let empty = LiftTable::<f32, 1, 1>::from_parts(
            [[0.0; TABLE_PER_KNOT]],
            [TablePiece::EMPTY],
            0,
            0,
            r,
        );
        assert_eq!(empty.knots(), 0);
        assert!(empty.follower_and_contact(&d.program, 1.0).1.is_none());
    }

    #[test]
    fn f64_table_keeps_within_the_hermite_bound() {
        for step in [1.0, 2.0] {
            for (si, (err, bound, rel, rel_bound)) in errors::<f64>(step).into_iter().enumerate() {
                std::println!("step {step} deg segment {si}: err {err:?} bound {bound:?} k_h, w rel {rel:?} bound {rel_bound:?}");
                for q in 0..3 {
                    // The f64 evaluation's rounding: a few ulps of the lift's scale.
                    assert!(
                        err[q] <= bound[q] + 1e-12,
                        "step {step} segment {si} q {q}: {} > {}",
                        err[q],
                        bound[q]
                    );
                }
                for q in 0..2 {
                    assert!(
                        rel[q] <= rel_bound[q] + 1e-14,
                        "step {step} segment {si}: relative {q} {} > {}",
                        rel[q],
                        rel_bound[q]
                    );
                }
            }
        }
    }
}
