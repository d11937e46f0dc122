//! The per-cam errors of the follower train (docs/MODEL.md §8.9): the roller radius and
//! the follower axis's offset, each one value per cam, applied through the exact
//! geometry rather than linearised (the `per-cam` profile method).
//!
//! The theoretical roller centre at cam angle θ is the pitch-curve point
//! `ρ(φ) u(φ)`, `ρ = R_a + y(φ)`, `u(φ) = (sin φ, cos φ)` (cam frame of E.6) at polar
//! angle φ = θ. A roller of radius `r + Δr` rides on the pitch curve offset by `Δr`
//! along its outward normal `n = (ρ u − ρ' w)/h`, `w = du/dφ = (cos φ, −sin φ)`,
//! `h = √(ρ² + ρ'²)` (the pitch curve is the surface offset by `r`; the surface offset
//! by `r + Δr` is the pitch curve offset by `Δr`). A follower axis offset by `e` is the
//! line `e w(θ) + d u(θ)`. The roller centre is where the two meet: the polar angle
//! `φ = θ + δ` with
//!
//! ```text
//! g(δ) = ρ sin δ + Δr (ρ sin δ − ρ' cos δ)/h − e = 0,
//! d = ρ cos δ + Δr (ρ cos δ + ρ' sin δ)/h          (all at φ = θ + δ)
//! ```
//!
//! solved by Newton's method on δ (the derivative of the first term,
//! `ρ cos δ + ρ' sin δ`, is the slope; the `Δr` term changes it by a fraction of order
//! `Δr/ρ`, so each step gains about four digits). The lift is counted from the base
//! circle, where the follower's zero is set (E.7's `s₀`): on the low dwell
//! `d₀ = √((R_a + Δr)² − e²)`, so the deviation is `d − d₀ − y(θ)`, to first order
//! `Δr (1/cos φ − 1) + e tan φ`: Eq. E.8's sensitivities.

use crate::{CamGeometry, CamProgram, Error, Real, Result};

/// Newton steps at most for one roller centre.
const NEWTON_STEPS: u32 = 40;

/// The per-cam errors of one cam's follower train (in).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AxisErrors<T> {
    /// The roller radius's error `Δr` (in): the roller is `r + Δr` all the way round.
    pub roller: T,
    /// The follower axis's offset `e` from the rotation centre (in): the camshaft
    /// bearings' non-roundness and the base circle's eccentricity as one offset.
    pub offset: T,
}

impl<T: Real> AxisErrors<T> {
    /// Whether both errors are zero (the theoretical follower train).
    pub fn is_zero(&self) -> bool {
        self.roller == T::ZERO && self.offset == T::ZERO
    }

    /// The lift deviation `d − d₀ − y(θ)` at cam angle `theta` (see the module docs).
    /// Errors if the Newton iteration does not settle (an offset or roller error that
    /// is not small against the pitch curve).
    pub fn lift_deviation<const S: usize>(
        &self,
        program: &CamProgram<T, S>,
        geometry: &CamGeometry<T>,
        theta: T,
    ) -> Result<T> {
        let ra = geometry.prime_radius();
        let (dr, e) = (self.roller, self.offset);
        let at = |delta: T| {
            let f = program.follower(theta + delta);
            (ra + f.y, f.dy, f.y)
        };
        let mut delta = T::ZERO;
        let tol = T::from_i32(4) * T::EPSILON;
        let mut settled = false;
        for _ in 0..NEWTON_STEPS {
            let (rho, drho, _) = at(delta);
            let (s, c) = delta.sin_cos();
            let h = (rho * rho + drho * drho).sqrt();
            let g = rho * s + dr * (rho * s - drho * c) / h - e;
            let slope = rho * c + drho * s;
            let step = g / slope;
            if !step.is_finite() {
                break;
            }
            delta -= step;
            if step.abs() <= tol * (T::ONE + delta.abs()) {
                settled = true;
                break;
            }
        }
        if !settled {
            return Err(Error::NoConvergence {
                what: "the roller centre on the offset follower axis",
                iterations: NEWTON_STEPS,
            });
        }
        let (rho, drho, y) = at(delta);
        let (s, c) = delta.sin_cos();
        let h = (rho * rho + drho * drho).sqrt();
        let y0 = program.follower(theta).y;
        // d − ρ(θ) without cancellation: (y(φ) − y(θ)) cos δ − ρ(θ)·2 sin²(δ/2).
        let half = (delta / T::TWO).sin();
        let along = (y - y0) * c - (ra + y0) * T::TWO * half * half;
        let normal = dr * (rho * c + drho * s) / h;
        // R_a − d₀ = −(Δr (2R_a + Δr) − e²)/(R_a + d₀).
        let grow = dr * (T::TWO * ra + dr) - e * e;
        let d0 = (ra * ra + grow).sqrt();
        Ok(along + normal - grow / (ra + d0))
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used, clippy::indexing_slicing)]
mod tests {
    use super::*;
    use crate::{DeviatedLift, LiftProfile, NormalMethod, ProfileSpec, RandomStream, Tolerances};

