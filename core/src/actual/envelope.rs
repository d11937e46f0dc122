//! The exact envelope (beyond the thesis): the roller centre's displacement on an actual
//! cam contour by exact contact of the roller circle (docs/MODEL.md §8.4).
//!
//! The thesis (IV.2.3) draws the follower's lift directly, point by point, within a
//! linearised tolerance band; it argues that waviness shorter than the roller cannot be
//! followed but its method cannot show it. Here the roller is a circle of radius `r`
//! whose centre moves on the follower axis, pressed onto the cam contour of IV.2.2
//! ([`ActualContour`]), and its position is found exactly.
//!
//! # Contact
//!
//! In the cam-fixed frame (that of [`crate::CamGeometry::surface_point`]) the follower
//! axis at cam angle `θ` is the ray from the rotation centre `c` along
//! `u = (sin θ, cos θ)`; `w = (cos θ, −sin θ)` is across it. A contour point `p` has the
//! coordinates `a = (p − c)·u` along the axis and `b = (p − c)·w` across it. The roller
//! centred at `c + d u` does not cut `p` if and only if `(d − a)² + b² ≥ r²`, that is
//! (for the roller on the outside, `d ≥ a`) `d ≥ a + √(r² − b²)` when `|b| < r`; points
//! with `|b| ≥ r` never constrain it. The spring holds the roller as low as the contour
//! lets it, so
//!
//! ```text
//! d(θ) = max over contour points p with |b| < r of  a(p) + √(r² − b(p)²)
//! ```
//!
//! and the follower's lift is `d(θ) − R_a` (`R_a = R_b + r` nominal). The maximiser is
//! the contact point; where two points tie the roller bridges a valley, and `d` has a
//! corner there (the lift stays continuous, its slope does not).
//!
//! # Search
//!
//! The contour is parametrised by its setting angle `φ`; on the theoretical cam the
//! contact at cam angle `θ` is the setting point `φ = θ`, and `b(φ) ≈ ρ sin(φ − θ)`
//! grows with `φ`. So the search starts at `φ = θ` and walks outwards in both
//! directions in steps of `Δφ/`[`ENVELOPE_SUBSTEPS`] (`Δφ` the contour's knot
//! interval) until `b ≥ r` (upwards) or `b ≤ −r` (downwards), or a quarter revolution
//! is walked; the best sample is then refined by a golden-section search over the two
//! steps around it ([`ENVELOPE_REFINE`] iterations). Within one knot interval the
//! contour is a cubic, so `g(φ) = a + √(r² − b²)` is smooth between samples and the
//! refinement finds its maximum to the rounding of `T` (the residual is
//! `g''·(2Δφ/8 · 0.618^{24})²`, below 10⁻¹⁵ in for any sane contour).
//!
//! # Perfect cam
//!
//! The theoretical cam is the envelope of the roller circle on the pitch curve
//! `R_a + y(θ)`, so on it `d(θ) = R_a + y(θ)` exactly (where it is not undercut). A
//! contour that lies within `ε` of the true surface (any point within `ε` of it) is
//! contained in the cam grown by `ε` and contains the cam shrunk by `ε`; the roller of
//! radius `r` on the grown cam sits where a roller of radius `r + ε` sits on the true
//! one, higher by `ε / cos φ` to first order (`φ` the pressure angle: the centre moves
//! along the normal by `ε`, constrained to the axis). So on a splined perfect cam
//! `|d(θ) − R_a − y(θ)| ≤ ε / cos φ_max` (plus the search's rounding).
//!
//! # Waviness (a sinusoid on a base circle)
//!
//! A contour of polar radius `ρ(φ) = R + A cos nφ` (wavelength `λ = 2πR/n`), roller of
//! radius `r` on a radial axis:
//!
//! * Over a crest (`θ = 0`) the roller sits at `d = R + A + r` exactly: every point is
//!   within the circle of radius `R + A`, which the roller touches from outside there.
//! * Over a valley (`θ = π/n`) the valley bottom is a point on the axis at `R − A`, so
//!   `d ≥ R − A + r`, with equality when the roller fits the valley: the valley's
//!   concave radius of curvature is `ρ²/(A n² − ρ)` (`ρ = R − A`, from the polar
//!   curvature `(ρ² + 2ρ'² − ρρ'')/(ρ² + ρ'²)^{3/2}`), so the roller reaches the bottom
//!   when `A n² ≤ ρ (ρ + r)/r`. The lift then swings by the full `2A`: the waviness
//!   passes (the roller follows even waves shorter than itself if they are shallow).
//! * Deeper or shorter waves are bridged: the roller rests on the two crests either side.
//!   Resting on the crest tips (radius `R + A` at `±π/n`) gives
//!   `d ≥ (R + A) cos(π/n) + √(r² − (R + A)² sin²(π/n))`, so the swing is at most
//!   `(R + A + r) − that ≈ λ²/(8r)·(1 + r/R)` (the sagitta of the chord `λ` under the
//!   roller), independent of `A`: a wave with `λ ≪ √(16 A r)` is attenuated by the
//!   factor `λ²(1 + r/R)/(16 A r)` at least. With the crests replaced by their
//!   osculating circles (radius `R_c = (R+A)²/(R + A + A n²)`, centres at `R + A − R_c`)
//!   the roller's centre is at distance `r + R_c` from both, which is the bridged swing
//!   to within the crest's departure from its osculating circle.

use crate::{ActualContour, Error, ProfileSpec, RandomStream, Real, Result};

/// Samples per contour knot interval in the envelope's walk along the contour.
pub const ENVELOPE_SUBSTEPS: usize = 8;

/// Golden-section iterations refining the best sample (the bracket shrinks by
/// `0.618^24 ≈ 1e-5`).
pub const ENVELOPE_REFINE: usize = 24;

/// An actual cam as the envelope method sees it: the random contour of IV.2.2, the
/// actual roller radius and the rotation centre's offset from the contour's origin
/// (the base circle's eccentricity and the camshaft bearings' non-roundness).
#[derive(Clone, Debug, PartialEq)]
pub struct ActualCam<T, const N: usize> {
    /// The cam contour (cam-fixed frame).
    pub contour: ActualContour<T, N>,
    /// The roller radius (in).
    pub roller_radius: T,
    /// The rotation centre in the contour's frame (in).
    pub centre: (T, T),
}

impl<T: Real, const N: usize> ActualCam<T, N> {
    /// One actual cam from `rng`: the contour of [`ActualContour::generate`] (its
    /// `2·intervals` deviates first), then the roller radius `r + σ_r z` and the rotation
    /// centre `(σ_e z_x, σ_e z_y)` (`σ = tolerance/3`, three more deviates, in this
    /// order). The roller radius and the eccentricity are one value per cam, as they
    /// are on a machine. Needs `3 ≤ intervals < N` and a positive roller radius.
    pub fn generate<const S: usize>(
        spec: &ProfileSpec<'_, T, S>,
        rng: &mut RandomStream<T>,
    ) -> Result<Self> {
        let contour = ActualContour::generate(spec, rng)?;
        let ProfileSpec {
            geometry,
            tolerances,
            ..
        } = *spec;
        let (_, sr, se) = tolerances.sigmas();
        let roller_radius = rng.gaussian(geometry.roller_radius, sr);
        let cx = rng.gaussian(T::ZERO, se);
        let cy = rng.gaussian(T::ZERO, se);
        Self::new(contour, roller_radius, (cx, cy))
    }

    /// A cam from its parts (the roller radius positive, the centre finite).
    pub fn new(contour: ActualContour<T, N>, roller_radius: T, centre: (T, T)) -> Result<Self> {
        if !(roller_radius > T::ZERO && roller_radius.is_finite()) {
            return Err(Error::InvalidParameter {
                field: "roller_radius",
                rule: "the actual roller radius must be positive and finite",
                value: roller_radius.to_f64(),
            });
        }
        if !(centre.0.is_finite() && centre.1.is_finite()) {
            return Err(Error::InvalidParameter {
                field: "centre",
                rule: "the rotation centre must be finite",
                value: f64::NAN,
            });
        }
        Ok(ActualCam {
            contour,
            roller_radius,
            centre,
        })
    }

    /// The roller centre's distance `d(θ)` from the rotation centre along the follower
    /// axis at cam angle `theta` (rad), by exact contact (see the module docs), or an
    /// error where no contour point lies within the roller's reach of the axis or the
    /// contour is not finite there.
    pub fn roller_centre(&self, theta: T) -> Result<T> {
        let r = self.roller_radius;
        let (s, c) = theta.sin_cos();
        let (cx, cy) = self.centre;
        // g(φ): the height the roller must clear for the setting point φ (None where
        // the point is out of reach), and b(φ).
        let g = |phi: T| -> (Option<T>, T) {
            let p = self.contour.point(phi);
            let (px, py) = (p.x - cx, p.y - cy);
            let a = px * s + py * c;
            let b = px * c - py * s;
            let q = r * r - b * b;
            if q > T::ZERO {
                (Some(a + q.sqrt()), b)
            } else {
                (None, b)
            }
        };
        let n = self.contour.intervals().max(1);
        let h = T::TWO * T::PI / T::from_usize(n * ENVELOPE_SUBSTEPS);
        // Steps in a quarter revolution.
        let max_steps = n * ENVELOPE_SUBSTEPS / 4 + 1;
        let (mut best, mut best_phi) = (-T::INFINITY, theta);
        let mut consider = |phi: T, v: Option<T>| {
            if let Some(v) = v {
                if v > best {
                    best = v;
                    best_phi = phi;
                }
            }
        };
        let (v0, _) = g(theta);
        consider(theta, v0);
        for dir in [T::ONE, -T::ONE] {
            for k in 1..=max_steps {
                let phi = theta + dir * T::from_usize(k) * h;
                let (v, b) = g(phi);
                if !b.is_finite() {
                    return Err(non_finite(theta));
                }
                consider(phi, v);
                if dir * b >= r {
                    break;
                }
            }
        }
        if !best.is_finite() {
            return Err(non_finite(theta));
        }
        // Golden section on [φ* − h, φ* + h] (g is −∞ out of reach).
        let value = |phi: T| g(phi).0.unwrap_or(-T::INFINITY);
        let inv_phi = T::from_f64(0.618_033_988_749_894_8);
        let (mut lo, mut hi) = (best_phi - h, best_phi + h);
        let mut x1 = hi - inv_phi * (hi - lo);
        let mut x2 = lo + inv_phi * (hi - lo);
        let (mut f1, mut f2) = (value(x1), value(x2));
        for _ in 0..ENVELOPE_REFINE {
            if f1 >= f2 {
                hi = x2;
                x2 = x1;
                f2 = f1;
                x1 = hi - inv_phi * (hi - lo);
                f1 = value(x1);
            } else {
                lo = x1;
                x1 = x2;
                f1 = f2;
                x2 = lo + inv_phi * (hi - lo);
                f2 = value(x2);
            }
        }
        Ok(best.max(f1).max(f2))
    }
}

fn non_finite<T: Real>(theta: T) -> Error {
    Error::InvalidParameter {
        field: "contour",
        rule: "no finite contour point within the roller's reach at this cam angle (deg)",
        value: theta.to_f64().to_degrees(),
    }
}