    type Lift = DeviatedLift<f64, 3601>;

    fn parts() -> (CamProgram<f64>, CamGeometry<f64>) {
        (CamProgram::reference(), CamGeometry::reference())
    }

    /// The per-cam lift of sample `i` for the given tolerances, at `intervals`.
    fn draw(tol: Tolerances<f64>, i: u64, intervals: usize) -> (Lift, AxisErrors<f64>) {
        let (p, g) = parts();
        let spec = ProfileSpec {
            program: &p,
            geometry: &g,
            tolerances: &tol,
            intervals,
        };
        let mut rng = RandomStream::for_sample(7, i, NormalMethod::Polar);
        let mut contour = std::boxed::Box::new(Lift::EMPTY);
        let axis = contour.draw_per_cam(&spec, &mut rng).unwrap();
        let mut lift = std::boxed::Box::new(Lift::EMPTY);
        lift.refit_per_cam(&contour, &axis, &spec).unwrap();
        (*lift, axis)
    }

    /// Bisection: the root of a function that changes sign on `[a, b]`.
    fn root(mut a: f64, mut b: f64, f: impl Fn(f64) -> f64) -> f64 {
        let fa = f(a);
        for _ in 0..200 {
            let m = 0.5 * (a + b);
            if (f(m) > 0.0) == (fa > 0.0) {
                a = m;
            } else {
                b = m;
            }
        }
        0.5 * (a + b)
    }

    #[test]
    fn zero_tolerances_give_the_theoretical_lift_bit_for_bit() {
        let (p, _) = parts();
        let (lift, axis) = draw(Tolerances::none(), 3, 21);
        assert!(axis.is_zero());
        for k in 0..7200 {
            let th = k as f64 * 0.05f64.to_radians();
            assert_eq!(lift.follower(&p, th), p.follower(th), "at {th}");
        }
    }

    #[test]
    fn without_roller_and_axis_errors_it_is_the_thesis_contour() {
        // The contour's deviates are drawn first, as the thesis draws its own.
        let (p, g) = parts();
        let tol = Tolerances::new(0.0005, 0.0, 0.0).unwrap();
        let spec = ProfileSpec {
            program: &p,
            geometry: &g,
            tolerances: &tol,
            intervals: 21,
        };
        let mut rng = RandomStream::for_sample(7, 2, NormalMethod::Polar);
        let thesis = Lift::thesis(&spec, &mut rng).unwrap();
        assert!(draw(tol, 2, 21).0 == thesis);
    }

    #[test]
    fn an_offset_axis_gives_the_lift_of_the_offset_follower() {
        // Cam and roller exact: the roller centre at `e` across and `d` along the axis
        // lies on the pitch curve, √(e² + d²) = R_a + y(θ + atan(e/d)), with the zero
        // on the base circle at √(R_a² − e²): solved here by bisection on d.
        let (p, g) = parts();
        let ra = g.prime_radius();
        // VI.1's ±0.001 in: σ_e = 0.00033 in.
        let tol = Tolerances::new(0.0, 0.0, 0.001).unwrap();
        let mut scaled = [[0.0f64; 1440]; 2];
        for (i, row) in scaled.iter_mut().enumerate() {
            let (lift, axis) = draw(tol, i as u64, 21);
            let e = axis.offset;
            assert!(axis.roller == 0.0 && e.abs() > 1e-5, "{axis:?}");
            let exact = |th: f64| {
                let y = p.follower(th).y;
                let d = root(ra + y - 0.01, ra + y + 0.01, |d| {
                    (e * e + d * d).sqrt() - ra - p.follower(th + e.atan2(d)).y
                });
                d - (ra * ra - e * e).sqrt() - y
            };
            // Every knot of the spline and every point halfway between knots.
            let knots = lift.spline().knots();
            assert!(knots.len() > 1440, "{}", knots.len());
            for w in knots.windows(2) {
                for th in [w[0], 0.5 * (w[0] + w[1])] {
                    let got = lift.follower(&p, th).y - p.follower(th).y;
                    let want = exact(th);
                    assert!(
                        (got - want).abs() < 1e-9,
                        "sample {i} at {th}: {got} vs {want}"
                    );
                }
            }
            for (k, s) in row.iter_mut().enumerate() {
                let th = (k as f64 * 0.25).to_radians();
                *s = (lift.follower(&p, th).y - p.follower(th).y) / e;
            }
        }
        // Two cams' deviations divided by their offsets are one shape (e tan φ) to
        // first order: they differ by O(e/R_a) of its size.
        let size = scaled[0].iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let apart = (0..1440).fold(0.0f64, |m, k| m.max((scaled[0][k] - scaled[1][k]).abs()));
        assert!(size > 0.3 && apart < 0.01 * size, "{size} {apart}");
    }

    #[test]
    fn a_roller_error_gives_the_pitch_curve_of_that_roller() {
        // Cam and axis exact: the roller of radius r + Δr centred on the axis at the
        // deviated lift touches the theoretical surface, its nearest point at exactly
        // r + Δr (found by a scan and golden section over the surface's cam angle).
        let (p, g) = parts();
        let ra = g.prime_radius();
        let tol = Tolerances::new(0.0, 0.01, 0.0).unwrap();
        for i in 0..2u64 {
            let (lift, axis) = draw(tol, i, 21);
            let dr = axis.roller;
            assert!(axis.offset == 0.0 && dr.abs() > 1e-4, "{axis:?}");
            for k in 0..180 {
                let th = (k as f64 * 2.0 + 0.25).to_radians();
                let d = ra + dr + lift.follower(&p, th).y;
                let c = (d * th.sin(), d * th.cos());
                let dist = |s: f64| {
                    let f = p.follower(s);
                    let (x, y) = g.surface_point(s, f.y, f.dy);
                    ((x - c.0).powi(2) + (y - c.1).powi(2)).sqrt()
                };
                let (mut a, mut b) = (th - 0.5, th + 0.5);
                let best = (0..=1000).map(|j| a + (b - a) * j as f64 / 1000.0).fold(
                    (f64::INFINITY, a),
                    |m, s| if dist(s) < m.0 { (dist(s), s) } else { m },
                );
                (a, b) = (best.1 - 1e-3, best.1 + 1e-3);
                let r = 0.5 * (5f64.sqrt() - 1.0);
                for _ in 0..80 {
                    let (x1, x2) = (b - r * (b - a), a + r * (b - a));
                    if dist(x1) < dist(x2) {
                        b = x2;
                    } else {
                        a = x1;
                    }
                }
                let near = dist(0.5 * (a + b));
                let want = g.roller_radius + dr;
                assert!(
                    (near - want).abs() < 1e-9,
                    "sample {i} at {th}: {near} vs {want}"
                );
            }
        }
    }
}
